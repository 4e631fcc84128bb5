#include "simulate/timestep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "simulate/contact_law.hpp"

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

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common/error.hpp"

namespace shapepress::simulate {

namespace {

// The Young's modulus a sphere of material `m` and radius `radius` stands against in its
// stiffest contact: its own, or, where a pair is stiffer than the Hertz contact its materials
// give, the modulus of a sphere whose Hertz contact would be as stiff against its partner:
// (1 − ν²) E*s against a wall (a rigid plane), 2 (1 − ν²) E*s against an equal sphere, with
// E*s = E* × the pair law's stiffness ratio (its stiffest branch over Hertz's tangent
// 2 E* √(R* δ); normal_laws.hpp) and E* the pair's, stated (Interaction::effective_modulus) or
// from the materials. Hertz pairs have ratio 1, so a Hertz scene's step is the Rayleigh time of
// its materials (or of a stated E*), to the bit. The ratio is taken at the smallest R* the sphere
// can meet: `smallest_radius` for a sphere partner, its own radius for a wall. A sub-sphere of a
// body (`body_radius` > its radius) whose pair takes the bodies' R* (contact_radius = "body")
// meets another body with that R*, at most R*_b = Rb Rb_max / (Rb + Rb_max) against the largest
// body: its Hertz tangent 2 E* √(R*_b δ) is √(R*_b / R*) times the sub-spheres' at one overlap.
double stiffest_contact_modulus(const MaterialTable& materials, int m, double radius,
                                double smallest_radius, double body_radius,
                                double largest_body_radius,
                                const std::vector<int>& wall_materials) {
  const Material& own = materials.material(m);
  double modulus = own.youngs_modulus;
  const double plane_strain = 1.0 - own.poisson_ratio * own.poisson_ratio;
  for (int k = 0; k < materials.count(); ++k) {
    if (!materials.has_pair(m, k)) continue;
    const bool wall =
        std::find(wall_materials.begin(), wall_materials.end(), k) != wall_materials.end();
    const PairConstants& pair = materials.pair(m, k);
    const double effective_radius =
        wall ? radius : radius * smallest_radius / (radius + smallest_radius);
    const double from_materials = materials_effective_modulus(own, materials.material(k));
    double stated = pair.effective_modulus * normal_stiffness_ratio(pair, effective_radius);
    if (!wall && pair.body_contact_radius && body_radius > radius)
      stated *= std::sqrt(body_radius * largest_body_radius / (body_radius + largest_body_radius) /
                          effective_radius);
    if (stated <= from_materials * (1.0 + 1e-12)) continue;
    modulus = std::max(modulus, (wall ? 1.0 : 2.0) * plane_strain * stated);
  }
  return modulus;
}

// `mass`: the mass each sphere's contacts move (its own, or its clump's).
TimeStepChoice select_with_masses(const SphereState& state, const MaterialTable& materials,
                                  const std::vector<int>& wall_materials,
                                  std::optional<double> fixed, double fraction, double speed,
                                  std::span<const double> mass) {
  TimeStepChoice choice;
  if (state.size() == 0) throw InputError("no spheres to simulate");
  std::size_t smallest = 0;
  choice.rayleigh_time = std::numeric_limits<double>::infinity();
  const double smallest_radius = *std::min_element(state.radius.begin(), state.radius.end());
  const double largest_body_radius =
      *std::max_element(state.body_radius.begin(), state.body_radius.end());
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Material& m = materials.material(state.material[i]);
    const double modulus =
        stiffest_contact_modulus(materials, state.material[i], state.radius[i], smallest_radius,
                                 state.body_radius[i], largest_body_radius, wall_materials);
    const double t = rayleigh_time(state.radius[i], m.density, modulus, m.poisson_ratio);
    if (t < choice.rayleigh_time) choice.rayleigh_time = t, smallest = i;
  }
  if (!(fraction > 0.0 && fraction <= 1.0))
    throw InputError("time_step_fraction must be in (0, 1]");
  choice.time_step = fixed ? *fixed : fraction * choice.rayleigh_time;
  if (!(choice.time_step > 0.0)) throw InputError("time_step must be > 0");
  const double r = state.radius[smallest], m = mass[smallest];
  const int mat = state.material[smallest];
  const double v = std::max(speed, 1e-3);  // a resting bed still sees mm/s impacts
  choice.collision_time =
      hertz_collision_time(0.5 * m, 0.5 * r, materials.pair(mat, mat).effective_modulus, v);
  for (int w : wall_materials)
    choice.collision_time =
        std::min(choice.collision_time,
                 hertz_collision_time(m, r, materials.pair(mat, w).effective_modulus, v));
  choice.collision_speed = v;
  return choice;
}

// After every bound has shortened the step: the Hertz collision at the fastest expected speed
// must still span enough steps.
TimeStepChoice checked(TimeStepChoice choice) {
  if (choice.time_step * minimum_steps_per_collision > choice.collision_time)
    throw InputError(fmt::format(
        "time step {:.3g} s resolves a Hertz collision at {:.3g} m/s ({:.3g} s) with fewer than "
        "{} steps: lower time_step or time_step_fraction",
        choice.time_step, choice.collision_speed, choice.collision_time,
        minimum_steps_per_collision));
  if (choice.time_step * accurate_steps_per_collision > choice.collision_time)
    spdlog::warn(
        "time step {:.3g} s resolves a Hertz collision at {:.3g} m/s with {:.0f} steps: the "
        "restitution may be off the input by more than 1 % (it is within 1 % from {} steps)",
        choice.time_step, choice.collision_speed, choice.collision_time / choice.time_step,
        accurate_steps_per_collision);
  return choice;
}

}  // namespace

TimeStepChoice select_time_step(const SphereState& state, const MaterialTable& materials,
                                const std::vector<int>& wall_materials, std::optional<double> fixed,
                                double fraction, double speed) {
  return checked(
      select_with_masses(state, materials, wall_materials, fixed, fraction, speed, state.mass));
}

namespace {

// fraction × the bonded network's period bound when that is shorter; a step above the bonds'
// stability limit is an InputError.
// The bounds take the bonds' elastic springs whatever the bond model: a yielding mode's tangent
// past yield is k H/(1 + H) < k and it unloads along k (bond_models.hpp, return_to_yield), so no
// model stiffens a bond beyond its elastic spring and the elastic bound holds for every model
// (tests/unit/simulate/bond_plasticity_test.cpp runs a plastic bed at the elastic step).
TimeStepChoice with_bond_period(TimeStepChoice choice, std::optional<double> fixed, double fraction,
                                const BondSet& bonds, const SphereState& state, int bond_substeps,
                                std::optional<double> bond_fraction, const Box& box) {
  if (bond_substeps < 0)
    throw InputError(fmt::format("bond_substeps must be >= 0, got {}", bond_substeps));
  choice.bond_period = bond_oscillation_period(bonds, state);
  if (!std::isfinite(choice.bond_period)) return choice;
  // Gershgorin's period bound is what a fraction takes (a step that does not move with the
  // estimate's last digits); the estimated top frequency is what stability is judged by.
  choice.bond_stability_step = bond_stability_step(bonds, state, box);
  const double limit = choice.bond_stability_step;
  const double bonds_fraction = bond_fraction.value_or(fraction);
  if (bond_substeps != 1) {
    const double bond_step = bonds_fraction * choice.bond_period;
    const double contacts = fixed ? *fixed : choice.time_step;
    const int n =
        bond_substeps > 0
            ? bond_substeps
            : std::max(1, static_cast<int>(std::ceil(contacts / bond_step * (1.0 - 1e-12))));
    choice.bond_substeps = n;
    if (!fixed) choice.time_step = std::min(contacts, n * bond_step);
    if (choice.time_step / n > limit)
      throw InputError(fmt::format(
          "a bond sub-step of {:.3g} s ({} per step of {:.3g} s) is above the stability limit "
          "{:.3g} s of the stiffest bonds (period bound {:.3g} s): raise bond_substeps or lower "
          "time_step",
          choice.time_step / n, n, choice.time_step, limit, choice.bond_period));
    return choice;
  }
  if (fixed) {
    if (*fixed > limit)
      throw InputError(fmt::format(
          "time_step {:.3g} s is above the stability limit {:.3g} s of the stiffest bonds "
          "(period bound {:.3g} s): lower time_step or the bond stiffness",
          *fixed, limit, choice.bond_period));
    return choice;
  }
  choice.time_step = std::min(choice.time_step, bonds_fraction * choice.bond_period);
  // A shorter Rayleigh step keeps any fraction stable; where the bonds set the step, a fraction
  // beyond what the bed's top frequency allows is refused.
  if (choice.time_step > limit)
    throw InputError(fmt::format(
        "{} {:.3g} is above {:.3g}, the stability limit of this bed's bonds (step {:.3g} s "
        "against {:.3g} s, {:.2g} x 2/omega_max; period bound {:.3g} s): lower it",
        bond_fraction ? "bond_time_step_fraction" : "time_step_fraction", bonds_fraction,
        limit / choice.bond_period, choice.time_step, limit, bond_stability_margin,
        choice.bond_period));
  return choice;
}

}  // namespace

TimeStepChoice select_time_step(const SphereState& state, const MaterialTable& materials,
                                const std::vector<int>& wall_materials, std::optional<double> fixed,
                                double fraction, double speed, const BondSet& bonds,
                                const Box& box) {
  return checked(with_bond_period(
      select_with_masses(state, materials, wall_materials, fixed, fraction, speed, state.mass),
      fixed, fraction, bonds, state, 1, std::nullopt, box));
}

TimeStepChoice select_time_step(const SphereState& state, const MaterialTable& materials,
                                const std::vector<int>& wall_materials, std::optional<double> fixed,
                                double fraction, double speed, const BondSet& bonds,
                                const ClumpSet& clumps, int bond_substeps,
                                std::optional<double> bond_fraction, const Box& box) {
  std::vector<double> mass(state.mass.begin(), state.mass.end());
  std::vector<double> overlap(state.size(), 0.0);
  std::vector<int> partners = wall_materials;
  for (std::size_t c = 0; c < clumps.size(); ++c)
    for (std::int32_t i = clumps.first[c]; i < clumps.last[c]; ++i) {
      mass[static_cast<std::size_t>(i)] = clumps.mass[c];
      overlap[static_cast<std::size_t>(i)] = assumed_clump_overlap * state.radius[i];
      partners.push_back(state.material[i]);
    }
  // One entry per material: clump_contact_period visits every partner for every sub-sphere.
  std::sort(partners.begin(), partners.end());
  partners.erase(std::unique(partners.begin(), partners.end()), partners.end());
  TimeStepChoice choice = with_bond_period(
      select_with_masses(state, materials, wall_materials, fixed, fraction, speed, mass), fixed,
      fraction, bonds, state, bond_substeps, bond_fraction, box);
  choice.clump_period = clump_contact_period(clumps, state, materials, partners, overlap);
  if (choice.bond_substeps > 1 && !clumps.empty())
    throw InputError("bond_substeps > 1 does not take rigid clumps");
  if (!fixed && std::isfinite(choice.clump_period))
    choice.time_step = std::min(choice.time_step, fraction * choice.clump_period);
  return checked(choice);
}

double clump_contact_period(const ClumpSet& clumps, const SphereState& state,
                            const MaterialTable& materials, const std::vector<int>& partners,
                            const std::vector<double>& overlap) {
  double fastest = 0.0;  // largest ω² bound over the clumps
  double damping = 0.0;  // largest damping-rate bound
  for (std::size_t c = 0; c < clumps.size(); ++c) {
    const Vector3& inertia = clumps.rotation[c].principal_inertia;
    const double inverse_mass = 1.0 / clumps.mass[c];
    const double inverse_inertia = 1.0 / std::min({inertia[0], inertia[1], inertia[2]});
    const double m = clump_damping_mass(clumps, c);
    double sum = 0.0, rate = 0.0;
    for (std::int32_t i = clumps.first[c]; i < clumps.last[c]; ++i) {
      const double delta = overlap[static_cast<std::size_t>(i)];
      if (!(delta > 0.0)) continue;
      // The stiffest partner: 2E* + 2·8G* per √(r δ), and its dampers.
      double stiffest = 0.0, damper = 0.0;
      const double root = std::sqrt(state.radius[i] * delta);
      for (int partner : partners)
        if (materials.has_pair(state.material[i], partner)) {
          const PairConstants& pc = materials.pair(state.material[i], partner);
          // kn = 2E*√(rδ) × the law's stiffness ratio (1 for Hertz), at R* = r/2 (an equal
          // partner; the ratio grows as R* shrinks only for a stated multi-contact k1).
          stiffest = std::max(stiffest, 2.0 * pc.effective_modulus *
                                                normal_stiffness_ratio(pc, 0.5 * state.radius[i]) +
                                            16.0 * pc.effective_shear_modulus);
          damper =
              std::max(damper, pc.damping_factor *
                                   (std::sqrt(2.0 * pc.effective_modulus * root * m) +
                                    2.0 * std::sqrt(8.0 * pc.effective_shear_modulus * root * m)));
        }
      const double arm2 = std::pow(state.position.x[i] - clumps.centre.x[c], 2) +
                          std::pow(state.position.y[i] - clumps.centre.y[c], 2) +
                          std::pow(state.position.z[i] - clumps.centre.z[c], 2);
      const double reach = inverse_mass + arm2 * inverse_inertia;
      sum += stiffest * root * reach;
      rate += damper * reach;
    }
    fastest = std::max(fastest, sum);
    damping = std::max(damping, rate);
  }
  double period = std::numeric_limits<double>::infinity();
  if (fastest > 0.0) period = 2.0 * std::numbers::pi / std::sqrt(fastest);
  if (damping > 0.0) period = std::min(period, std::numbers::pi / damping);
  return period;
}

}  // namespace shapepress::simulate
