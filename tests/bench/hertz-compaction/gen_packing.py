#!/usr/bin/env python3
# The packing of the reference scene (README.md beside this script).
"""Deterministic initial packing for the peer DEM benchmark (no numpy needed).

Jittered simple-cubic lattice: NX x NY x NZ spheres, spacing S, each coordinate
perturbed by a uniform jitter in [-J, +J] drawn from splitmix64 (seed SEED), in
the order k (z, outer), j (y), i (x, inner), components x, y, z.
u = (splitmix64() >> 11) * 2**-53  in [0,1);  offset = J * (2u - 1).
Centre of sphere (i,j,k) = ((i+0.5)S + dx, (j+0.5)S + dy, (k+0.5)S + dz).
Writes:
  packing.txt   : one line per sphere "x y z r"   (SI units, metres)
  packing.data  : LAMMPS / LIGGGHTS data file (atom_style sphere / granular)
"""
NX, NY, NZ = 20, 20, 50
D = 1.0e-3          # diameter [m]
RHO = 1541.0        # density [kg/m^3]
S = 1.05e-3         # lattice spacing [m]
J = 0.02e-3         # jitter half-width [m]
SEED = 20240601
LX, LY, H0 = NX * S, NY * S, NZ * S

MASK = (1 << 64) - 1
state = SEED
def splitmix64():
    global state
    state = (state + 0x9E3779B97F4A7C15) & MASK
    z = state
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
    return z ^ (z >> 31)
def jit():
    u = (splitmix64() >> 11) * (1.0 / 9007199254740992.0)
    return J * (2.0 * u - 1.0)

pts = []
for k in range(NZ):
    for j in range(NY):
        for i in range(NX):
            dx, dy, dz = jit(), jit(), jit()
            pts.append(((i + 0.5) * S + dx, (j + 0.5) * S + dy, (k + 0.5) * S + dz))

with open("packing.txt", "w") as f:
    for p in pts:
        f.write("%.12e %.12e %.12e %.12e\n" % (p[0], p[1], p[2], D / 2))
with open("packing.data", "w") as f:
    f.write("peer DEM benchmark: %d spheres, jittered SC lattice, seed %d\n\n" % (len(pts), SEED))
    f.write("%d atoms\n1 atom types\n\n" % len(pts))
    f.write("0.0 %.12e xlo xhi\n0.0 %.12e ylo yhi\n0.0 %.12e zlo zhi\n\nAtoms\n\n" % (LX, LY, H0 + D))  # box 1 d above the punch
    for n, p in enumerate(pts):
        f.write("%d 1 %.6e %.6e %.12e %.12e %.12e\n" % (n + 1, D, RHO, p[0], p[1], p[2]))
zmin = min(p[2] for p in pts); zmax = max(p[2] for p in pts)
print("N=%d LX=%.6g LY=%.6g H0=%.6g zmin-r=%.4g top gap=%.4g first=%s" %
      (len(pts), LX, LY, H0, zmin - D / 2, H0 - zmax - D / 2, pts[0]))
