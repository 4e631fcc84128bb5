#pragma once
// One step's inputs of the bond loops drawn at random: every sphere moved by up to 1e-3 r, with
// random velocities, spins and predicted motion, so that two loops (the vectorized blocks and the
// scalar loop, or two bond models) can be compared on the same arbitrary step.
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

}  // namespace shapepress::simulate::testing
