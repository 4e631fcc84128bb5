#!/usr/bin/env bash
# The rubber-sphere ladder's speed (issue 4, "Speed"): the calibrated BMS sphere (R = 10 mm, paper
# §3.1) pressed to 40 % between plates for N = 100, 250, 545, 819, 1322 sub-spheres, on 1 and on
# 2 threads. Prints wall and CPU seconds per run (the force.csv's last row: the loop, without
# start-up and fill) and the ladder's totals. Targets: N = 545 < 10 s wall on 2 cores, the whole
# ladder < 3 min.
#   tests/bench/bms-plate/run.sh [THREADS...]                   (default: 1 2)
#   COUNTS="545" SHAPEPRESS=/path/to/shapepress BASELINE=/path/to/other/shapepress run.sh 2
# BASELINE adds the other binary's run of each (N, threads) right after this one's (alternating,
# so both see the same machine load), and the ratio of their CPU seconds.
# The calibrated config: calibrated-config.sh beside this script.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
shapepress=${SHAPEPRESS:-$root/build/app/shapepress}
[[ -x "$shapepress" ]] || { echo "run.sh: $shapepress is not built" >&2; exit 2; }
[[ -z "${BASELINE:-}" || -x "$BASELINE" ]] || { echo "run.sh: BASELINE=$BASELINE is not executable" >&2; exit 2; }
threads=("$@")
[[ ${#threads[@]} -gt 0 ]] || threads=(1 2)
for t in "${threads[@]}"; do
  [[ "$t" =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: THREADS must be positive integers, got '$t'" >&2; exit 2; }
done
read -r -a counts <<<"${COUNTS:-100 250 545 819 1322}"

work=$(mktemp -d -t shapepress-bms-bench.XXXXXX)
trap 'rm -rf "$work"' EXIT
config=$work/calibrated.toml
source "$here/calibrated-config.sh"

run() {  # binary threads N → "loop_wall_s loop_cpu_s force_N process_wall_s"
  local out=$work/run-$2-$3 t0 t1
  rm -rf "$out"
  t0=$(date +%s.%N)
  "$1" --quiet --threads "$2" plate --config "$config" --particle bms --count "$3" \
      --out "$out" > "$out.log" 2>&1 || { cat "$out.log" >&2; exit 1; }
  t1=$(date +%s.%N)
  # Last row: cpu_s and wall_s columns; the force at 40 % (top plate) as a check of the physics.
  awk -F, -v p="$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }')" '/^#/ { next } !h { for (k = 1; k <= NF; ++k) c[$k] = k; h = 1; next }
           { w = $c["wall_s"]; u = $c["cpu_s"]; f = $c["top_force_N"] }
           END { printf "%.2f %.2f %.4g %s\n", w, u, f, p }' "$out/force.csv"
}

# wall_s, cpu_s: the compression loop (force.csv); run_s: the whole command (fill, bonds, output).
printf "%-6s %-8s %-9s %-9s %-9s %-10s %s\n" N threads wall_s cpu_s run_s force_N "${BASELINE:+baseline_wall_s cpu_s cpu_ratio}"
declare -A wall_total cpu_total run_total
for t in "${threads[@]}"; do
  wall_total[$t]=0; cpu_total[$t]=0; run_total[$t]=0
  for n in "${counts[@]}"; do
    read -r wall cpu force process < <(run "$shapepress" "$t" "$n")
    extra=""
    if [[ -n "${BASELINE:-}" ]]; then
      read -r bwall bcpu _ _ < <(run "$BASELINE" "$t" "$n")
      extra=$(awk -v w="$bwall" -v c="$bcpu" -v u="$cpu" 'BEGIN { printf "%-9s %-9s %.2f", w, c, c / u }')
    fi
    printf "%-6s %-8s %-9s %-9s %-9s %-10s %s\n" "$n" "$t" "$wall" "$cpu" "$process" "$force" "$extra"
    run_total[$t]=$(awk -v a="${run_total[$t]}" -v b="$process" 'BEGIN { print a + b }')
    wall_total[$t]=$(awk -v a="${wall_total[$t]}" -v b="$wall" 'BEGIN { print a + b }')
    cpu_total[$t]=$(awk -v a="${cpu_total[$t]}" -v b="$cpu" 'BEGIN { print a + b }')
  done
  printf "%-6s %-8s %-9s %-9s %-9s\n" ladder "$t" "${wall_total[$t]}" "${cpu_total[$t]}" "${run_total[$t]}"
done
