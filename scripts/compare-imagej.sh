#!/usr/bin/env bash
# Prints docs/imaging.md's table "side by side with ImageJ 1.53t": for each real image of
# tests/data/imaging, ImageJ's stored Analyze Particles results (without and with its Watershed)
# and shape-stats runs with the options below, as count, mean area (px²), mean Feret and mean
# MinFeret (px). Needs a built build/app/shapepress, not ImageJ. The scores against the
# hand marks come from `ctest --test-dir build -R MarkedParticles -V`.
set -euo pipefail
cd "$(dirname "$0")/.."
shapepress=build/app/shapepress
data=tests/data/imaging
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

runs=("" "--no-split" "--split neck" "--split imagej" "--split-gaps smoothed"
  "--denoise none" "--background none" "--background quadratic --background-min-fraction 0"
  "--imagej" "--imagej --split imagej")

# mean of the columns named in $2.. of a CSV ($1), '#' lines skipped: "count area feret minferet"
means() {
  awk -F, -v area="$2" -v feret="$3" -v minferet="$4" '
    /^#/ { next }
    !header { for (i = 1; i <= NF; ++i) col[$i] = i; header = 1; next }
    { ++n; a += $col[area]; f += $col[feret]; m += $col[minferet] }
    END { if (n) printf "%d | %.1f | %.2f | %.2f", n, a / n, f / n, m / n; else printf "0 | — | — | —" }' "$1"
}

echo "| image | run | count | area | Feret | MinFeret |"
echo "|---|---|---:|---:|---:|---:|"
for entry in coins.png:bright gravel256.png:bright gravel256_tr.png:bright gravel256_br.png:bright \
  blobs.gif:dark water_coins.png:dark smarties.png:dark; do
  image=${entry%%:*} polarity=${entry##*:} stem=${image%.*}
  for ws in 0 1; do
    label=$([[ $ws == 1 ]] && echo "ImageJ, Watershed" || echo "ImageJ, no watershed")
    if [[ -f $data/${stem}_ij_ws$ws.csv ]]; then
      echo "| $stem | $label | $(means "$data/${stem}_ij_ws$ws.csv" Area Feret MinFeret) |"
    else
      echo "| $stem | $label | 0 | — | — | — |"
    fi
  done
  for run in "${runs[@]}"; do
    read -ra options <<<"$run"
    label=${run:-**defaults**}
    [[ -n $run ]] && label="\`$run\`"
    if "$shapepress" shape-stats "$data/$image" --polarity "$polarity" --pixel-size 1m \
      --out "$work/out" --no-overlays --quiet "${options[@]}" >/dev/null 2>&1; then
      echo "| $stem | $label | $(means "$work/out/particles.csv" area_px feret_max_m feret_min_m) |"
    else
      echo "| $stem | $label | 0 | — | — | — |"
    fi
    rm -rf "$work/out"
  done
done
