#!/usr/bin/env python3
# The loading stress of compaction runs where their beds reach given solid fractions, by one of the
# volumes punch.csv states (docs/measurements.md, "What the BMS-sphere control rules out"): beds of
# different bodies compared where they are equally dense, and the ratio of each to the first run
# (the control). The stress is read at the first loading record at or past each fraction, so a
# fraction the run never reaches is left empty. A run still going (no punch.csv yet) is read from
# its newest checkpoint's records, by the volume it states its solid fraction by
# (punch.solid_fraction_volume in its effective.toml) or by its sub-spheres'. Needs only Python's
# standard library; bad input exits 2.
#   scripts/stress-at-solid-fraction.py control/ run/ --at 0.60,0.65,0.69
#   scripts/stress-at-solid-fraction.py spheres/ bms/ --volume shape --at 0.70,0.74
import argparse
import csv
import json
import os
import sys

COLUMNS = {"body": "solid_fraction", "shape": "solid_fraction_shape",
           "spheres": "solid_fraction_spheres"}
LOADING, HOLD, UNLOADING = "0", "1", "2"
# A run pressed to a target fraction stops within a step of it: that counts as reaching it.
REACHED = 1e-4


def fail(message):
    print(message, file=sys.stderr)
    sys.exit(2)


def stated_volume(run):
    # The volume a compaction states `solid_fraction` by: its effective.toml's
    # punch.solid_fraction_volume, "body" when absent (runs from before the key).
    try:
        with open(os.path.join(run, "effective.toml")) as f:
            for line in f:
                key, _, value = line.partition("=")
                if key.strip() == "solid_fraction_volume":
                    return value.strip().strip('"')
    except OSError as e:
        fail(f"{run}: no punch.csv and no effective.toml to read a running compaction by "
             f"({e.strerror})")
    return "body"


def checkpoint_curve(run, column):
    # The newest checkpoint's records: the rows punch.csv will have (checkpoint format 1).
    folder = os.path.join(run, "checkpoints")
    names = sorted(n for n in os.listdir(folder) if n.startswith("step_") and n.endswith(".json"))
    if not names:
        fail(f"{run}: no punch.csv and no checkpoint in {folder}")
    path = os.path.join(folder, names[-1])
    try:
        with open(path) as f:
            checkpoint = json.load(f)
        records = checkpoint["state"]["records"]
    except (OSError, ValueError, KeyError) as e:
        fail(f"{path}: not a compaction checkpoint ({e})")
    if checkpoint.get("version") != 1:
        fail(f"{path}: checkpoint format {checkpoint.get('version')}, this script reads 1")
    stated = stated_volume(run)
    if column == COLUMNS["spheres"]:
        field = column
    elif column == COLUMNS.get(stated):
        field = "solid_fraction"
    else:
        fail(f"{run}: a running compaction's checkpoint has its solid fraction by the "
             f"{stated} volume and by the sub-spheres', not {column}")
    rows = [{"phase": str(r["phase"]), "stress_Pa": r["stress"], column: r[field]}
            for r in records]
    return path, rows


def loading_curve(run, column):
    if os.path.isdir(run) and not os.path.exists(os.path.join(run, "punch.csv")) and \
            os.path.isdir(os.path.join(run, "checkpoints")):
        path, rows = checkpoint_curve(run, column)
        return path, densest_loading(path, rows, column)
    path = os.path.join(run, "punch.csv") if os.path.isdir(run) else run
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    except OSError as e:
        fail(f"{path}: cannot read ({e.strerror})")
    if not rows or column not in rows[0] or "stress_Pa" not in rows[0] or "phase" not in rows[0]:
        fail(f"{path}: not a compaction punch.csv with columns phase, stress_Pa and {column}")
    return path, densest_loading(path, rows, column)


def densest_loading(path, rows, column):
    # Loading and hold, and the unloading records up to the punch's turn: the record written as
    # the punch turns is the densest, the peak of a run pressed to a solid fraction.
    curve, densest = [], float("-inf")
    for number, row in enumerate(rows, start=2):
        if row["phase"] not in (LOADING, HOLD, UNLOADING):
            continue
        try:
            point = (float(row[column]), float(row["stress_Pa"]))
        except ValueError:
            fail(f"{path}: line {number}: {column} or stress_Pa is not a number")
        if row["phase"] == UNLOADING and point[0] < densest:
            break
        densest = max(densest, point[0])
        curve.append(point)
    return curve


def stress_at(curve, fraction):
    densest = float("-inf")
    for solid_fraction, stress in curve:
        densest = max(densest, solid_fraction)
        if densest >= fraction - REACHED:
            return stress
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("runs", nargs="+", help="compaction folders (or their punch.csv)")
    parser.add_argument("--at", required=True,
                        help="comma-separated solid fractions, e.g. 0.60,0.65,0.69")
    parser.add_argument("--volume", choices=sorted(COLUMNS), default="body",
                        help="the volume the fractions are by (punch.csv's columns)")
    args = parser.parse_args()
    try:
        fractions = [float(v) for v in args.at.split(",")]
    except ValueError:
        fail(f"--at: {args.at!r} is not a comma-separated list of numbers")
    if any(not 0.0 < v < 1.0 for v in fractions):
        fail(f"--at: every solid fraction must lie in (0, 1), got {args.at}")
    column = COLUMNS[args.volume]
    table = []
    for run in args.runs:
        path, curve = loading_curve(run, column)
        table.append((path, [stress_at(curve, v) for v in fractions]))
    writer = csv.writer(sys.stdout)
    writer.writerow(["run", "quantity"] + [f"{column}={v:g}" for v in fractions])
    control = table[0][1]
    for path, stresses in table:
        writer.writerow([path, "stress_MPa"] +
                        ["" if s is None else f"{s / 1e6:.4g}" for s in stresses])
        if path != table[0][0]:
            writer.writerow([path, "over_first"] + [
                "" if s is None or c is None or c <= 0.0 else f"{s / c:.3g}"
                for s, c in zip(stresses, control)])


if __name__ == "__main__":
    main()
