#!/usr/bin/python3
"""Writes a packed bonded bed (pack's packed.h5) and a compact config as a LAMMPS BPM scene.

    export.py PACKED.h5 CONFIG.toml OUTDIR

OUTDIR/bed.data  atom_style bpm/sphere: one atom per sub-sphere (molecule = its body), the
                 bonds, one bond type per body; box periodic in x and y as the packing's, z
                 from below the floor to above the punch.
OUTDIR/bonds.in  the bond types' bpm/rotational coefficients (bond_coeff lines: the bond style
                 makes a fix, so it comes after read_data, and the data file cannot hold them).
OUTDIR/bed.in    the scene's numbers as LAMMPS variables, for lammps.in.

The mapping (docs/models.md, "Bonded multi-sphere particles"; LAMMPS bond_style bpm/rotational):
shapepress' bond of sub-spheres ri = rj = r (every body here has one sub-sphere radius) is a beam
of radius R = lambda r, A = pi R^2, I = pi R^4 / 4, J = pi R^4 / 2, with kbar_n = Ebar / (ri + rj)
(P&C 2004 §2.2.2) and kbar_s = shear_ratio kbar_n, and
    kn = kbar_n A,  ks = kbar_s A,  kt = kbar_s J,  kb = kbar_n I.
bpm/rotational's Fr = Kr (r - r0), shear force Ks times the displacement of the bond's midpoint,
twist torque Kt psi and bending torque Kb theta (psi, theta: the relative turns of the two ends)
are the same springs at small strain, so Kr = kn, Ks = ks, Kt = kt, Kb = kb.
Dampers: shapepress' c = 2 zeta sqrt(k m*) per mode, m* = m/2 (sqrt(k I*), I* = 0.4 m r^2 / 2,
for the turns). bpm/rotational's normal and sliding dampers are gamma_n and gamma_s times the
relative normal and midpoint sliding velocities, so gamma_n = cn and gamma_s = cs; its twist
torque is gamma_t / 2 times the relative spin about the bond, so gamma_t = 2 ct; its rolling
torque is gamma_r |r| / 2 times the relative spin normal to the bond, so gamma_r = 2 cb / r0,
with r0 the body's mean rest length (the one approximate mapping: a body's rest lengths spread
by up to 14 %, and one bond type per body carries one gamma_r).
Masses: a sub-sphere weighs rho (body volume / sub-spheres' volume) 4/3 pi r^3, as in
packing/bed_state.cpp, so a body weighs rho times its body volume.
Contacts (pair granular hertz/material): LAMMPS takes E* = E / (2 (1 - nu^2)) for a pair of one
material, shapepress' E* of two equal materials, so the particles' E is passed as it is; a
granular wall takes E* = E / (2 (1 - nu^2)) of the one E given, so the walls get
E = 2 (1 - nu^2) E*_wall with E*_wall = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2) of the particle
and tool materials. Bad input exits 2 naming the file, key and value.
"""
import math
import pathlib
import re
import sys
import tomllib

import h5py
import numpy as np

UNITS = {
    "Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9,
    "m": 1.0, "mm": 1e-3, "um": 1e-6,
    "s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9,
    "m/s": 1.0, "mm/s": 1e-3,
    "kg/m^3": 1.0,
}


def fail(message):
    print(f"export.py: {message}", file=sys.stderr)
    sys.exit(2)


def quantity(config_path, key, value):
    """A config number: plain, or a string "<number> <unit>" in the units above (SI out)."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    if isinstance(value, str):
        m = re.fullmatch(r"\s*([-+0-9.eE]+)\s*(\S+)?\s*", value)
        if m:
            try:
                number = float(m.group(1))
            except ValueError:
                number = None
            if number is not None and (m.group(2) is None or m.group(2) in UNITS):
                return number * UNITS.get(m.group(2), 1.0)
    fail(f"{config_path}: {key} = {value!r} is not a number with one of the units "
         f"{', '.join(UNITS)}")


def lookup(config, config_path, *keys):
    node = config
    for k in keys:
        if not isinstance(node, dict) or k not in node:
            fail(f"{config_path}: {'.'.join(keys)} is missing")
        node = node[k]
    return node


def main(argv):
    if len(argv) != 4:
        fail("usage: export.py PACKED.h5 CONFIG.toml OUTDIR")
    packed_path, config_path, outdir = argv[1], argv[2], pathlib.Path(argv[3])
    try:
        config = tomllib.loads(pathlib.Path(config_path).read_text())
    except (OSError, tomllib.TOMLDecodeError) as e:
        fail(f"{config_path}: {e}")
    q = lambda *keys: quantity(config_path, ".".join(keys), lookup(config, config_path, *keys))

    materials = {m.get("name"): m for m in config.get("material", [])}
    particle_name = lookup(config, config_path, "particles", "material")
    wall_name = lookup(config, config_path, "walls", "material")
    for name in (particle_name, wall_name):
        if name not in materials:
            fail(f"{config_path}: no [[material]] named {name!r}")

    def material(name, key):
        value = materials[name].get(key)
        if value is None:
            fail(f"{config_path}: material {name!r} has no {key}")
        return quantity(config_path, f"material {name}.{key}", value)

    e_p, nu_p, rho = (material(particle_name, k)
                      for k in ("youngs_modulus", "poisson_ratio", "density"))
    e_w, nu_w = material(wall_name, "youngs_modulus"), material(wall_name, "poisson_ratio")

    def interaction(a, b):
        for it in config.get("interaction", []):
            if {it.get("first"), it.get("second")} == {a, b}:
                for key, wanted in (("normal_law", "hertz"), ("sliding_friction", 0.0),
                                    ("rolling_friction", 0.0)):
                    if it.get(key, wanted) != wanted:
                        fail(f"{config_path}: interaction {a}-{b}: {key} = {it.get(key)!r}; "
                             f"this bench maps only {key} = {wanted!r}")
                if "restitution" not in it:
                    fail(f"{config_path}: interaction {a}-{b} has no restitution")
                return float(it["restitution"])
        fail(f"{config_path}: no [[interaction]] between {a!r} and {b!r}")

    e_pp = interaction(particle_name, particle_name)
    e_pw = interaction(particle_name, wall_name)

    bond = lookup(config, config_path, "bond")
    modulus = q("bond", "modulus")
    shear_ratio = float(bond.get("shear_ratio", 1.0))
    lam = float(bond.get("radius_multiplier", 1.0))
    zeta = float(bond.get("damping_ratio", 0.0))
    if not modulus > 0 or not shear_ratio > 0 or not lam > 0 or not 0 <= zeta <= 1:
        fail(f"{config_path}: [bond] modulus {modulus}, shear_ratio {shear_ratio}, "
             f"radius_multiplier {lam}, damping_ratio {zeta} out of range")
    dt = q("run", "time_step")
    speed = q("punch", "speed")
    box_x, box_y, bottom = q("box", "x"), q("box", "y"), q("box", "bottom")

    try:
        f = h5py.File(packed_path, "r")
    except OSError as e:
        fail(f"{packed_path}: {e}")
    with f:
        for key in ("particles/position", "particles/radius", "particles/body", "bonds/pairs",
                    "bonds/rest_length", "bodies/template", "bodies/first_particle"):
            if key not in f:
                fail(f"{packed_path}: no /{key} (not a packing of bonded bodies made by pack)")
        x = f["particles/position"][:]
        r = f["particles/radius"][:]
        body = f["particles/body"][:]
        pairs = f["bonds/pairs"][:]
        rest = f["bonds/rest_length"][:]
        template = f["bodies/template"][:]
        ratio = {}
        for t in np.unique(template):
            attrs = f[f"templates/{t}"].attrs
            ratio[int(t)] = float(attrs["body_volume"]) / float(attrs["sphere_volume"])
        pbox_x, pbox_y = float(f.attrs["box_x"]), float(f.attrs["box_y"])
        floor, top = float(f.attrs["floor"]), float(f.attrs["top"])
    if abs(pbox_x - box_x) > 1e-9 * box_x or abs(pbox_y - box_y) > 1e-9 * box_y or \
            abs(floor - bottom) > 1e-12:
        fail(f"{config_path}: box x = {box_x}, y = {box_y}, bottom = {bottom} m is not "
             f"{packed_path}'s ({pbox_x}, {pbox_y}, floor {floor})")
    top = max(top, float(np.max(x[:, 2] + r)))
    n, nb, nbody = len(r), len(pairs), len(template)
    if np.any(body[pairs[:, 0]] != body[pairs[:, 1]]):
        fail(f"{packed_path}: a bond joins two bodies")
    for b in range(nbody):
        rb = r[body == b]
        if rb.size and np.ptp(rb) > 1e-12 * rb[0]:
            fail(f"{packed_path}: body {b} has sub-spheres of several radii; this export maps "
                 f"equal sub-spheres only (one bond type per body)")

    # Per body: the bond coefficients of its sub-sphere radius (module docstring).
    coeffs = []
    for b in range(nbody):
        rb = float(r[body == b][0])
        bonds_b = body[pairs[:, 0]] == b
        r0 = float(np.mean(rest[bonds_b])) if np.any(bonds_b) else 2 * rb
        R = lam * rb
        area, inertia, polar = math.pi * R**2, math.pi * R**4 / 4, math.pi * R**4 / 2
        kbar_n = modulus / (2 * rb)
        kbar_s = shear_ratio * kbar_n
        kn, ks, kt, kb = kbar_n * area, kbar_s * area, kbar_s * polar, kbar_n * inertia
        mass = rho * ratio[int(template[b])] * 4 / 3 * math.pi * rb**3
        m_eff, i_eff = mass / 2, 0.4 * mass * rb**2 / 2
        cn, cs = 2 * zeta * math.sqrt(kn * m_eff), 2 * zeta * math.sqrt(ks * m_eff)
        ct, cb = 2 * zeta * math.sqrt(kt * i_eff), 2 * zeta * math.sqrt(kb * i_eff)
        # Critical forces and torques far beyond any load: these bonds never break, as
        # shapepress' default infinite strengths.
        big = 1e30
        coeffs.append((kn, ks, kt, kb, big, big, big, big, cn, cs, 2 * cb / r0, 2 * ct))

    # Wrapped into the periodic box, with image flags so that the bodies stay whole unwrapped.
    image = np.floor(x[:, :2] / np.array([box_x, box_y])).astype(int)
    wrapped = x.copy()
    wrapped[:, 0] -= image[:, 0] * box_x
    wrapped[:, 1] -= image[:, 1] * box_y
    zlo = bottom - 2 * float(r.max())
    zhi = top + 2 * float(r.max())

    outdir.mkdir(parents=True, exist_ok=True)
    with open(outdir / "bed.data", "w") as out:
        out.write(f"LAMMPS data file: {packed_path} with the bonds of {config_path} "
                  f"(tests/bench/lammps-bpm/export.py)\n\n")
        out.write(f"{n} atoms\n1 atom types\n{nb} bonds\n{nbody} bond types\n\n")
        out.write(f"0 {box_x!r} xlo xhi\n0 {box_y!r} ylo yhi\n{zlo!r} {zhi!r} zlo zhi\n\n")
        out.write("Atoms # bpm/sphere\n\n")
        for i in range(n):
            density = rho * ratio[int(template[body[i]])]
            out.write(f"{i + 1} {body[i] + 1} 1 {2 * r[i]!r} {density!r} {wrapped[i, 0]!r} "
                      f"{wrapped[i, 1]!r} {wrapped[i, 2]!r} {image[i, 0]} {image[i, 1]} 0\n")
        out.write("\nBonds\n\n")
        for k, (i, j) in enumerate(pairs):
            out.write(f"{k + 1} {body[i] + 1} {i + 1} {j + 1}\n")

    with open(outdir / "bonds.in", "w") as out:
        out.write("# Kr Ks Kt Kb Fcr Fcs Tct Tcb gamma_n gamma_s gamma_r gamma_t per body\n")
        for t, c in enumerate(coeffs, 1):
            out.write(f"bond_coeff {t} " + " ".join(f"{v:.17g}" for v in c) + "\n")

    e_star_wall = 1 / ((1 - nu_p**2) / e_p + (1 - nu_w**2) / e_w)
    skin = 0.1 * 2 * float(r.min())  # shapepress' skin: 0.1 of the smallest diameter
    with open(outdir / "bed.in", "w") as out:
        out.write(f"# {packed_path} with {config_path} (export.py)\n")
        for name, value in (("E", e_p), ("NU", nu_p), ("COR", e_pp),
                            ("EWALL", 2 * (1 - nu_p**2) * e_star_wall), ("CORWALL", e_pw),
                            ("DT", dt), ("VPUNCH", speed), ("ZFLOOR", bottom), ("ZPUNCH", top),
                            ("SKIN", skin), ("COMMCUT", 2 * float(rest.max()) + skin)):
            out.write(f"variable {name} equal {value!r}\n")
    print(f"export.py: {n} sub-spheres, {nb} bonds, {nbody} bodies; punch from {top!r} m; "
          f"wall E* {e_star_wall:.6g} Pa")


if __name__ == "__main__":
    main(sys.argv)
