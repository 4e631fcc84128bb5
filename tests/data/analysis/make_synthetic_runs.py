#!/usr/bin/env python3
"""Writes the synthetic run folders used by the analysis tests (run from this folder).

compaction_run/punch.csv: a Heckel-exact loading branch (K = 1/(50 MPa), A = 0.5) to 100 MPa,
  a hold, and a linear elastic unloading to H_unloaded = 1.04 H_min; H0 = gap at zero stress.
plate_run/force.csv: the Tatara force of the paper's rubber sphere (R = 10 mm, E = 18.5 MPa,
  nu = 0.46) as the "simulated" force, with the Hertz force in hertz_force_N, to 40 % deformation.
bad_run/punch.csv: a punch curve without its stress_Pa column.
Each folder also gets the run.json its stage would write (common/run_metadata.hpp): the report
reads H0, the die area, the particle kind, sub-sphere count and fills from it, not from the
comment lines, which stay for people.
"""
import json
import math
import os

DIE_AREA = 1e-4
SOLID_HEIGHT = 4e-3
K, A = 1.0 / 50e6, 0.5


def write(path, comments, header, rows):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        for c in comments:
            f.write("# " + c + "\n")
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join("%.10g" % v for v in r) + "\n")


def write_run_json(folder, stage, outputs, facts):
    record = {"schema": 1, "stage": stage, "version": "synthetic", "revision": "",
              "command": "tests/data/analysis/make_synthetic_runs.py", "inputs": [],
              "outputs": outputs, "facts": facts}
    with open(os.path.join(folder, "run.json"), "w") as f:
        json.dump(record, f, indent=2)
        f.write("\n")


def punch_rows():
    rows = []
    h0 = SOLID_HEIGHT / (1 - math.exp(-A))
    n = 101
    for i in range(n):
        p = 100e6 * i / (n - 1)
        d = 1 - math.exp(-(K * p + A))
        rows.append((p, d, 0))
    p_max, d_max = rows[-1][0], rows[-1][1]
    h_min = SOLID_HEIGHT / d_max
    out = []
    step = 0
    for p, d, phase in rows:
        out.append((p, SOLID_HEIGHT / d, phase))
    for _ in range(5):
        out.append((p_max, h_min, 1))
    h_u = 1.04 * h_min
    for i in range(1, 21):
        h = h_min + (h_u - h_min) * i / 20
        out.append((p_max * (h_u - h) / (h_u - h_min), h, 2 if i < 20 else 3))
    table = []
    for step, (p, h, phase) in enumerate(out):
        table.append((1e-5 * step, step * 10, h, (h0 - h) / h0, p * DIE_AREA, p * DIE_AREA, p,
                      SOLID_HEIGHT / h, phase, 0.0, 0, 0, 0.0))
    return h0, table


PUNCH_HEADER = ["time_s", "step", "gap_m", "strain", "top_force_N", "bottom_force_N", "stress_Pa",
                "solid_fraction", "phase", "kinetic_energy_J", "contacts", "wall_contacts",
                "contacts_per_particle"]


def tatara_force(delta, r=0.01, e=18.5e6, nu=0.46):
    es = e / (1 - nu * nu)

    def approach(f):
        a = (3 * f * r / (4 * es)) ** (1 / 3)
        s = a * a + 4 * r * r
        return 2 * ((3 * f / (4 * es * math.sqrt(r))) ** (2 / 3) - f * (1 + nu) / (math.pi * e) *
                    ((1 - nu) / math.sqrt(s) + 2 * r * r / s ** 1.5))
    lo, hi = 0.0, 1.0
    while approach(hi) < delta:
        hi *= 2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if approach(mid) < delta else (lo, mid)
    return 0.5 * (lo + hi)


def main():
    h0, table = punch_rows()
    comments = ["synthetic (tests/data/analysis/make_synthetic_runs.py): Heckel K = 2e-08 1/Pa, "
                "A = 0.5, unload to 1.04 H_min",
                "shapepress compact; strain from H0 = %.10g m; die area %.10g m^2" % (h0, DIE_AREA),
                "phase: 0 load, 1 hold, 2 unload, 3 done"]
    write("compaction_run/punch.csv", comments, PUNCH_HEADER, table)
    write("bad_run/punch.csv", comments, [c for c in PUNCH_HEADER if c != "stress_Pa"],
          [r[:6] + r[7:] for r in table])
    # H0 as the comment gives it (10 digits), so the numbers the tests expect do not move.
    compaction_facts = {"reference_gap_m": float("%.10g" % h0), "die_area_m2": DIE_AREA,
                        "solid_volume_m3": float("%.10g" % (SOLID_HEIGHT * DIE_AREA)), "strain_reference": "start",
                        "particle_kind": "sphere", "spheres": 0, "clumps": 0, "bonds": 0,
                        "laws": [], "time_step_s": 1e-6, "steps": (len(table) - 1) * 10}
    for folder in ("compaction_run", "bad_run"):
        write_run_json(folder, "compact", ["punch.csv"], compaction_facts)
    r, es = 0.01, 18.5e6 / (1 - 0.46 ** 2)
    rows = []
    for i in range(81):
        deformation = 0.4 * i / 80
        delta = 2 * r * deformation
        hertz = math.sqrt(2) / 3 * es * math.sqrt(r) * delta ** 1.5
        f = tatara_force(delta) if delta > 0 else 0.0
        rows.append((1e-4 * i, deformation, delta, f, f, hertz))
    write("plate_run/force.csv",
          ["synthetic (tests/data/analysis/make_synthetic_runs.py): Tatara force of R = 10 mm, "
           "E = 18.5 MPa, nu = 0.46 as top_force_N",
           "hertz_force_N = (sqrt(2)/3) E* sqrt(R) approach^1.5 (models.md), E* sphere-plate"],
          ["time_s", "deformation", "approach_m", "top_force_N", "bottom_force_N", "hertz_force_N"],
          rows)
    write_run_json("plate_run", "plate", ["force.csv"],
                   {"particle_kind": "sphere", "sub_spheres": 1, "bonds": 0, "fills": 1,
                    "radius_m": r, "max_deformation": 0.4, "normal_law": "hertz", "laws": [],
                    "time_step_s": 1e-4, "rows": len(rows)})


if __name__ == "__main__":
    main()
