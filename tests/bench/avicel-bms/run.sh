#!/usr/bin/env bash
# The Avicel PH 200 BMS bench (issue 18 point 7): COUNT bodies of about SUB sub-spheres each
# (three generated Avicel-like shapes, Table 2's sizes above 180 um, packed and pre-compressed to
# 0.59 by `pack`), pressed by `compact` with Table 4's parameters (multi-contact law, beta = 1.3,
# Table 4's bonds), beside the spherical Avicel bed (150 spheres) for the cost per sphere-step.
#   tests/bench/avicel-bms/run.sh [THREADS]        COUNT=150 SUB=350 STEPS=0 (0: the whole run)
#                                                  DENSITY_SCALE=1000 (run.density_scale)
#                                                  BMS_CONFIG=avicel-ph200-bms.toml (Table 4's
#                                                  bonds; -calibrated.toml: the FEM-calibrated
#                                                  bonds and k1), SPHERES_CONFIG likewise
#                                                  BOND_SUBSTEPS=1 (run.bond_substeps of the
#                                                  bonded bed; 0: as many as the bonds need)
#                                                  OLD_SHAPEPRESS=path: another build (say
#                                                  main's, copied aside) pressing the same bed,
#                                                  ROUNDS times alternating with this one (2)
#                                                  PACKED=path: press this packed.h5 instead of
#                                                  generating, filling and packing one
# A reduced run for a noisy machine: STEPS=4000 with a packed bed of the study's 150 bodies at a
# lower N (COUNT=50 SUB=120 no longer packs: 50 bodies jam at 0.56 by body volume, short of the
# protocol's 0.59).
# Both compactions run with the mass scaling DENSITY_SCALE, the largest the spherical Avicel bed
# stays quasi-static at (docs/measurements.md, "Mass scaling"); 1 is the unscaled run.
# Prints wall and CPU seconds and peak memory of each stage, sub-sphere-steps and bond-steps per
# second, and the ratio to the spheres' particle-steps per second; with OLD_SHAPEPRESS, each
# build's loop seconds on the bonded bed, round by round, their ratio (old over new, the medians),
# and whether the two punch.csv are the same bytes.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../../.." && pwd)
bin=${SHAPEPRESS:-$repo/build/app/shapepress}
threads=${1:-2}
count=${COUNT:-150}
sub=${SUB:-350}
steps=${STEPS:-0}
scale=${DENSITY_SCALE:-1000}
work=${WORK:-$(mktemp -d)}
echo "avicel-bms bench: $count bodies x ~$sub sub-spheres, $threads threads, steps ${steps}, density scale $scale in $work"
cd "$work"
if [[ -n "${PACKED:-}" && ! -f packed.h5 ]]; then
  cp "$PACKED" packed.h5
fi
timed() {  # label command...: wall/CPU seconds and peak memory of one stage
  local label=$1; shift
  /usr/bin/time -f "$label wall_s=%e cpu_s=%U+%S max_rss_kB=%M" "$@" 2> >(grep -E "wall_s=|error|warning" >&2)
}
[[ -f packed.h5 ]] || [[ -f shapes/shapes.csv ]] || timed generate "$bin" --quiet generate \
  --targets "$repo/tests/data/geometry/avicel_ph200_projected.toml" --count 3 --seed 7 --out shapes
[[ -f packed.h5 ]] || [[ -f templates.h5 ]] || timed fill "$bin" --quiet fill shapes/*.stl --kind bms --count "$sub" \
  --lattice random --out templates.h5
sed "s/^count = .*/count = $count/" "$repo/pipelines/configs/pack-avicel-bms.toml" > pack.toml
[[ -f packed.h5 ]] || timed pack "$bin" --quiet --threads "$threads" pack templates.h5 \
  --config pack.toml --out packed.h5
bms_config=${BMS_CONFIG:-avicel-ph200-bms.toml}
spheres_config=${SPHERES_CONFIG:-avicel-ph200-spheres.toml}
substeps=${BOND_SUBSTEPS:-1}
for kind in bms spheres; do
  config=$bms_config
  run_keys="density_scale = $scale"
  [[ $kind == bms ]] && run_keys="$run_keys\nbond_substeps = $substeps"
  [[ $kind == spheres ]] && config=$spheres_config
  sed -E "s/^\[run\]$/[run]\n$run_keys/" \
    "$repo/pipelines/configs/$config" > "compact-$kind.toml"
done
step_args=()
[[ "$steps" != 0 ]] && step_args=(--steps "$steps")
timed compact-bms "$bin" --quiet --threads "$threads" compact \
  --config compact-bms.toml --packing packed.h5 --out bms \
  "${step_args[@]}" | tee bms.summary
timed compact-spheres "$bin" --quiet --threads "$threads" compact \
  --config compact-spheres.toml --out spheres "${step_args[@]}" \
  | tee spheres.summary
if [[ -n "${OLD_SHAPEPRESS:-}" ]]; then
  rounds=${ROUNDS:-2}
  for ((round = 1; round <= rounds; ++round)); do
    for build in old new; do
      exe=$bin
      [[ $build == old ]] && exe=$OLD_SHAPEPRESS
      rm -rf "side-$build-$round"
      "$exe" --quiet --threads "$threads" compact --config compact-bms.toml --packing packed.h5 \
        --out "side-$build-$round" "${step_args[@]}" > "side-$build-$round.summary"
    done
  done
  python3 - "$work" "$rounds" <<'PY'
import json, pathlib, statistics, sys
w, rounds = pathlib.Path(sys.argv[1]), int(sys.argv[2])
def loop_s(build, r):
    return json.loads((w / f"side-{build}-{r}" / "run.json").read_text())["facts"]["loop_s"]
old = [loop_s("old", r) for r in range(1, rounds + 1)]
new = [loop_s("new", r) for r in range(1, rounds + 1)]
for r, (o, n) in enumerate(zip(old, new), 1):
    print(f"side by side, round {r}: old {o:.2f} s, new {n:.2f} s, old/new {o / n:.3f}")
print(f"old/new loop seconds, medians: {statistics.median(old) / statistics.median(new):.3f}")
same = all((w / f"side-old-{r}" / "punch.csv").read_bytes() ==
           (w / f"side-new-{r}" / "punch.csv").read_bytes() for r in range(1, rounds + 1))
print(f"punch.csv old and new: {'identical' if same else 'DIFFERENT'}")
PY
fi
python3 - "$work" <<'PY'
import json, re, sys, pathlib
w = pathlib.Path(sys.argv[1])
def summary(name):
    line = (w / f"{name}.summary").read_text()
    return {k: float(v) for k, v in re.findall(r"(\w+)=([-0-9.e+]+)", line)}
def facts(name):
    d = json.loads((w / name / "run.json").read_text())
    return d.get("facts", d)
b, s = summary("bms"), summary("spheres")
fb = facts("bms")
bond_rate = fb["bonds"] * b["steps"] / b["loop_s"]
print(f"bms: {fb['spheres']} sub-spheres, {fb['bonds']} bonds, time step {fb['time_step_s']:.3g} s "
      f"({fb.get('bond_substeps', 1)} bond sub-steps, bound by {fb.get('time_step_bound', '?')}), "
      f"{b['steps']:.0f} steps in {b['loop_s']:.1f} s: {b['particle_steps_per_s']:.3g} "
      f"sub-sphere-steps/s, {bond_rate:.3g} bond-steps/s, contacts/particle "
      f"{b['contacts_per_particle']:.3g}, quasi-static {fb['quasi_static']} "
      f"(KE/W {fb['max_kinetic_to_work']:.3g}, imbalance {fb['mean_force_imbalance']:.3g})")
print(f"spheres: {s['particle_steps_per_s']:.3g} particle-steps/s, contacts/particle "
      f"{s['contacts_per_particle']:.3g}")
print(f"cost per sub-sphere-step / per sphere-step: "
      f"{s['particle_steps_per_s'] / b['particle_steps_per_s']:.2f}")
PY
