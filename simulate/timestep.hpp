#pragma once
#include <limits>
#include <optional>
#include <vector>

#include "simulate/bonds.hpp"
#include "simulate/clumps.hpp"
#include "simulate/materials.hpp"
#include "simulate/state.hpp"

// The time step: a fraction of the Rayleigh time of the smallest sphere (the usual DEM rule,
// e.g. LIGGGHTS' check/timestep/gran), taken with the modulus of the stiffest contact law in use
// (each normal law's stiffness_ratio, normal_laws.hpp: 1 for Hertz, k2/k1 = 1/λp and more for the
// multi-contact law of Giannis 2023 Eq. 6), checked against the Hertz collision time at the
// fastest expected impact speed, which must span many steps.
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
  double time_step = 0.0;        // s
  double rayleigh_time = 0.0;    // of the smallest sphere
  double collision_time = 0.0;   // shortest Hertz impact at `speed`, sphere–sphere or –wall
  double collision_speed = 0.0;  // m/s, the speed it was taken at
  double bond_period = std::numeric_limits<double>::infinity();  // bond_oscillation_period
  // The longest stable step through the bonds (bond_stability_step): a step, or a bond sub-step,
  // above it is refused.
  double bond_stability_step = std::numeric_limits<double>::infinity();
  double clump_period = std::numeric_limits<double>::infinity();  // clump_contact_period
  // Bond sub-steps per step (EngineSettings::bond_substeps): time_step / bond_substeps is the
  // bonds' step.
  int bond_substeps = 1;
};

// Bound on the shortest period of a rigid clump rocking on its contacts: a clump's mass and
// inertia sit behind all its sub-spheres' contacts at once, which the Rayleigh time of one
// sub-sphere does not see (a 41-sphere clump pressed 40 % between plates blows up at 0.2 t_R).
// ω² is at most the trace of the mass-normalised stiffness of the contacts,
//   ω² ≤ Σ_i (kn,i + 2 kt,i) (1/M + |r_i|²/I_min),  kn = 2E*√(r δ), kt = 8G*√(r δ)
// (the Hertz and Mindlin tangent stiffnesses at overlap δ_i = overlap[i], against the partner
// material of the stiffest pair), and the contact dampers' rate is at most
//   γ ≤ Σ_i c_i (1/M + |r_i|²/I_min),  c_i = damping_factor (√(kn m) + √(kt m)), m = M/n
// (clump_damping_mass). Returns min(2π/ω_max, π/γ_max) [s] (the dampers held below π/γ as for
// bonds), +inf without clumps or contacts.
double clump_contact_period(const ClumpSet& clumps, const SphereState& state,
                            const MaterialTable& materials, const std::vector<int>& partners,
                            const std::vector<double>& overlap);
// The overlap the generic bound assumes for every sub-sphere (fraction of its radius, one
// contact each) where the scene does not say more (compact).
inline constexpr double assumed_clump_overlap = 0.1;

// `fixed` if given, else fraction × the Rayleigh time of the smallest sphere, against the stiffest
// contact it can have (its materials' E, a stated E*, or a law stiffer than Hertz). InputError when
// the step resolves a Hertz collision at `speed` (the fastest expected relative speed) with
// fewer than minimum_steps_per_collision steps.
TimeStepChoice select_time_step(const SphereState& state, const MaterialTable& materials,
                                const std::vector<int>& wall_materials, std::optional<double> fixed,
                                double fraction, double speed);

// With bonds: fraction × min(Rayleigh time, the bonded network's shortest period bound
// T_b = 2π/ω_G, ω_G Gershgorin's bound on the top frequency). A step above the bonds' stability
// limit (bond_stability_step: 0.9 × velocity Verlet's 2/ω_max with ω_max estimated by Lanczos,
// between T_b/π and about twice it) is an InputError: a fixed one naming time_step, one the
// bonds set naming time_step_fraction with the largest fraction this bed allows. `box`: the
// periodic box, for the bonds' directions across it.
TimeStepChoice select_time_step(const SphereState& state, const MaterialTable& materials,
                                const std::vector<int>& wall_materials, std::optional<double> fixed,
                                double fraction, double speed, const BondSet& bonds,
                                const Box& box = {});

// `bond_fraction`, when given, replaces `fraction` for the bonds' bound: the bonds' step is
// bond_fraction × T_b, below the stability limit. The bonds' fastest modes (a sub-sphere turning
// against its bonds) carry little of a pressed bed's energy, so their step needs stability
// rather than the contacts' resolution (docs/measurements.md, "A longer step for the bonds").
// With bond sub-steps (`bond_substeps` n > 1, EngineSettings::bond_substeps): the bonds take
// fraction × T_b per sub-step and the step is fraction × the contacts' bound (Rayleigh time,
// clumps), at most n sub-steps long; n = 0 takes as many sub-steps as that bound needs
// (TimeStepChoice::bond_substeps says how many). A fixed step is split into n.
// With rigid clumps too: a clump's sub-sphere has no own mass (clumps.hpp), so its Hertz
// collision time is that of a sphere of its radius carrying the clump's mass (the mass its
// contacts decelerate; the contact damping uses the same). The step is fraction ×
// min(Rayleigh time of the smallest sub-sphere, bond period, clump_contact_period with every
// sub-sphere touching the stiffest partner at assumed_clump_overlap of its radius).
TimeStepChoice select_time_step(const SphereState& state, const MaterialTable& materials,
                                const std::vector<int>& wall_materials, std::optional<double> fixed,
                                double fraction, double speed, const BondSet& bonds,
                                const ClumpSet& clumps, int bond_substeps = 1,
                                std::optional<double> bond_fraction = std::nullopt,
                                const Box& box = {});

}  // namespace shapepress::simulate
