#!/usr/bin/env python3
"""Writes the reference forces and energies of the normal contact laws (one CSV per law) from
their closed-form equations, for tests/unit/simulate/contact_law_reference_test.cpp. Written apart
from the C++ (branch by branch as the papers state them, in exact rationals where the inputs
allow), so the test compares two derivations, not the code with itself.
    python3 tests/data/contact_laws/make_reference.py
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
COMMON = ["overlap", "radius_i", "radius_j", "effective_modulus", "poisson_ratio", "pair_pressure"]


def g(v):
    return "" if v is None else repr(float(v))


def write(name, formulas, columns, rows):
    with open(os.path.join(HERE, name + ".csv"), "w") as out:
        for line in formulas:
            out.write("# " + line + "\n")
        out.write(",".join(columns) + "\n")
        for row in rows:
            out.write(",".join(g(row.get(c)) for c in columns) + "\n")


def hertz():
    rows = []
    for delta, ri, rj, e_star in [(1e-6, 1e-4, 1e-4, 1e8), (3e-6, 2e-4, 5e-5, 2.5e8),
                                  (2e-5, 1e-3, 1e-3, 1.85e7), (1e-7, 5e-5, 3e-4, 5e9),
                                  (4e-6, 1e-4, 1e10, 3e8)]:  # the last: against a plane
        r = ri * rj / (ri + rj)
        rows.append({"overlap": delta, "radius_i": ri, "radius_j": rj, "effective_modulus": e_star,
                     "poisson_ratio": 0.3, "pair_pressure": 0.0,
                     "force": 4.0 / 3.0 * e_star * math.sqrt(r) * delta ** 1.5,
                     "energy": 8.0 / 15.0 * e_star * math.sqrt(r) * delta ** 2.5})
    write("hertz", ["Hertz (Johnson 1985 Eq. 4.22), R* = ri rj / (ri + rj):",
                    "force = 4/3 E* sqrt(R*) overlap^(3/2)",
                    "energy = 8/15 E* sqrt(R*) overlap^(5/2)"],
          COMMON + ["force", "energy"], rows)


def multicontact():
    keys = ["plasticity_ratio", "loading_stiffness", "adhesion_stiffness", "pull_off_force",
            "multicontact_prefactor"]
    rows = []

    def case(delta, ri, rj, e_star, nu, pressure, lam, k1_given, kc, f0, beta, xmax_before):
        """xmax_before: the largest δ^{3/2} the contact reached before this step (0: virgin)."""
        r = ri * rj / (ri + rj)
        k1 = k1_given if k1_given is not None else 4.0 / 3.0 * e_star * math.sqrt(r)
        k2 = k1 / lam
        x = delta ** 1.5
        # Eq. 6 (Giannis 2023): loading k1 x while x >= xmax; unloading/reloading k2 (x - xp)
        # with xp = (1 - λp) xmax (the branches meet at xmax); never below the adhesive -kc x.
        if x >= xmax_before:
            xmax = x
            hysteretic = k1 * x
        else:
            xmax = xmax_before
            xp = (1.0 - lam) * xmax
            hysteretic = max(k2 * (x - xp), -kc * x)
        xp = (1.0 - lam) * xmax
        area = math.pi * r * delta  # A_ij = π a², a² = R* δ
        # P_ij: the pair's mean trace of the Love–Weber stress, 3 × its mean pressure p̄
        # (the pair_pressure column), a tensile p̄ counting as 0.
        trace = 3.0 * max(pressure, 0.0)
        force = f0 + hysteretic + beta * nu * area * trace
        # Energy given back unloading along k2 to the plastic overlap δp = xp^{2/3}:
        # ∫_{δp}^{δ} k2 (s^{3/2} - xp) ds = k2 (2/5 (δ^{5/2} - δp^{5/2}) - xp (δ - δp)).
        dp = xp ** (2.0 / 3.0)
        energy = k2 * (0.4 * (delta ** 2.5 - dp ** 2.5) - xp * (delta - dp)) if delta > dp else 0.0
        row = {"overlap": delta, "radius_i": ri, "radius_j": rj, "effective_modulus": e_star,
               "poisson_ratio": nu, "pair_pressure": pressure, "plasticity_ratio": lam,
               "loading_stiffness": k1_given, "adhesion_stiffness": kc, "pull_off_force": f0,
               "multicontact_prefactor": beta,
               # The history the law keeps: k1 xp, the "plastic force".
               "plastic_force": k1 * (1.0 - lam) * xmax_before,
               "plastic_force_after": k1 * xp,
               "force": force, "energy": energy}
        rows.append(row)

    # Defaults (λp = 1, kc = F0 = β = 0): Hertz.
    case(1e-6, 1e-4, 1e-4, 1e8, 0.3, 0.0, 1.0, None, 0.0, 0.0, 0.0, 0.0)
    # Virgin loading with λp = 0.3, k1 from E*.
    case(2e-6, 1e-4, 1e-4, 1e8, 0.3, 0.0, 0.3, None, 0.0, 0.0, 0.0, 0.0)
    # Unloading below a δmax of 3 µm (x = 5.196e-9), along k2 = k1/λp.
    case(2.5e-6, 1e-4, 1e-4, 1e8, 0.3, 0.0, 0.3, None, 0.0, 0.0, 0.0, (3e-6) ** 1.5)
    # Reloading past δmax: back on the loading branch, the history follows.
    case(3.5e-6, 1e-4, 1e-4, 1e8, 0.3, 0.0, 0.3, None, 0.0, 0.0, 0.0, (3e-6) ** 1.5)
    # A stated k1, adhesion and pull-off: deep unloading ends on the adhesive branch -kc x.
    case(1.0e-6, 2e-4, 2e-4, 1e8, 0.3, 0.0, 0.2, 2e6, 5e5, -1e-4, 0.0, (4e-6) ** 1.5)
    # The same contact just below δmax: still the k2 branch.
    case(3.9e-6, 2e-4, 2e-4, 1e8, 0.3, 0.0, 0.2, 2e6, 5e5, -1e-4, 0.0, (4e-6) ** 1.5)
    # The multi-contact term β ν π R* δ 3p̄ with a confining pressure; a tensile p̄ counts as 0.
    case(2e-6, 1e-4, 3e-4, 2.58e8, 0.3, 5e6, 0.3, None, 0.0, 0.0, 1.3, 0.0)
    case(2e-6, 1e-4, 3e-4, 2.58e8, 0.3, -5e6, 0.3, None, 0.0, 0.0, 1.3, 0.0)
    # Against a plane (R* = ri), Avicel-like.
    case(5e-6, 1e-4, 1e10, 2.8e8, 0.3, 2e7, 0.3, None, 0.0, 0.0, 1.3, (6e-6) ** 1.5)
    write("multicontact",
          ["Multi-contact adhesive elastic-plastic law, Giannis et al. 2023 Eq. 6, x = overlap^(3/2):",
           "k1 = loading_stiffness or 4/3 E* sqrt(R*); k2 = k1 / plasticity_ratio; xp = (1 - lp) xmax",
           "hys = k1 x if x >= xmax (then xmax = x) else max(k2 (x - xp), -kc x)",
           "force = F0 + hys + beta nu pi R* overlap 3 max(P, 0), P = pair_pressure the pair's mean",
           "Love-Weber pressure -tr(sigma)/3 (so 3P is the mean trace, P_ij of Eq. 6)",
           "plastic_force = k1 xp (the history before and after the step)",
           "energy = k2 (2/5 (d^(5/2) - dp^(5/2)) - xp (d - dp)), dp = xp^(2/3), 0 if d <= dp"],
          COMMON + keys + ["plastic_force", "plastic_force_after", "force", "energy"], rows)


hertz()
multicontact()
