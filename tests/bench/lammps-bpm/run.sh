#!/usr/bin/env bash
# The bonded bed in shapepress and in LAMMPS' BPM package side by side (issue 38, "A peer on the
# same bonded bed"; README.md beside this file):
#   LAMMPS_BPM=/path/to/lmp tests/bench/lammps-bpm/run.sh PACKED.h5
# PACKED.h5 (or the environment's PACKED): a packed bonded bed made by `pack` (bodies of equal
# sub-spheres). Environment:
#   LAMMPS_BPM   the lmp binary built with the BPM and GRANULAR packages (required; README.md)
#   STEPS=4000   steps of each run        ROUNDS=3   runs of each code, alternating
#   CONFIG       the compact config (default bench.toml beside this file)
#   SHAPEPRESS   the shapepress binary (default build/app/shapepress)
#   FRACTION=0.2 the force comparison takes the records where shapepress' punch force is above
#                this fraction of its maximum
#   WORK         the working folder (default a new temporary one)
# Each code runs on one core (shapepress --threads 1; LAMMPS built without MPI and OpenMP).
# Prints per round each code's loop seconds, the medians' sub-sphere-steps/s and bond-steps/s,
# the ratio of the speeds per core, the punch force against strain of both (RMS relative
# difference over the loaded part of the curve), and the difference of the bonds' length changes
# and of the sub-spheres' displacements at the last step.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../../.." && pwd)
if [[ -z "${LAMMPS_BPM:-}" ]]; then
  echo "run.sh: LAMMPS_BPM is not set: build LAMMPS with its BPM and GRANULAR packages as" \
    "$here/README.md says, then LAMMPS_BPM=/path/to/lmp $0 PACKED.h5" >&2
  exit 2
fi
if [[ ! -x "$LAMMPS_BPM" ]]; then
  echo "run.sh: LAMMPS_BPM=$LAMMPS_BPM is not an executable file" >&2
  exit 2
fi
lmp_help=$("$LAMMPS_BPM" -h)
packages=$(sed -n '/^Installed packages:/{n;n;p;q}' <<< "$lmp_help")
if ! [[ " $packages " == *" BPM "* && " $packages " == *" GRANULAR "* ]]; then
  echo "run.sh: $LAMMPS_BPM lacks the BPM or GRANULAR package (it has: $packages); build it as" \
    "$here/README.md says" >&2
  exit 2
fi
packed=${1:-${PACKED:-}}
if [[ $# -gt 1 || ! -f "$packed" ]]; then
  echo "run.sh: give the packed bed, a packed.h5 made by pack: $0 PACKED.h5, or PACKED=PACKED.h5" \
    "(got '$packed')" >&2
  exit 2
fi
packed=$(realpath "$packed")
bin=${SHAPEPRESS:-$repo/build/app/shapepress}
config=$(realpath "${CONFIG:-$here/bench.toml}")
steps=${STEPS:-4000}
rounds=${ROUNDS:-3}
fraction=${FRACTION:-0.2}
for name in STEPS ROUNDS; do
  value=${!name:-1}
  if ! [[ $value =~ ^[1-9][0-9]*$ ]]; then
    echo "run.sh: $name=$value is not a positive whole number" >&2
    exit 2
  fi
done
work=${WORK:-$(mktemp -d)}
mkdir -p "$work"
cd "$work"
record_every=$(sed -n 's/^record_every *= *\([0-9]*\).*/\1/p' "$config")
record_every=${record_every:-100}
# shapepress writes one snapshot, at the last step (the end state that the bonds' strains are
# compared on; a few milliseconds inside its loop).
sed -E "s/^snapshot_every *=.*/snapshot_every = $steps/" "$config" > compact.toml
grep -q "^snapshot_every = $steps" compact.toml || {
  echo "run.sh: $config has no [run] snapshot_every line to set" >&2
  exit 2
}
config=$work/compact.toml
/usr/bin/python3 "$here/export.py" "$packed" "$config" lammps
cp "$here/lammps.in" lammps/
echo "lammps-bpm bench: $packed, $steps steps, $rounds rounds, 1 core each, in $work"
version=$(sed -n 's/^Large-scale Atomic.* - \([0-9][^-]*-.*\)$/\1/p' <<< "$lmp_help" | head -1)
echo "LAMMPS $version, packages: $packages"
for ((round = 1; round <= rounds; ++round)); do
  rm -rf "sp-$round"
  "$bin" --quiet --threads 1 compact --config "$config" --packing "$packed" --steps "$steps" \
    --out "sp-$round" > "sp-$round.summary"
  (cd lammps && OMP_NUM_THREADS=1 "$LAMMPS_BPM" -in lammps.in -log "../lmp-$round.log" \
    -screen none -var NSTEPS "$steps" -var NREC "$record_every" &&
    mv final.dump "../lmp-$round.dump")
  /usr/bin/python3 - "$work" "$round" <<'PY'
import json, pathlib, re, sys
w, r = pathlib.Path(sys.argv[1]), sys.argv[2]
sp = json.loads((w / f"sp-{r}" / "run.json").read_text())["facts"]["loop_s"]
lmp = float(re.search(r"Loop time of ([0-9.eE+-]+)", (w / f"lmp-{r}.log").read_text()).group(1))
print(f"round {r}: shapepress {sp:.2f} s, LAMMPS {lmp:.2f} s, LAMMPS/shapepress {lmp / sp:.3f}")
PY
done
/usr/bin/python3 - "$work" "$rounds" "$steps" "$fraction" "$packed" <<'PY'
import csv, json, pathlib, re, statistics, sys
import h5py
import numpy as np
w, rounds, steps = pathlib.Path(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
fraction, packed = float(sys.argv[4]), sys.argv[5]
facts = json.loads((w / "sp-1" / "run.json").read_text())["facts"]
n, bonds = facts["spheres"], facts["bonds"]
sp = [json.loads((w / f"sp-{r}" / "run.json").read_text())["facts"]["loop_s"]
      for r in range(1, rounds + 1)]
logs = [(w / f"lmp-{r}.log").read_text() for r in range(1, rounds + 1)]
lmp = [float(re.search(r"Loop time of ([0-9.eE+-]+)", t).group(1)) for t in logs]
ms, ml = statistics.median(sp), statistics.median(lmp)
print(f"{n} sub-spheres, {bonds} bonds, {steps} steps of {facts['time_step_s']:.3g} s")
for name, t in (("shapepress", ms), ("LAMMPS BPM", ml)):
    print(f"{name}: median loop {t:.2f} s: {n * steps / t:.3g} sub-sphere-steps/s, "
          f"{bonds * steps / t:.3g} bond-steps/s per core")
print(f"shapepress / LAMMPS BPM speed per core (medians): {ml / ms:.2f}")

# The punch force against the strain from the start gap, record by record (same steps).
rows = [row for row in csv.reader(l for l in (w / "sp-1" / "punch.csv").open()
                                  if not l.startswith("#"))]
head = rows[0]
sp_curve = {int(float(r[head.index("step")])): (float(r[head.index("strain")]),
                                                float(r[head.index("top_force_N")]))
            for r in rows[1:]}
lmp_curve, cols = {}, None
for line in logs[0].splitlines():
    parts = line.split()
    if parts[:2] == ["Step", "Time"]:
        cols = parts
        continue
    if cols and len(parts) == len(cols):
        try:
            values = [float(p) for p in parts]
        except ValueError:
            cols = None
            continue
        lmp_curve[int(values[0])] = (values[cols.index("v_gap")], values[cols.index("v_ptop")])
gap0 = lmp_curve[0][0]
common = sorted(set(sp_curve) & set(lmp_curve))
strain = np.array([sp_curve[s][0] for s in common])
f_sp = np.array([sp_curve[s][1] for s in common])
f_lmp = np.array([lmp_curve[s][1] for s in common])
strain_lmp = np.array([(gap0 - lmp_curve[s][0]) / gap0 for s in common])
print(f"strain of the two at the same steps differs by at most "
      f"{np.max(np.abs(strain - strain_lmp)):.2g}")
loaded = f_sp > fraction * f_sp.max()
rel = (f_lmp[loaded] - f_sp[loaded]) / f_sp[loaded]
print(f"punch force, {loaded.sum()} records above {fraction} of shapepress' maximum "
      f"{f_sp.max():.4g} N: LAMMPS - shapepress RMS {np.sqrt(np.mean(rel**2)) * 100:.2g} %, "
      f"mean {np.mean(rel) * 100:+.2g} %, largest {np.max(np.abs(rel)) * 100:.2g} %; "
      f"at the end shapepress {f_sp[-1]:.4g} N, LAMMPS {f_lmp[-1]:.4g} N")
print("step strain shapepress_N LAMMPS_N")
for k in np.unique(np.linspace(0, len(common) - 1, 11).astype(int)):
    print(f"{common[k]} {strain[k]:.5f} {f_sp[k]:.5g} {f_lmp[k]:.5g}")

# The bonds' strains at the end: each bond's length change from its rest length in both codes
# (nearest image across the periodic sides), over the round-1 end states.
with h5py.File(packed, "r") as f:
    pairs, rest = f["bonds/pairs"][:], f["bonds/rest_length"][:]
    box = np.array([f.attrs["box_x"], f.attrs["box_y"]])
    x0 = f["particles/position"][:]
with h5py.File(w / "sp-1" / "snapshots" / f"step_{steps:010d}.h5", "r") as f:
    x_sp = f["particles/position"][:]
dump = (w / "lmp-1.dump").read_text().splitlines()
start = next(k for k, l in enumerate(dump) if l.startswith("ITEM: ATOMS")) + 1
x_lmp = np.array([[float(v) for v in l.split()[1:4]] for l in dump[start:]])
def stretch(x):
    d = x[pairs[:, 1]] - x[pairs[:, 0]]
    d[:, :2] -= box * np.round(d[:, :2] / box)
    return np.linalg.norm(d, axis=1) - rest
def moved(x):
    d = x - x0
    d[:, :2] -= box * np.round(d[:, :2] / box)
    return d
s_sp, s_lmp = stretch(x_sp), stretch(x_lmp)
u_sp, u_lmp = moved(x_sp), moved(x_lmp)
rms = lambda a: np.sqrt(np.mean(a**2))
print(f"bond length changes at the end: RMS {rms(s_sp):.3g} m (shapepress), {rms(s_lmp):.3g} m "
      f"(LAMMPS); their difference RMS {rms(s_lmp - s_sp) / rms(s_sp) * 100:.2g} % of "
      f"shapepress' RMS")
print(f"sub-sphere displacements at the end: RMS {rms(u_sp):.3g} m (shapepress); the codes' "
      f"difference RMS {rms(u_lmp - u_sp) / rms(u_sp) * 100:.2g} % of it")
PY
