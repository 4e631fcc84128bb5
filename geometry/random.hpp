#pragma once
// Seeded random numbers whose values do not depend on the standard library's distributions
// (those are implementation-defined), so a seed gives the same particles on every platform.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

#include <Eigen/Geometry>

namespace shapepress::geometry {

using Rng = std::mt19937_64;

inline double uniform01(Rng& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// Box–Muller.
inline double standard_normal(Rng& rng) {
  const double u = 1.0 - uniform01(rng);  // (0, 1]
  const double v = uniform01(rng);
  return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * std::numbers::pi * v);
}

// Uniformly distributed rotation (Shoemake 1992).
inline Eigen::Matrix3d random_rotation(Rng& rng) {
  const double u1 = uniform01(rng), u2 = uniform01(rng), u3 = uniform01(rng);
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  const double two_pi = 2.0 * std::numbers::pi;
  Eigen::Quaterniond q(b * std::cos(two_pi * u3), a * std::sin(two_pi * u2),
                       a * std::cos(two_pi * u2), b * std::sin(two_pi * u3));
  return q.normalized().toRotationMatrix();
}

// Uniform direction on the unit sphere.
inline Eigen::Vector3d random_direction(Rng& rng) {
  const double z = 2.0 * uniform01(rng) - 1.0;
  const double phi = 2.0 * std::numbers::pi * uniform01(rng);
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

}  // namespace shapepress::geometry
