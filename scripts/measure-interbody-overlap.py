#!/usr/bin/env python3
# How deep the sub-spheres of two different bodies are pressed into each other in a compaction
# snapshot (docs/measurements.md, "Contacts between bodies"): over the touching pairs that join two
# bodies, the overlap over the smaller radius, its median, 90th and 99th percentiles and largest,
# beside the punch's stress; and how many body pairs touch (the bodies' coordination, 2 pairs /
# bodies) and how many sub-sphere contacts each carries (docs/measurements.md, "Why the bed
# stiffens with N"). compact stops a run at `max_overlap_fraction` of that ratio.
# A measurement tool, not part of the build: needs Debian's python3-h5py and python3-numpy.
#   scripts/measure-interbody-overlap.py run/snapshots/step_0000200000.h5 ...
import argparse
import sys

import h5py
import numpy as np

parser = argparse.ArgumentParser()
parser.add_argument("snapshots", nargs="+")
args = parser.parse_args()
print(
    "snapshot,stress_MPa,between_bodies,overlap_over_radius_median,p90,p99,largest,"
    "body_pairs,contacts_per_body_pair,body_coordination"
)
for path in args.snapshots:
    try:
        f = h5py.File(path, "r")
        x, r = f["particles/position"][:], f["particles/radius"][:]
        body = f["particles/body"][:]
        a, b = f["engine/contact_first"][:], f["engine/contact_second"][:]
        box = (f["engine"].attrs["box_x"], f["engine"].attrs["box_y"])
        quads = f["walls/quads"][:]
        wall_force = f["walls/force"][:]
        points = f["walls/points"][:]
    except (OSError, KeyError) as e:
        sys.exit(f"{path}: not a compaction snapshot ({e})")
    d = x[b] - x[a]
    for axis in (0, 1):
        if box[axis] > 0:
            d[:, axis] -= box[axis] * np.round(d[:, axis] / box[axis])
    overlap = r[a] + r[b] - np.linalg.norm(d, axis=1)
    between = (overlap > 0) & (body[a] != body[b])
    ratio = overlap[between] / np.minimum(r[a], r[b])[between]
    # The punch's area from its quad (the die's cross-section).
    corners = points[quads[0]]
    area = np.linalg.norm(np.cross(corners[1] - corners[0], corners[3] - corners[0]))
    stress = abs(wall_force[0]) / area / 1e6
    if ratio.size == 0:
        print(f"{path},{stress:.4g},0,,,,,0,,0")
        continue
    q = np.percentile(ratio, [50, 90, 99, 100])
    first, second = body[a][between], body[b][between]
    pairs = np.unique(np.stack([np.minimum(first, second), np.maximum(first, second)]), axis=1)
    bodies = np.unique(body).size
    print(
        f"{path},{stress:.4g},{ratio.size},"
        + ",".join(f"{v:.3f}" for v in q)
        + f",{pairs.shape[1]},{ratio.size / pairs.shape[1]:.3f},{2 * pairs.shape[1] / bodies:.3f}"
    )
