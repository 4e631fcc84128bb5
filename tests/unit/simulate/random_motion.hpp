#pragma once
// Bonded spheres in random motion for the bond tests: one step's inputs of the bond loops drawn at
// random (every sphere moved by up to 1e-3 r, with random velocities, spins and predicted motion),
// so that two loops (the vectorized blocks and the scalar loop, or two bond models) can be compared
// on the same arbitrary step; and one body of 27 near-touching spheres, each moving at random, for
// the bonds' stability runs.
#include <cstddef>
#include <random>
#include <vector>

#include "simulate/state.hpp"

namespace shapepress::simulate::testing {

template <class Random>
void move_at_random(SphereState& s, std::vector<double>& motion, double r, Random& random) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    s.position.x[i] += 1e-3 * r * unit(random), s.position.y[i] += 1e-3 * r * unit(random);
    s.position.z[i] += 1e-3 * r * unit(random);
    s.velocity.x[i] = 1e-3 * unit(random), s.velocity.y[i] = 1e-3 * unit(random);
    s.velocity.z[i] = 1e-3 * unit(random);
    s.angular_velocity.x[i] = unit(random), s.angular_velocity.y[i] = unit(random);
    s.angular_velocity.z[i] = unit(random);
    for (std::size_t c = 0; c < 6; ++c)
      motion[8 * i + c] = 1e-3 * unit(random);
  }
}

// A 3 × 3 × 3 body (body 0) of spheres of radius about r and density rho, 2.05 r apart with a
// jitter of 0.01 r, each moving and spinning at random (1e-3 m/s, 1e-3/r rad/s at the most).
inline SphereState moving_cube_body(double r, double rho) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> jitter(-0.01 * r, 0.01 * r), speed(-1e-3, 1e-3);
  SphereState s;
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 3; ++y)
      for (int z = 0; z < 3; ++z)
        s.add_sphere(2.05 * r * x + jitter(random), 2.05 * r * y + jitter(random),
                     2.05 * r * z + jitter(random), r * (1.0 + 0.1 * jitter(random) / r), rho, 0);
  s.body.assign(s.size(), 0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    s.velocity.x[i] = speed(random), s.velocity.y[i] = speed(random);
    s.velocity.z[i] = speed(random), s.angular_velocity.x[i] = speed(random) / r;
    s.angular_velocity.y[i] = speed(random) / r, s.angular_velocity.z[i] = speed(random) / r;
  }
  return s;
}

}  // namespace shapepress::simulate::testing
