#include "simulate/timestep.hpp"

#include <cmath>
#include <numbers>

namespace shapepress::simulate {

double rayleigh_time(double radius, double density, double youngs_modulus, double poisson_ratio) {
  const double shear_modulus = youngs_modulus / (2.0 * (1.0 + poisson_ratio));
  return std::numbers::pi * radius * std::sqrt(density / shear_modulus) /
         (0.1631 * poisson_ratio + 0.8766);
}

double hertz_collision_time(double effective_mass, double effective_radius,
                            double effective_modulus, double speed) {
  return 2.868 * std::pow(effective_mass * effective_mass /
                              (effective_radius * effective_modulus * effective_modulus * speed),
                          0.2);
}

}  // namespace shapepress::simulate
