#pragma once
// The first half kick and the drift of velocity Verlet over a range of spheres, as one loop the
// compiler vectorizes (Engine::step calls it on each thread's share). Clones for AVX-512 and AVX2
// are picked at load time; every lane performs the scalar loop's IEEE operations in its order,
// so each clone gives the same bits.
#include <cstdint>

namespace shapepress::simulate {

// The arrays of the loop, none aliasing another: the state's (velocity, spin and position in and
// out; force, torque and 1/m in), the positions of the last list build, and the packed copies
// of the pair loop (Engine::pack_spheres: per sphere x, y, z, r and predicted v, ω, m, 1/I).
struct VerletArrays {
  double *vx, *vy, *vz, *wx, *wy, *wz, *px, *py, *pz;
  const double *fx, *fy, *fz, *tx, *ty, *tz, *inverse_mass;
  const double *rx, *ry, *rz;  // positions at the last list build
  double* geometry;
  double* motion;
};

// The uniform strain in z between the walls since the last build, z -> offset + strain (z -
// origin): displacements are measured against it (Engine::list_affine_drift).
struct DriftField {
  double offset = 0.0, strain = 0.0, origin = 0.0;
};

// Spheres [begin, end): v += dt/2 F/m (and ω += dt/2 τ/I) with Cundall's damping α when α > 0
// (locally_damped, by the velocity at the start of the step), x += dt v, the packed copies of x
// and of the velocities predicted for the end of the step, v + dt/2 F/m. Returns the largest
// squared deviation from the drift field since the last build (0 for an empty range).
double kick_drift_range(const VerletArrays& arrays, std::int64_t begin, std::int64_t end, double dt,
                        double alpha, const DriftField& drift);

}  // namespace shapepress::simulate
