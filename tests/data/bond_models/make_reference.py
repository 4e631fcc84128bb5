#!/usr/bin/python3
"""Writes the bond models' reference files, tests/data/bond_models/<model>.csv, from the closed
form of a bonded pair under a prescribed displacement history (stdlib only):

    /usr/bin/python3 tests/data/bond_models/make_reference.py

A Potyondy-Cundall parallel bond of radius R = lambda r between two spheres of radius r
(A = pi R^2, I = pi R^4/4, J = pi R^4/2) has per mode an elastic spring
    normal kn A, shear ks A, twist ks J, bending kn I
(kn, ks per unit area). Each mode is driven on its own along a straight path (the test drives the
engine's bond with the same history): the normal mode by the centre distance, 2r + u; the shear
mode by a slip u of the second sphere normal to the bond; the twist and bending modes by turning
the spheres by -u/2 and +u/2 about the bond axis or normal to it.

elastic: F = -k u (the restoring force on the second sphere, the engine's sign).

elastic_plastic: the mode yields at F_y0 = sigma_y A (normal), tau_y A (shear), tau_y J/R (twist),
sigma_y I/R (bending), the same in tension and compression, and hardens isotropically:
F_y(kappa) = F_y0 + H k kappa, kappa the accumulated plastic displacement. Along a leg of the path
that moves the same way, from a state (F0, kappa0), the mode is elastic until its force reaches
the limit F_y(kappa0) in the direction of motion, after an elastic reach
    a = (F_y(kappa0) - s R0)/k,   s = sign of the motion, R0 = -F0 the resistance,
and past it follows the tangent k H/(1 + H), its plastic displacement growing by 1/(1 + H) of
the displacement beyond the reach:
    beyond = max(0, |u - u0| - a)
    R = s (F_y(kappa0) + k H/(1 + H) beyond)   if beyond > 0,   else R0 + k (u - u0)
    kappa = kappa0 + beyond/(1 + H),   u_p = u - R/k,   F = -R.
Unloading is elastic (slope k) from the reduced force: the plastic displacement u_p stays.
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
MODES = ["normal", "shear", "twist", "bending"]
PATH_FIELDS = ["normal_plastic_path", "shear_plastic_path", "twist_plastic_path",
               "bend_plastic_path"]

RADIUS = 1e-3          # r [m], lambda = 1: R = r
NORMAL_STIFFNESS = 1e12  # kn [N/m^3]
SHEAR_STIFFNESS = 5e11   # ks [N/m^3]


def springs(radius, kn, ks):
    area = math.pi * radius ** 2
    bend = math.pi * radius ** 4 / 4.0
    polar = math.pi * radius ** 4 / 2.0
    return [kn * area, ks * area, ks * polar, kn * bend]


def limits(radius, sigma_y, tau_y):
    area = math.pi * radius ** 2
    bend = math.pi * radius ** 4 / 4.0
    polar = math.pi * radius ** 4 / 2.0
    return [sigma_y * area, tau_y * area, tau_y * polar / radius, sigma_y * bend / radius]


def leg(state, u, k, limit0, hardening):
    """The closed form along one leg from state (u0, R0, kappa0) to displacement u."""
    u0, r0, kappa0 = state
    if u == u0:
        return state
    s = 1.0 if u > u0 else -1.0
    limit = limit0 + hardening * k * kappa0
    reach = (limit - s * r0) / k
    beyond = max(0.0, abs(u - u0) - reach)
    if beyond > 0.0:
        r = s * (limit + k * hardening / (1.0 + hardening) * beyond)
        kappa = kappa0 + beyond / (1.0 + hardening)
    else:
        r = r0 + k * (u - u0)
        kappa = kappa0
    return (u, r, kappa)


def path_points(unit, k, limit0, hardening):
    """The displacements of the history, in units of the yield displacement `unit`: load to 3,
    unload to zero force, reload to 4, compress to -3, unload to zero force; rows every half
    unit along each leg and at each turning point."""
    points = [0.0]

    def go_to(target):
        start = points[-1]
        n = max(1, int(math.ceil(abs(target - start) / (0.5 * unit))))
        for m in range(1, n + 1):
            points.append(start + (target - start) * m / n)

    def zero_force_point():
        # The plastic displacement of the state reached so far: where unloading meets F = 0.
        state = (0.0, 0.0, 0.0)
        for u in points[1:]:
            state = leg(state, u, k, limit0, hardening)
        return state[0] - state[1] / k

    go_to(3.0 * unit)
    go_to(zero_force_point())
    go_to(4.0 * unit)
    go_to(-3.0 * unit)
    go_to(zero_force_point())
    return points


def fmt(x):
    return repr(float(x))


def write(name, header_comment, columns, rows):
    path = os.path.join(HERE, name + ".csv")
    with open(path + ".tmp", "w") as out:
        out.write("# Written by tests/data/bond_models/make_reference.py (the closed form, not the "
                  "engine's code); read by\n# tests/unit/simulate/bond_model_reference_test.cpp.\n")
        for line in header_comment:
            out.write("# " + line + "\n")
        out.write(",".join(columns) + "\n")
        for row in rows:
            out.write(",".join(row) + "\n")
    os.replace(path + ".tmp", path)


def elastic():
    k = springs(RADIUS, NORMAL_STIFFNESS, SHEAR_STIFFNESS)
    units = [1e-5, 8e-6, 8e-3, 1e-2]  # displacements of the order of the plastic cases'
    rows = []
    for mode in range(4):
        points = [0.0]
        for target in (3.0, -2.0, 0.5):
            start = points[-1]
            for m in range(1, 7):
                points.append(start + (target * units[mode] - start) * m / 6)
        for step, u in enumerate(points):
            rows.append([MODES[mode], str(step), fmt(u), fmt(RADIUS), fmt(NORMAL_STIFFNESS),
                         fmt(SHEAR_STIFFNESS), fmt(-k[mode] * u), fmt(0.0)])
    write("elastic",
          ["Potyondy-Cundall elastic parallel bond: force = -k displacement, k = kn A, ks A, "
           "ks J, kn I by mode;",
           "plastic_displacement = 0. step 0: a bond at rest; each row moves on from the one "
           "before."],
          ["mode", "step", "displacement", "radius", "normal_stiffness", "shear_stiffness",
           "force", "plastic_displacement"], rows)


def elastic_plastic():
    k = springs(RADIUS, NORMAL_STIFFNESS, SHEAR_STIFFNESS)
    rows = []
    # sigma_y, tau_y [Pa], H: perfectly plastic, hardening, and hardening with unequal limits.
    for sigma_y, tau_y, hardening in ((1e7, 4e6, 0.0), (1e7, 4e6, 0.25), (2.5e7, 3e6, 1.5)):
        limit = limits(RADIUS, sigma_y, tau_y)
        for mode in range(4):
            unit = limit[mode] / k[mode]
            state = (0.0, 0.0, 0.0)
            for step, u in enumerate(path_points(unit, k[mode], limit[mode], hardening)):
                state = leg(state, u, k[mode], limit[mode], hardening)
                _, r, kappa = state
                paths = [0.0] * 4
                paths[mode] = kappa
                rows.append([MODES[mode], str(step), fmt(u), fmt(RADIUS), fmt(NORMAL_STIFFNESS),
                             fmt(SHEAR_STIFFNESS), fmt(sigma_y), fmt(tau_y), fmt(hardening),
                             fmt(-r), fmt(u - r / k[mode])] + [fmt(p) for p in paths])
    write("elastic_plastic",
          ["Elastic-plastic bond, per-mode limits F_y0 = sigma_y A, tau_y A, tau_y J/R, "
           "sigma_y I/R, linear isotropic hardening",
           "F_y(kappa) = F_y0 + H k kappa; along each leg elastic until the limit, then the "
           "tangent k H/(1 + H), kappa += beyond/(1 + H)",
           "(the module's docstring). force = -R on the second sphere; plastic_displacement = "
           "u - R/k; <mode>_plastic_path = kappa.",
           "step 0: a bond at rest; each row moves on from the one before."],
          ["mode", "step", "displacement", "radius", "normal_stiffness", "shear_stiffness",
           "yield_stress", "shear_yield_stress", "hardening_ratio", "force",
           "plastic_displacement"] + PATH_FIELDS, rows)


if __name__ == "__main__":
    elastic()
    elastic_plastic()
