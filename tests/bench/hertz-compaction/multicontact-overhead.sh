#!/usr/bin/env bash
# Cost of the multi-contact law (paper Eq. 6, issue 5) against plain Hertz on the engine's
# reference scene (README.md beside this script), with ONE build, alternating in one run:
#   hertz        the shipped bench config
#   multicontact λp = 0.3, β = 1.3 (plastic history, Love–Weber stress, β ν A P term)
#   mc-reduced   normal_law = "multicontact" with its defaults (Hertz forces + the stress sum)
# Prints the loop time of each run and the ratios to Hertz of the same repeat. Optional
# BASELINE=/path/to/other/shapepress adds that binary's Hertz run (e.g. main before a change).
#   tests/bench/hertz-compaction/multicontact-overhead.sh [REPEATS] [STEPS] [THREADS]  (2 4000 1)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
repeats=${1:-2}
steps=${2:-4000}
threads=${3:-1}
shapepress=${SHAPEPRESS:-$root/build/app/shapepress}
[[ -x "$shapepress" ]] || { echo "multicontact-overhead.sh: $shapepress is not built" >&2; exit 2; }
work=$(mktemp -d -t shapepress-mc-bench.XXXXXX)
trap 'rm -rf "$work"' EXIT
cd "$work"
python3 "$here/gen_packing.py" >/dev/null
config=$root/pipelines/configs/hertz-compaction-bench.toml
cp "$config" hertz.toml
sed 's/^rolling_friction = 0.0/rolling_friction = 0.0\nnormal_law = "multicontact"\nplasticity_ratio = 0.3\nmulticontact_prefactor = 1.3/' \
  "$config" > multicontact.toml
sed 's/^rolling_friction = 0.0/rolling_friction = 0.0\nnormal_law = "multicontact"/' "$config" > mc-reduced.toml

loop_time() {  # binary config → "loop_s contacts_per_particle"
  local summary
  summary=$("$1" --quiet --threads "$threads" compact --config "$2" --packing packing.txt \
      --steps "$steps" --out run | grep '^SUMMARY')
  echo "$(sed -E 's/.*loop_s=([^ ]+).*/\1/' <<<"$summary") $(sed -E 's/.*contacts_per_particle=([^ ]+).*/\1/' <<<"$summary")"
}

printf "%-4s %-14s %-10s %-8s %-6s\n" rep run loop_s ratio Z
for rep in $(seq 1 "$repeats"); do
  read -r hertz z < <(loop_time "$shapepress" hertz.toml)
  printf "%-4s %-14s %-10s %-8s %-6s\n" "$rep" hertz "$hertz" 1.00 "$z"
  if [[ -n "${BASELINE:-}" ]]; then
    read -r t z < <(loop_time "$BASELINE" hertz.toml)
    printf "%-4s %-14s %-10s %-8s %-6s\n" "$rep" hertz-baseline "$t" \
      "$(awk -v a="$t" -v b="$hertz" 'BEGIN { printf "%.3f", a / b }')" "$z"
  fi
  for law in multicontact mc-reduced; do
    read -r t z < <(loop_time "$shapepress" "$law.toml")
    printf "%-4s %-14s %-10s %-8s %-6s\n" "$rep" "$law" "$t" \
      "$(awk -v a="$t" -v b="$hertz" 'BEGIN { printf "%.3f", a / b }')" "$z"
  done
done
