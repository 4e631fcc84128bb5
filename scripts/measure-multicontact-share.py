#!/usr/bin/env python3
# The multi-contact term's share of the normal force in a compaction snapshot (Giannis 2023
# Eq. 6; docs/measurements.md, "One material, the body volume, ..."): per touching contact the
# hysteretic force (the loading branch k1 δ^{3/2}, k1 = 4/3 E*_L √R*, or the unloading branch
# from the snapshot's plastic force) and the term 3 β ν π R* δ p̄ (p̄ the pair's mean Love–Weber
# pressure, tension as 0), as the engine computes them (simulate/multicontact_law.hpp).
# A measurement tool, not part of the build: needs Debian's python3-h5py and python3-numpy.
#   scripts/measure-multicontact-share.py --loading-modulus 1.39e9 --poisson 0.3 --beta 1.3 \
#       --plasticity-ratio 0.3 --box 1e-3 run/snapshots/step_0000400000.h5 ...
import argparse
import sys

import h5py
import numpy as np

parser = argparse.ArgumentParser()
parser.add_argument("--loading-modulus", type=float, required=True, help="E_L [Pa]")
parser.add_argument("--poisson", type=float, required=True)
parser.add_argument("--beta", type=float, required=True, help="multicontact_prefactor")
parser.add_argument("--plasticity-ratio", type=float, required=True, help="λp")
parser.add_argument("--box", type=float, required=True, help="periodic box side [m]")
parser.add_argument("snapshots", nargs="+")
args = parser.parse_args()
effective_modulus = args.loading_modulus / (2 * (1 - args.poisson**2))
print("snapshot,solid_fraction_body,contacts,between_bodies,share_all,share_between_bodies,"
      "median_share_between_bodies,median_overlap_over_radius_between_bodies")
for path in args.snapshots:
    try:
        f = h5py.File(path, "r")
        x, r = f["particles/position"][:], f["particles/radius"][:]
        body, p = f["particles/body"][:], f["particles/pressure"][:]
        a, b = f["engine/contact_first"][:], f["engine/contact_second"][:]
        plastic = f["engine/contact_plastic_force"][:]
        names = [n.decode() if isinstance(n, bytes) else n for n in f["scenario/names"][:]]
        scenario = dict(zip(names, f["scenario/values"][:]))
        walls = f["walls/position"][:]
    except (OSError, KeyError) as e:
        sys.exit(f"{path}: not a compaction snapshot ({e})")
    d = x[b] - x[a]
    d[:, :2] -= args.box * np.round(d[:, :2] / args.box)
    overlap = (r[a] + r[b] - np.linalg.norm(d, axis=1)).clip(0)
    radius = r[a] * r[b] / (r[a] + r[b])
    loading = 4 / 3 * effective_modulus * np.sqrt(radius) * overlap**1.5
    hysteretic = np.minimum(loading, (loading - plastic) / args.plasticity_ratio).clip(0)
    pressure = np.maximum(0.5 * (p[a] + p[b]), 0)
    confinement = 3 * args.beta * args.poisson * np.pi * radius * overlap * pressure
    touching = overlap > 0
    between = touching & (body[a] != body[b])
    total = hysteretic + confinement
    share = lambda sel: confinement[sel].sum() / total[sel].sum() if sel.any() else float("nan")
    per_contact = (confinement / np.where(total > 0, total, 1))[between & (total > 0)]
    fraction = scenario.get("bed_body_volume", float("nan")) / (args.box**2 * abs(walls[1] - walls[0]))
    smaller = np.minimum(r[a], r[b])
    print(f"{path},{fraction:.4f},{touching.sum()},{between.sum()},{share(touching):.4f},"
          f"{share(between):.4f},{np.median(per_contact) if per_contact.size else float('nan'):.4f},"
          f"{np.median(overlap[between] / smaller[between]) if between.any() else float('nan'):.4f}")
