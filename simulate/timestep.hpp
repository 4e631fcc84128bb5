#pragma once
#include <limits>
#include <optional>
#include <vector>

#include "simulate/bonds.hpp"
#include "simulate/materials.hpp"
#include "simulate/state.hpp"

// The time step: a fraction of the Rayleigh time of the smallest sphere (the usual DEM rule,
// e.g. LIGGGHTS' check/timestep/gran), checked against the Hertz collision time at the fastest
// expected impact speed, which must span many steps.
namespace shapepress::simulate {

// t_R = π r √(ρ/G) / (0.1631 ν + 0.8766), G = E / (2(1+ν)).
double rayleigh_time(double radius, double density, double youngs_modulus, double poisson_ratio);

// Duration of a Hertz impact at relative speed v: t_c = 2.868 (m*² / (R* E*² v))^{1/5}
// (Johnson 1985, §11.4).
double hertz_collision_time(double effective_mass, double effective_radius,
                            double effective_modulus, double speed);

// Steps per Hertz collision below which the contact is not resolved: an InputError.
inline constexpr double minimum_steps_per_collision = 10.0;
// Below this many steps per collision the measured restitution is more than 1 % off the input e
// (validation/simulate Restitution.ErrorShrinksWithTheStepsPerCollision: 2.1 % at 16 steps,
// 0.6 % at 62): select_time_step warns.
inline constexpr double accurate_steps_per_collision = 60.0;

}  // namespace shapepress::simulate

namespace shapepress::simulate {

struct TimeStepChoice {
  double time_step = 0.0;       // s
  double rayleigh_time = 0.0;   // of the smallest sphere
  double collision_time = 0.0;  // shortest Hertz impact at `speed`, sphere–sphere or –wall
  double bond_period = std::numeric_limits<double>::infinity();  // bond_oscillation_period
};

// `fixed` if given, else fraction × the Rayleigh time of the smallest sphere. InputError when
// the step resolves a Hertz collision at `speed` (the fastest expected relative speed) with
// fewer than minimum_steps_per_collision steps.
TimeStepChoice select_time_step(const SphereState& state, const MaterialTable& materials,
                                const std::vector<int>& wall_materials, std::optional<double> fixed,
                                double fraction, double speed);

// With bonds: fraction × min(Rayleigh time, the bonded network's shortest period bound
// T_b = 2π/ω_max). A fixed step above T_b/π (velocity Verlet's stability limit 2/ω_max) is an
// InputError.
TimeStepChoice select_time_step(const SphereState& state, const MaterialTable& materials,
                                const std::vector<int>& wall_materials, std::optional<double> fixed,
                                double fraction, double speed, const BondSet& bonds);

}  // namespace shapepress::simulate
