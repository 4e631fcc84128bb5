#pragma once
// Small scenes shared by the engine's validation tests.
#include <cstdlib>
#include <string>

#include "simulate/engine.hpp"
#include "simulate/timestep.hpp"

namespace shapepress::simulate::testing {

// SHAPEPRESS_FULL_VALIDATION=1 runs the sizes the issue names; CI runs reduced ones.
inline bool full_validation() {
  const char* value = std::getenv("SHAPEPRESS_FULL_VALIDATION");
  return value != nullptr && std::string(value) == "1";
}

inline MaterialTable one_material(double e, double mu_s, double mu_r = 0.0, double E = 1e8,
                                  double nu = 0.3, double rho = 1541.0) {
  return MaterialTable({{"m", E, nu, rho}}, {{"m", "m", e, mu_s, mu_r}});
}

// 0.2 × Rayleigh time of a sphere of material 0 (the engine's default rule).
inline double default_time_step(const MaterialTable& table, double radius) {
  const Material& m = table.material(0);
  return 0.2 * rayleigh_time(radius, m.density, m.youngs_modulus, m.poisson_ratio);
}

}  // namespace shapepress::simulate::testing
