#!/usr/bin/env bash
# Cost against accuracy of the time step (issue 4): the calibrated BMS sphere (calibrated-config.sh)
# pressed to 40 % with fixed steps of FACTOR × the default step (0.2 of the bond network's period
# bound, which is shorter than the contacts' Rayleigh time in the shipped elastic network), one
# thread. Prints per factor the CPU seconds and the RMS and largest
# relative change of the top-plate force against factor 1 at the 1 % steps from 5 % to 40 %.
# A factor whose change stays at the level of factor 0.5's (the path noise of the fill)
# is as accurate as the default step.
#   tests/bench/bms-plate/timestep.sh [N] [FACTOR...]      (defaults 545, 0.5 1 2 3)
# Needs python3 and a build/ (or SHAPEPRESS=/path/to/shapepress).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
shapepress=${SHAPEPRESS:-$root/build/app/shapepress}
[[ -x "$shapepress" ]] || { echo "timestep.sh: $shapepress is not built" >&2; exit 2; }
count=${1:-545}
[[ "$count" =~ ^[1-9][0-9]*$ ]] || { echo "timestep.sh: N must be a positive integer, got '$count'" >&2; exit 2; }
shift || true
factors=("$@")
[[ ${#factors[@]} -gt 0 ]] || factors=(0.5 1 2 3)
work=$(mktemp -d -t shapepress-bms-timestep.XXXXXX)
trap 'rm -rf "$work"' EXIT
config=$work/calibrated.toml
source "$here/calibrated-config.sh"

plate() {  # config out
  "$shapepress" --quiet --threads 1 plate --config "$1" --particle bms --count "$count" \
      --out "$2" > "$2.log" 2>&1 || { cat "$2.log" >&2; exit 1; }
}
plate "$config" "$work/f1"
step=$(sed -nE 's/.*time_step_s = ([^ ;]+).*/\1/p' "$work/f1/force.csv")
for f in "${factors[@]}"; do
  [[ "$f" == 1 ]] && continue
  dt=$(awk -v f="$f" -v s="$step" 'BEGIN { printf "%.9g", f * s }')
  sed "s/^\[run\]\$/[run]\ntime_step = $dt/" "$config" > "$work/f$f.toml"
  plate "$work/f$f.toml" "$work/f$f"
done
python3 - "$work" "$step" "${factors[@]}" <<'PY'
import csv, math, sys
work, step, factors = sys.argv[1], float(sys.argv[2]), sys.argv[3:]
def curve(path):
    rows = [r for r in csv.reader(open(path)) if r and not r[0].startswith('#')]
    head = rows[0]
    col = {name: head.index(name) for name in ('deformation', 'top_force_N', 'cpu_s', 'time_s')}
    return [{k: float(r[c]) for k, c in col.items()} for r in rows[1:]]
def at(c, x):  # top force at deformation x, linear between records
    for a, b in zip(c, c[1:]):
        if a['deformation'] <= x <= b['deformation']:
            t = (x - a['deformation']) / (b['deformation'] - a['deformation'])
            return a['top_force_N'] + t * (b['top_force_N'] - a['top_force_N'])
    raise SystemExit(f'timestep.sh: deformation {x} outside the run')
ref = curve(f'{work}/f1/force.csv')
print(f"{'factor':<7} {'step_s':<11} {'cpu_s':<8} {'rms_change':<11} {'max_change':<11} force_40_N")
for f in factors:
    c = curve(f'{work}/f{f}/force.csv')
    changes = [at(c, k / 100) / at(ref, k / 100) - 1 for k in range(5, 41)]
    rms = math.sqrt(sum(e * e for e in changes) / len(changes))
    print(f"{f:<7} {float(f) * step:<11.4g} {c[-1]['cpu_s']:<8.2f} {rms:<11.2%} "
          f"{max(abs(e) for e in changes):<11.2%} {c[-1]['top_force_N']:.1f}")
PY
