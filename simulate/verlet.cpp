#include "simulate/verlet.hpp"

#include <algorithm>

#include "simulate/engine.hpp"

namespace shapepress::simulate {

// `omp simd` because GCC does not vectorize the max reduction by itself (a > b ? a : b is not a
// max for NaN and signed zeros; the squared deviations are neither). Built with
// -ffp-contract=off (simulate/CMakeLists.txt): the AVX-512 clone would otherwise fuse a multiply
// and an add into one rounding.
__attribute__((target_clones("avx512f", "avx2", "default"))) double kick_drift_range(
    const VerletArrays& arrays, std::int64_t begin, std::int64_t end, double dt, double alpha,
    const DriftField& drift) {
  double* __restrict vx = arrays.vx;
  double* __restrict vy = arrays.vy;
  double* __restrict vz = arrays.vz;
  double* __restrict wx = arrays.wx;
  double* __restrict wy = arrays.wy;
  double* __restrict wz = arrays.wz;
  double* __restrict px = arrays.px;
  double* __restrict py = arrays.py;
  double* __restrict pz = arrays.pz;
  const double* __restrict fx = arrays.fx;
  const double* __restrict fy = arrays.fy;
  const double* __restrict fz = arrays.fz;
  const double* __restrict tx = arrays.tx;
  const double* __restrict ty = arrays.ty;
  const double* __restrict tz = arrays.tz;
  const double* __restrict inverse_mass = arrays.inverse_mass;
  const double* __restrict rx = arrays.rx;
  const double* __restrict ry = arrays.ry;
  const double* __restrict rz = arrays.rz;
  double* __restrict geometry = arrays.geometry;
  double* __restrict motion = arrays.motion;
  const double half = 0.5 * dt;
  const double drift_offset = drift.offset, drift_strain = drift.strain;
  const double drift_origin = drift.origin;
  const bool damped = alpha > 0.0;
  double largest = 0.0;
#pragma omp simd reduction(max : largest)
  for (std::int64_t i = begin; i < end; ++i) {
    double* gi = geometry + 4 * i;
    double* mi = motion + 8 * i;
    const double im = half * inverse_mass[i], ii = half * mi[7];
    double f0 = fx[i], f1 = fy[i], f2 = fz[i], t0 = tx[i], t1 = ty[i], t2 = tz[i];
    if (damped) {  // by the velocity at the start of the step
      f0 = locally_damped(f0, vx[i], alpha), f1 = locally_damped(f1, vy[i], alpha);
      f2 = locally_damped(f2, vz[i], alpha), t0 = locally_damped(t0, wx[i], alpha);
      t1 = locally_damped(t1, wy[i], alpha), t2 = locally_damped(t2, wz[i], alpha);
    }
    vx[i] += f0 * im;
    vy[i] += f1 * im;
    vz[i] += f2 * im;
    wx[i] += t0 * ii;
    wy[i] += t1 * ii;
    wz[i] += t2 * ii;
    px[i] += dt * vx[i];
    py[i] += dt * vy[i];
    pz[i] += dt * vz[i];
    gi[0] = px[i], gi[1] = py[i], gi[2] = pz[i];
    mi[0] = vx[i] + f0 * im, mi[1] = vy[i] + f1 * im, mi[2] = vz[i] + f2 * im;
    mi[3] = wx[i] + t0 * ii, mi[4] = wy[i] + t1 * ii, mi[5] = wz[i] + t2 * ii;
    const double dx = px[i] - rx[i], dy = py[i] - ry[i];
    const double dz = pz[i] - rz[i] - (drift_offset + drift_strain * (rz[i] - drift_origin));
    largest = std::max(largest, dx * dx + dy * dy + dz * dz);
  }
  return largest;
}

}  // namespace shapepress::simulate
