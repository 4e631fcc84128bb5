// What the engine reports about itself: energies, contact counts, divergence checks, and the
// checkpoint a restart continues from.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "common/error.hpp"
#include "simulate/contact_block.hpp"
#include "simulate/engine.hpp"

namespace shapepress::simulate {
namespace {

// Overlap of list pair p (negative when apart), with its periodic image shift.
double pair_overlap(const SphereState& s, const PairList& pairs, std::size_t p) {
  const int i = pairs.first[p], j = pairs.second[p];
  const double dx = s.position.x[j] - s.position.x[i] + pairs.shift(p)[0];
  const double dy = s.position.y[j] - s.position.y[i] + pairs.shift(p)[1];
  const double dz = s.position.z[j] - s.position.z[i];
  return s.radius[i] + s.radius[j] - std::sqrt(dx * dx + dy * dy + dz * dz);
}

}  // namespace

EnergySummary Engine::energy() const {
  const SphereState& s = state_;
  EnergySummary e;
  const auto& g = settings_.gravity;
  const std::vector<std::int32_t>& clump_of = clumps_.clump_of;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!clump_of.empty() && clump_of[i] >= 0) continue;  // the body holds its motion
    const double v2 = s.velocity.x[i] * s.velocity.x[i] + s.velocity.y[i] * s.velocity.y[i] +
                      s.velocity.z[i] * s.velocity.z[i];
    const double w2 = s.angular_velocity.x[i] * s.angular_velocity.x[i] +
                      s.angular_velocity.y[i] * s.angular_velocity.y[i] +
                      s.angular_velocity.z[i] * s.angular_velocity.z[i];
    e.kinetic += 0.5 * s.mass[i] * v2 + 0.5 * w2 / s.inverse_inertia[i];
    e.gravitational -=
        s.mass[i] * (g[0] * s.position.x[i] + g[1] * s.position.y[i] + g[2] * s.position.z[i]);
  }
  e.kinetic += clump_kinetic_energy(clumps_);
  for (std::size_t c = 0; c < clumps_.size(); ++c)
    e.gravitational -= clumps_.mass[c] * (g[0] * clumps_.centre.x[c] + g[1] * clumps_.centre.y[c] +
                                          g[2] * clumps_.centre.z[c]);
  const auto add_contact = [&](const PairConstants& pc, double r_eff, double ri, double rj,
                               double overlap, const ContactHistory& h) {
    e.elastic += normal_elastic_energy(pc, r_eff, ri, rj, overlap, h);
    const double kt = 8.0 * pc.effective_shear_modulus * std::sqrt(r_eff * overlap);
    const double* xi = h.tangential;
    e.elastic += 0.5 * kt * (xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]);
  };
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const int i = pairs_.first[p], j = pairs_.second[p];
    const double overlap = pair_overlap(s, pairs_, p);
    if (overlap <= 0.0) continue;
    if (!pair_bond_.empty() && pair_bond_[p] >= 0 && bonds_.intact[pair_bond_[p]]) continue;
    const PairConstants& pc = materials_.pair(s.material[i], s.material[j]);
    const double bodies_radius = body_contact_radius(pc.body_contact_radius, s.body.data(),
                                                     s.body_radius.data(), s.radius.data(), i, j);
    add_contact(pc,
                bodies_radius > 0.0 ? bodies_radius
                                    : s.radius[i] * s.radius[j] / (s.radius[i] + s.radius[j]),
                s.radius[i], s.radius[j], overlap, history_[p]);
  }
  e.elastic += bond_elastic_energy(bonds_);
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    const PlaneWall& w = walls_[k];
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double overlap = s.radius[i] - w.facing * (s.position.z[i] - w.position);
      if (overlap > 0.0)
        add_contact(materials_.pair(s.material[i], w.material), s.radius[i], s.radius[i], 0.0,
                    overlap, wall_history_[k][i]);
    }
  }
  return e;
}

void Engine::check_divergence() const {
  // Each message names the step size: one too large for the scene is the usual cause.
  const auto diverged = [&](const std::string& what) {
    return ComputationError(fmt::format(
        "{}; time step {:.3g} s (too large for the scene? lower time_step or time_step_fraction)",
        what, settings_.time_step));
  };
  const SphereState& s = state_;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double values[6] = {s.position.x[i], s.position.y[i], s.position.z[i],
                              s.velocity.x[i], s.velocity.y[i], s.velocity.z[i]};
    for (double v : values)
      if (!std::isfinite(v))
        throw diverged(fmt::format(
            "diverged at step {}: sphere {} has a non-finite position or velocity", step_, i));
  }
  const double fraction = settings_.max_overlap_fraction;
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const int i = pairs_.first[p], j = pairs_.second[p];
    const double overlap = pair_overlap(s, pairs_, p);
    // A bonded pair without the contact law (contact_when_bonded false) is a piece of one
    // elastic body: its overlap is the bond's compression, a strain of the particle, not a
    // contact gone too deep (under a plate a protruding sub-sphere is pressed into its bonded
    // neighbour by more than its radius before the others take the load; docs/models.md). Only
    // the linear bond keeps the centres apart, so it has failed when they come within a fifth of
    // the radii sum. With the contact law (true) the pair is checked as any contact below.
    const bool bond_only =
        !pair_bond_.empty() && pair_bond_[p] >= 0 && bonds_.intact[pair_bond_[p]];
    if (bond_only) {
      const double radii_sum = s.radius[i] + s.radius[j];
      if (overlap > bond_only_overlap_limit * radii_sum)
        throw diverged(fmt::format(
            "diverged at step {}: bonded spheres {} and {} overlap by {:.3g} m, {:.3f} of their "
            "radii sum, past the limit {} (their centres nearer than {:.2g} of it): with "
            "contact_when_bonded = false only the linear bond holds them apart (time step too "
            "large, the load too fast, or set contact_when_bonded = true for the contact law "
            "beside the bond)",
            step_, i, j, overlap, overlap / radii_sum, bond_only_overlap_limit,
            1.0 - bond_only_overlap_limit));
      continue;
    }
    if (overlap > fraction * std::min(s.radius[i], s.radius[j]))
      throw diverged(fmt::format(
          "diverged at step {}: spheres {} and {} overlap by {:.3g} m, more than {} of the "
          "smaller radius (time step too large or the load too fast?)",
          step_, i, j, overlap, fraction));
  }
  for (std::size_t k = 0; k < walls_.size(); ++k)
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double overlap =
          s.radius[i] - walls_[k].facing * (s.position.z[i] - walls_[k].position);
      if (overlap > fraction * s.radius[i])
        throw diverged(fmt::format(
            "diverged at step {}: sphere {} overlaps wall {} by {:.3g} m, more than {} of its "
            "radius",
            step_, i, k, overlap, fraction));
    }
  // Energy: a passive system can only lose what it holds plus what walls and gravity put in.
  // A blow-up grows without bound, so "doubled beyond the budget" catches it without tripping on
  // the integrator's small energy error. The floor is 1 µJ per kg of spheres ((1 mm/s)² scale).
  const EnergySummary e = energy();
  const double budget = energy_reference_ + work_in_;
  double total_mass = 0.0;
  for (double m : s.mass)
    total_mass += m;
  for (double m : clumps_.mass)
    total_mass += m;
  const double floor = 1e-6 * total_mass;
  if (e.kinetic + e.elastic > 2.0 * std::max(budget, 0.0) + floor) {
    std::size_t fastest = 0;
    double fastest_v2 = -1.0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double v2 = s.velocity.x[i] * s.velocity.x[i] + s.velocity.y[i] * s.velocity.y[i] +
                        s.velocity.z[i] * s.velocity.z[i];
      if (v2 > fastest_v2) fastest_v2 = v2, fastest = i;
    }
    throw diverged(fmt::format(
        "diverged at step {}: energy {:.3g} J grew beyond the {:.3g} J held and put in; fastest "
        "sphere {} at {:.3g} m/s",
        step_, e.kinetic + e.elastic, budget, fastest, std::sqrt(fastest_v2)));
  }
}

void Engine::rebase_energy() {
  pack_spheres();  // the packed radius, mass and 1/I follow any change made to the state
  const EnergySummary e = energy();
  energy_reference_ = e.kinetic + e.elastic;
  work_in_ = 0.0;
}

std::vector<std::int32_t> Engine::contacts_per_sphere() const {
  std::vector<std::int32_t> count(state_.size(), 0);
  for (std::size_t p = 0; p < pairs_.size(); ++p)
    if (pair_touching_[p]) ++count[pairs_.first[p]], ++count[pairs_.second[p]];
  for (const auto& touching : wall_touching_)
    for (std::size_t i = 0; i < touching.size(); ++i)
      count[i] += touching[i];
  return count;
}

std::vector<double> Engine::particle_stress() const {
  if (!particle_stress_on_) return {};
  const SphereState& s = state_;
  std::vector<double> stress(stress_components * s.size(), 0.0);
  // l ⊗ f = -rc n ⊗ F at either end of a contact (i first: l = rc n, f = -F; i second:
  // l = -rc n, f = F), n from first to second, F on second; the symmetric part is kept.
  const auto add = [](double* sigma, double rc, const double n[3], const double force[3]) {
    sigma[0] -= rc * n[0] * force[0];
    sigma[1] -= 0.5 * rc * (n[0] * force[1] + n[1] * force[0]);
    sigma[2] -= 0.5 * rc * (n[0] * force[2] + n[2] * force[0]);
    sigma[3] -= rc * n[1] * force[1];
    sigma[4] -= 0.5 * rc * (n[1] * force[2] + n[2] * force[1]);
    sigma[5] -= rc * n[2] * force[2];
  };
  const auto add_pair = [&](std::size_t i, std::size_t p, double* sigma) {
    if (!pair_touching_[p]) return;
    const int a = pairs_.first[p], b = pairs_.second[p];
    const double d[3] = {s.position.x[b] - s.position.x[a] + pairs_.shift(p)[0],
                         s.position.y[b] - s.position.y[a] + pairs_.shift(p)[1],
                         s.position.z[b] - s.position.z[a]};
    const double distance = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double n[3] = {d[0] / distance, d[1] / distance, d[2] / distance};
    const double overlap = s.radius[a] + s.radius[b] - distance;
    add(sigma, s.radius[i] - 0.5 * overlap, n, pair_results_[pair_slot_[p]].force);
  };
  for (std::size_t i = 0; i < s.size(); ++i) {
    double* sigma = &stress[stress_components * i];
    // The gather's order: partners below i (i second), then above (i first).
    for (std::int32_t e = pairs_.second_offset[i]; e < pairs_.second_offset[i + 1]; ++e)
      add_pair(i, static_cast<std::size_t>(pairs_.second_pairs[e]), sigma);
    for (std::int32_t p = pairs_.first_offset[i]; p < pairs_.first_offset[i + 1]; ++p)
      add_pair(i, static_cast<std::size_t>(p), sigma);
    // Bonds (as the gather, forces.cpp): at either end l ⊗ f = -share d ⊗ F, d = x_second -
    // x_first (nearest image), F on `second`, share the end's part of d up to the bond centre.
    if (!bonds_.empty())
      for (std::int32_t e = bonds_.gather_offset[i]; e < bonds_.gather_offset[i + 1]; ++e) {
        const std::int32_t entry = bonds_.gather[e];
        const std::size_t b = static_cast<std::size_t>(entry >> 1);
        const std::size_t first = static_cast<std::size_t>(bonds_.first[b]);
        const std::size_t second = static_cast<std::size_t>(bonds_.second[b]);
        double d[3] = {s.position.x[second] - s.position.x[first],
                       s.position.y[second] - s.position.y[first],
                       s.position.z[second] - s.position.z[first]};
        if (box_.periodic_x()) d[0] -= box_.length_x * std::nearbyint(d[0] / box_.length_x);
        if (box_.periodic_y()) d[1] -= box_.length_y * std::nearbyint(d[1] / box_.length_y);
        const Vec3Array& f = bonds_.result.force;
        const double force[3] = {f.x[b], f.y[b], f.z[b]};
        add(sigma, bonds_.constants.arm[static_cast<std::size_t>(entry & 1)][b], d, force);
      }
    for (std::size_t k = 0; k < walls_.size(); ++k) {
      // (a restarted engine has no wall forces until its first step)
      if (wall_force_per_sphere_.size() <= k || wall_force_per_sphere_[k].size() != s.size() ||
          !wall_touching_[k][i])
        continue;
      const double gap = walls_[k].facing * (s.position.z[i] - walls_[k].position);
      const double n[3] = {0.0, 0.0, -static_cast<double>(walls_[k].facing)};
      const double force[3] = {wall_tangential_[k][2 * i], wall_tangential_[k][2 * i + 1],
                               wall_force_per_sphere_[k][i]};
      add(sigma, gap, n, force);
    }
    const double r = s.radius[i];
    const double inverse_volume = 3.0 / (4.0 * std::numbers::pi * r * r * r);
    for (int c = 0; c < stress_components; ++c)
      sigma[c] *= inverse_volume;
  }
  return stress;
}

EngineCheckpoint Engine::checkpoint() const {
  EngineCheckpoint c;
  c.step = step_;
  c.time = time_;
  c.walls = walls_;
  c.build_reference = build_reference_;
  c.build_wall_position = build_wall_position_;
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const double* xi = history_[p].tangential;
    const auto& normal = history_[p].normal;
    if (pair_touching_[p] || xi[0] != 0.0 || xi[1] != 0.0 || xi[2] != 0.0 ||
        std::any_of(normal.begin(), normal.end(), [](double v) { return v != 0.0; })) {
      c.first.push_back(pairs_.first[p]);
      c.second.push_back(pairs_.second[p]);
      c.history.push_back(history_[p]);
    }
  }
  c.wall_history = wall_history_;
  c.wall_force = wall_force_;
  c.particle_pressure = pressure_;
  c.energy_reference = energy_reference_;
  c.work_in = work_in_;
  c.bond_force = bond_force_;
  c.slow_force = slow_force_;
  c.bonds = bonds_;
  c.clumps = clumps_;
  return c;
}

}  // namespace shapepress::simulate
