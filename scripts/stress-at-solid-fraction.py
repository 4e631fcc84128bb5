#!/usr/bin/env python3
# The loading stress of compaction runs where their beds reach given solid fractions, by one of the
# volumes punch.csv states (docs/measurements.md, "What the BMS-sphere control rules out"): beds of
# different bodies compared where they are equally dense, and the ratio of each to the first run
# (the control). The stress is read at the first loading record at or past each fraction, so a
# fraction the run never reaches is left empty. Needs only Python's standard library; bad input
# exits 2.
#   scripts/stress-at-solid-fraction.py control/ run/ --at 0.60,0.65,0.69
#   scripts/stress-at-solid-fraction.py spheres/ bms/ --volume shape --at 0.70,0.74
import argparse
import csv
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


def loading_curve(run, column):
    path = os.path.join(run, "punch.csv") if os.path.isdir(run) else run
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    except OSError as e:
        fail(f"{path}: cannot read ({e.strerror})")
    if not rows or column not in rows[0] or "stress_Pa" not in rows[0] or "phase" not in rows[0]:
        fail(f"{path}: not a compaction punch.csv with columns phase, stress_Pa and {column}")
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
    return path, curve


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
