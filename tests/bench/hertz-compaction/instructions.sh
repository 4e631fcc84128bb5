#!/usr/bin/env bash
# The engine benchmark counted in instructions instead of seconds: the reference scene
# (README.md beside this script) run by shapepress, LIGGGHTS 3.8 and LAMMPS 29Sep2021 on one
# core under valgrind's callgrind, which counts the instructions each executes. On a shared,
# loaded machine wall-clock ratios swing by tens of per cent between runs; instruction counts do
# not (they miss cache misses and branch mispredictions, which run.sh's timed ratio includes).
# Each engine runs STEPS steps and 1 step; the difference is the cost of STEPS-1 steps without
# start-up, input and output. Prints instructions per particle-step and the peers' over ours.
# Valgrind's CPU has no AVX-512: shapepress' contact block runs its AVX2 clone here.
#   tests/bench/hertz-compaction/instructions.sh [STEPS]    (default 1000; the full scene is
#                                                            4000, about an hour under callgrind)
# Needs: scripts/install-deps.sh --peers (liggghts, lammps, python3, valgrind) and a build/.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
steps=${1:-1000}
[[ "$steps" =~ ^[0-9]+$ && "$steps" -ge 2 ]] || { echo "instructions.sh: STEPS must be an integer >= 2, got '$steps'" >&2; exit 2; }
script=instructions.sh
source "$here/scene.sh" liggghts lmp valgrind python3

# Total instructions callgrind counted for a command (its "Collected" line).
count() {
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 >/dev/null |
    awk '/Collected :/ { print $NF }'
}
shapepress_run() {
  count "$shapepress" --quiet --threads 1 compact \
    --config "$root/pipelines/configs/hertz-compaction-bench.toml" --packing packing.txt \
    --steps "$1" --out "run-$1"
}
liggghts_run() { count liggghts -in liggghts.in -log none -var NSTEPS "$1"; }
lammps_run() { count lmp -in lammps.in -log none -var NSTEPS "$1"; }

per_step() {  # total_long total_short → instructions per particle-step
  awk -v a="$1" -v b="$2" -v s="$steps" -v n=$particles 'BEGIN { printf "%.1f", (a - b) / ((s - 1) * n) }'
}
s_long=$(shapepress_run "$steps"); s_short=$(shapepress_run 1)
l_long=$(liggghts_run "$steps"); l_short=$(liggghts_run 1)
m_long=$(lammps_run "$steps"); m_short=$(lammps_run 1)
s=$(per_step "$s_long" "$s_short"); l=$(per_step "$l_long" "$l_short"); m=$(per_step "$m_long" "$m_short")
printf "%-12s %-28s\n" engine "instructions/particle-step"
printf "%-12s %-28s\n" liggghts "$l"
printf "%-12s %-28s\n" lammps "$m"
printf "%-12s %-28s\n" shapepress "$s"
awk -v a="$l" -v b="$s" -v st="$steps" 'BEGIN { printf "ratio liggghts/shapepress over steps 2..%d: %.2f\n", st, a / b }'
awk -v a="$m" -v b="$s" -v st="$steps" 'BEGIN { printf "ratio lammps/shapepress over steps 2..%d: %.2f\n", st, a / b }'
