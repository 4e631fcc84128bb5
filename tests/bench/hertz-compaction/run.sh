#!/usr/bin/env bash
# The engine benchmark: the reference scene (README.md beside this script) in shapepress and in
# LIGGGHTS 3.8 (Debian), alternating in one run, on 1 core and on 2 (2 threads vs 2 MPI ranks).
# Prints particle-steps per second for each, the ratios, peak memory, and the physics at the end
# (punch force, mean contacts per particle, kinetic energy) side by side.
#   tests/bench/hertz-compaction/run.sh [REPEATS] [STEPS]     (defaults 3, 4000)
# Needs: scripts/install-deps.sh --peers (liggghts, openmpi-bin, python3, time) and a build/.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
repeats=${1:-3}
steps=${2:-4000}
script=run.sh
source "$here/scene.sh" liggghts mpirun python3 /usr/bin/time

# particle-steps per second from a loop time in seconds
rate() { awk -v n=$particles -v s="$steps" -v t="$1" 'BEGIN { printf "%.4g", n * s / t }'; }

run_liggghts() {  # ranks → "loop_s peak_kib cpu_s force_N contacts ke_J"
  local ranks=$1 launcher=()
  [[ $ranks -gt 1 ]] && launcher=(mpirun --allow-run-as-root --oversubscribe -np "$ranks")
  /usr/bin/time -f "%M %U" -o mem.txt "${launcher[@]}" liggghts -in liggghts.in -log none \
      -var NSTEPS "$steps" > liggghts.out 2>&1
  local loop final
  loop=$(awk '/^Loop time of/ { print $4 }' liggghts.out)
  final=$(grep '^FINAL' liggghts.out)
  local force z ke
  force=$(sed -E 's/.*punch_force=([^ ]+).*/\1/' <<<"$final")
  z=$(sed -E 's/.*Z_mean=([^ ]+).*/\1/' <<<"$final")
  ke=$(sed -E 's/.* ke=([^ ]+).*/\1/' <<<"$final")
  # mpirun's own RSS is not the engine's: take the largest of the ranks' maxima reported.
  echo "$loop $(cat mem.txt) $force $z $ke"
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

# ratio: of loop (wall) times, the target. cpu_ratio: of user CPU seconds of the whole process
# (all threads or ranks, start-up included): less disturbed when other work shares the cores.
printf "%-4s %-8s %-12s %-12s %-9s %-9s %-9s %-10s %-8s %-10s\n" rep cores engine steps/s ratio \
  cpu_ratio peakMiB punch_N Z KE_J
for rep in $(seq 1 "$repeats"); do
  for cores in 1 2; do
    read -r l_loop l_mem l_cpu l_force l_z l_ke < <(run_liggghts "$cores")
    read -r s_loop s_mem s_cpu s_force s_z s_ke < <(run_shapepress "$cores")
    l_rate=$(rate "$l_loop"); s_rate=$(rate "$s_loop")
    ratio=$(awk -v a="$s_loop" -v b="$l_loop" 'BEGIN { printf "%.2f", b / a }')
    cpu_ratio=$(awk -v a="$s_cpu" -v b="$l_cpu" 'BEGIN { printf "%.2f", b / a }')
    printf "%-4s %-8s %-12s %-12s %-9s %-9s %-9s %-10s %-8s %-10s\n" "$rep" "$cores" liggghts "$l_rate" \
      1.00 1.00 "$((l_mem / 1024))" "$l_force" "$l_z" "$l_ke"
    printf "%-4s %-8s %-12s %-12s %-9s %-9s %-9s %-10s %-8s %-10s\n" "$rep" "$cores" shapepress "$s_rate" \
      "$ratio" "$cpu_ratio" "$((s_mem / 1024))" "$s_force" "$s_z" "$s_ke"
  done
done
echo "peak memory per particle (shapepress, last run): $(awk -v m="$s_mem" -v n=$particles 'BEGIN { printf "%.0f", m * 1024 / n }') bytes"
