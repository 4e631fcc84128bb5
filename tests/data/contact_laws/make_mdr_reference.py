#!/usr/bin/env python3
"""Writes tests/data/contact_laws/mdr.csv, the reference forces and energies of the MDR normal law
(Zunker & Kamrin 2024, Part I: elastic-perfectly plastic spheres, no adhesion, no bulk response)
for tests/unit/simulate/contact_law_reference_test.cpp. Written apart from the C++ in 40-digit
arithmetic (mpmath): the side overlaps, the yield strain (a root found by mpmath.findroot, where
the C++ bisects), the indenter force in its closed trigonometric form (where the C++ takes a
series at small displacements) and the energy as the quadrature of the pair's force from the
overlap of zero force (where the C++ sums a series of the integral). Each row is one step of a
history: loading past yield, unloading to zero force and reloading past the largest overlap, for
two equal spheres, two unequal ones and a sphere on a wall (radius_j = 0).
    python3 tests/data/contact_laws/make_mdr_reference.py
"""
import os

import mpmath as mp

mp.mp.dps = 40
HERE = os.path.dirname(os.path.abspath(__file__))
COLUMNS = ["overlap", "radius_i", "radius_j", "effective_modulus", "poisson_ratio", "pair_pressure",
           "yield_stress", "max_overlap", "yield_strain", "max_overlap_after",
           "yield_strain_after", "force", "energy"]
FORMULAS = [
    "MDR (Zunker & Kamrin 2024, Part I), non-adhesive, one side = a sphere of radius R on a flat:",
    "E = 2 E* for a side of a sphere pair (two sides), E* against a wall (one side, radius_j = 0)",
    "pY(s) = Y (1.75 exp(-4.4 s) + 1); the side yields when 4 E sqrt(s) / (3 pi) > pY(s), s = dms/R",
    "sY: the root of 4 E sqrt(s) / (3 pi) = pY(s) (kept as yield_strain, 0 until a side yields)",
    "elastic side: A = 4R, B = 2R, dp = 0, scale = 1",
    "plastic side: a2 = 2 dms R - dms^2 + (sY^2 - sY) R^2, A = 4 pY sqrt(a2) / E, B = 2 sqrt(a2),",
    "  zR = R - dms + A/2, G = E (1 - nu) / 2,",
    "  dR = pY (2 a2 (nu - 1) - (2 nu - 1) zR (sqrt(a2 + zR^2) - zR)) / (2 G sqrt(a2 + zR^2)),",
    "  dp = dms - A/2 - dR, scale = 1 + 2 dR / A",
    "pair: dm = max(max_overlap, overlap); dgi = dm (2 rj - dm) / (2 (ri + rj - dm)) (capped 0.95 ri),",
    "  dgj = dm - dgi; di = dgi + (dpi - dgi) (overlap - dm) / (dpi + dpj - dm)",
    "side force: de = (di - dpi) / scale, u = de / A, theta = 2 asin(sqrt(u)),",
    "  F = E A B / 4 (theta - sin(theta) cos(theta)) for de > 0, else 0; pair F = (Fi + Fj) / 2",
    "energy: the integral of F over the overlap from zero force (di = dpi) to overlap, dm fixed",
]


def yield_pressure(y, s):
    return y * (mp.mpf("1.75") * mp.exp(-mp.mpf("4.4") * s) + 1)


class Law:
    def __init__(self, e_star, nu, y, ri, rj):
        self.nu, self.y, self.ri, self.rj = mp.mpf(nu), mp.mpf(y), mp.mpf(ri), mp.mpf(rj)
        self.wall = rj == 0
        self.e = mp.mpf(e_star) * (1 if self.wall else 2)

    def hertz_pressure(self, s):
        return 4 * self.e * mp.sqrt(s) / (3 * mp.pi)

    def yield_strain(self):
        return mp.findroot(lambda s: self.hertz_pressure(s) - yield_pressure(self.y, s),
                           (mp.mpf("1e-12"), mp.mpf(3)), solver="anderson")

    def side(self, r, dms):
        """(A, B, dp, scale, yielded) of a side of radius r at its largest overlap dms."""
        s = dms / r
        py = yield_pressure(self.y, s)
        if not self.hertz_pressure(s) > py:
            return 4 * r, 2 * r, mp.mpf(0), mp.mpf(1), False
        sy = self.yield_strain()
        a2 = 2 * dms * r - dms ** 2 + (sy ** 2 - sy) * r ** 2
        a = mp.sqrt(a2)
        height = 4 * py * a / self.e
        zr = r - dms + height / 2
        g = self.e * (1 - self.nu) / 2
        root = mp.sqrt(a2 + zr ** 2)
        dr = py * (2 * a2 * (self.nu - 1) - (2 * self.nu - 1) * zr * (root - zr)) / (2 * g * root)
        return height, 2 * a, dms - height / 2 - dr, 1 + 2 * dr / height, True

    def indenter(self, height, width, de):
        if de <= 0:
            return mp.mpf(0)
        u = de / height
        theta = 2 * mp.asin(mp.sqrt(u))
        return self.e * height * width / 4 * (theta - mp.sin(theta) * mp.cos(theta))

    def sides(self, dm):
        """[(radius, dg, A, B, dp, scale, yielded)] at the largest overlap dm."""
        if self.wall:
            return [(self.ri, dm) + self.side(self.ri, dm)]
        dg = dm * (2 * self.rj - dm) / (2 * (self.ri + self.rj - dm))
        if dg > mp.mpf("0.95") * self.ri:
            dg = mp.mpf("0.95") * self.ri
        elif dm - dg > mp.mpf("0.95") * self.rj:
            dg = dm - mp.mpf("0.95") * self.rj
        return [(self.ri, dg) + self.side(self.ri, dg), (self.rj, dm - dg) + self.side(self.rj, dm - dg)]

    def force(self, overlap, dm):
        sides = self.sides(dm)
        if self.wall:
            (_, _, height, width, dp, scale, _), = sides
            return self.indenter(height, width, (overlap - dp) / scale)
        span = sum(s[4] for s in sides) - dm
        total = mp.mpf(0)
        for _, dg, height, width, dp, scale, _ in sides:
            d = dg + (dp - dg) * (overlap - dm) / span
            total += self.indenter(height, width, (d - dp) / scale)
        return total / 2

    def zero_force_overlap(self, dm):
        return sum(s[4] for s in self.sides(dm))  # dp of the wall's one side, dpi + dpj of a pair


def rows_of(history, e_star, nu, y, ri, rj):
    """One row per overlap of `history`, each step's history the previous step's."""
    law = Law(e_star, nu, y, ri, rj)
    rows, dm, sy = [], mp.mpf(0), mp.mpf(0)
    for overlap in history:
        overlap = mp.mpf(overlap)
        dm_after = max(dm, overlap)
        yielded = any(s[6] for s in law.sides(dm_after))
        sy_after = law.yield_strain() if yielded else mp.mpf(0)
        force = law.force(overlap, dm_after)
        start = law.zero_force_overlap(dm_after)
        energy = mp.quad(lambda d: law.force(d, dm_after), [start, overlap]) if overlap > start else 0
        rows.append({"overlap": overlap, "radius_i": ri, "radius_j": rj, "effective_modulus": e_star,
                     "poisson_ratio": nu, "pair_pressure": 0.0, "yield_stress": y,
                     "max_overlap": dm, "yield_strain": sy, "max_overlap_after": dm_after,
                     "yield_strain_after": sy_after, "force": force, "energy": energy})
        dm, sy = dm_after, sy_after
    return rows


def g(v):
    return repr(float(v))


def main():
    # Avicel-like (the LAMMPS decks): E = 8 GPa, nu = 0.3, Y = 160 MPa; E* of two equal
    # spheres E / (2 (1 - nu^2)), of a sphere on a rigid wall E / (1 - nu^2).
    e, nu, y = 8e9, 0.3, 1.6e8
    pair_e = e / (2 * (1 - nu * nu))
    wall_e = e / (1 - nu * nu)
    r = 1e-4
    rows = []
    # Two equal spheres: elastic (one tiny overlap on the series branch), past yield, unloading
    # to zero force, reloading to and past the largest overlap.
    rows += rows_of([1e-10, 1e-6, 2e-6, 1e-5, 4e-5, 3.95e-5, 3.8e-5, 3.6e-5, 3.4e-5, 2.0e-5, 3.9e-5,
                     4e-5, 5e-5], pair_e, nu, y, r, r)
    # Unequal spheres (1:2).
    rows += rows_of([3e-6, 2e-5, 6e-5, 5.9e-5, 5.5e-5, 4e-5, 5.8e-5, 6.2e-5], pair_e, nu, y, r, 2 * r)
    # A sphere on a wall to a large deformation (0.4 R) and back.
    rows += rows_of([2e-6, 1e-5, 4e-5, 3.97e-5, 3.93e-5, 3.85e-5, 3.0e-5, 3.95e-5, 4e-5, 4.5e-5],
                    wall_e, nu, y, r, 0.0)
    with open(os.path.join(HERE, "mdr.csv"), "w") as out:
        for line in FORMULAS:
            out.write("# " + line + "\n")
        out.write(",".join(COLUMNS) + "\n")
        for row in rows:
            out.write(",".join(g(row[c]) for c in COLUMNS) + "\n")


main()
