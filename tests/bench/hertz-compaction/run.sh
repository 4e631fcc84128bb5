#!/usr/bin/env bash
# The engine benchmark: the reference scene (README.md beside this script) in LIGGGHTS 3.8,
# LAMMPS 29Sep2021 (both Debian) and shapepress, alternating in one run, on 1 core and on 2
# (2 MPI ranks for the peers, 2 threads for shapepress). Prints particle-steps per second for
# each, each engine's speed relative to each peer, peak memory, and the physics at the end (punch
# force, mean contacts per particle, kinetic energy) side by side; then the medians over repeats.
#   tests/bench/hertz-compaction/run.sh [REPEATS] [STEPS]     (defaults 3, 4000)
# Needs: scripts/install-deps.sh --peers (liggghts, lammps, openmpi-bin, python3, time), build/.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
repeats=${1:-3}
steps=${2:-4000}
[[ "$repeats" =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: REPEATS must be a positive integer, got '$repeats'" >&2; exit 2; }
[[ "$steps" =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: STEPS must be a positive integer, got '$steps'" >&2; exit 2; }
script=run.sh
source "$here/scene.sh" liggghts lmp mpirun python3 /usr/bin/time

# particle-steps per second from a loop time in seconds
rate() { awk -v n=$particles -v s="$steps" -v t="$1" 'BEGIN { printf "%.4g", n * s / t }'; }
ratio() { awk -v num="$1" -v den="$2" 'BEGIN { printf "%.2f", num / den }'; }

# LIGGGHTS and LAMMPS share the input conventions (-in, -log none, -var NSTEPS), the "Loop time
# of" line and the deck's FINAL line.
run_peer() {  # binary deck ranks → "loop_s peak_kib cpu_s force_N contacts ke_J"
  local binary=$1 deck=$2 ranks=$3 launcher=()
  [[ $ranks -gt 1 ]] && launcher=(mpirun --allow-run-as-root --oversubscribe -np "$ranks")
  /usr/bin/time -f "%M %U" -o mem.txt "${launcher[@]}" "$binary" -in "$deck" -log none \
      -var NSTEPS "$steps" > peer.out 2>&1 || { cat peer.out >&2; exit 1; }
  local loop final
  loop=$(awk '/^Loop time of/ { print $4 }' peer.out)
  final=$(grep '^FINAL' peer.out)
  local force z ke
  force=$(sed -E 's/.*punch_force=([^ ]+).*/\1/' <<<"$final")
  z=$(sed -E 's/.*Z_mean=([^ ]+).*/\1/' <<<"$final")
  ke=$(sed -E 's/.* ke=([^ ]+).*/\1/' <<<"$final")
  # mpirun's own RSS is not the engine's: time reports the largest of the ranks' maxima.
  echo "$loop $(cat mem.txt) $(printf "%.6g %.5g %.4g" "$force" "$z" "$ke")"
}

run_shapepress() {  # threads → "loop_s peak_kib cpu_s force_N contacts ke_J"
  local threads=$1
  /usr/bin/time -f "%M %U" -o mem.txt "$shapepress" --quiet --threads "$threads" compact \
      --config "$root/pipelines/configs/hertz-compaction-bench.toml" --packing packing.txt \
      --steps "$steps" --out run > shapepress.out 2>&1 || { cat shapepress.out >&2; exit 1; }
  local summary
  summary=$(grep '^SUMMARY' shapepress.out)
  local loop force z ke
  loop=$(sed -E 's/.*loop_s=([^ ]+).*/\1/' <<<"$summary")
  force=$(sed -E 's/.*punch_force_N=([^ ]+).*/\1/' <<<"$summary")
  z=$(sed -E 's/.*contacts_per_particle=([^ ]+).*/\1/' <<<"$summary")
  ke=$(sed -E 's/.*kinetic_energy_J=([^ ]+).*/\1/' <<<"$summary")
  echo "$loop $(cat mem.txt) $force $z $ke"
}

# x_liggghts, x_lammps: the engine's speed over the peer's, from loop (wall) times — the target.
# cpu_x_*: the same from user CPU seconds of the whole process (all threads or ranks, start-up
# included), less disturbed when other work shares the cores.
format="%-4s %-6s %-11s %-10s %-10s %-9s %-10s %-9s %-8s %-9s %-7s %-8s\n"
printf "$format" rep cores engine steps/s x_liggghts x_lammps cpu_x_ligg cpu_x_lmp peakMiB \
  punch_N Z KE_J
medians=ratios.txt  # in the scratch folder scene.sh removes on exit
for rep in $(seq 1 "$repeats"); do
  for cores in 1 2; do
    read -r l_loop l_mem l_cpu l_force l_z l_ke < <(run_peer liggghts liggghts.in "$cores")
    read -r m_loop m_mem m_cpu m_force m_z m_ke < <(run_peer lmp lammps.in "$cores")
    read -r s_loop s_mem s_cpu s_force s_z s_ke < <(run_shapepress "$cores")
    printf "$format" "$rep" "$cores" liggghts "$(rate "$l_loop")" 1.00 "$(ratio "$m_loop" "$l_loop")" \
      1.00 "$(ratio "$m_cpu" "$l_cpu")" "$((l_mem / 1024))" "$l_force" "$l_z" "$l_ke"
    printf "$format" "$rep" "$cores" lammps "$(rate "$m_loop")" "$(ratio "$l_loop" "$m_loop")" 1.00 \
      "$(ratio "$l_cpu" "$m_cpu")" 1.00 "$((m_mem / 1024))" "$m_force" "$m_z" "$m_ke"
    printf "$format" "$rep" "$cores" shapepress "$(rate "$s_loop")" "$(ratio "$l_loop" "$s_loop")" \
      "$(ratio "$m_loop" "$s_loop")" "$(ratio "$l_cpu" "$s_cpu")" "$(ratio "$m_cpu" "$s_cpu")" \
      "$((s_mem / 1024))" "$s_force" "$s_z" "$s_ke"
    echo "$cores $(ratio "$l_loop" "$s_loop") $(ratio "$m_loop" "$s_loop")" >> "$medians"
  done
done
echo "shapepress' speed over each peer, median of $repeats alternating runs (wall loop time):"
median() {  # cores column → median of that column over this core count's repeats
  awk -v c="$1" -v k="$2" '$1 == c { print $k }' "$medians" | sort -g |
    awk '{ v[NR] = $1 } END { printf "%.2f", NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}
for cores in 1 2; do
  echo "  $cores core(s): x_liggghts $(median "$cores" 2), x_lammps $(median "$cores" 3)"
done
echo "peak memory per particle (shapepress, last run): $(awk -v m="$s_mem" -v n=$particles 'BEGIN { printf "%.0f", m * 1024 / n }') bytes"
