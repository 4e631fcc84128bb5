#pragma once
// Normal sub-model: the multi-contact adhesive elastic–plastic law of Giannis et al. 2023, Eq. 6
// (EEPA-type branches with exponent 3/2, Thakur et al. 2014, plus the multi-contact term
// β ν A_ij P_ij). Equations and the choices the paper leaves open: models.md "Multi-contact
// adhesive elastic–plastic law".
//
// With x = δ^{3/2} and xp = δp^{3/2} the three branches of Eq. 6 are one clamp,
//   f_hys = F0 + max(min(k1 x, k2 (x - xp)), -kc x),
// and the plastic overlap follows the largest overlap so the loading and unloading branches
// meet at δmax: xp = (1 - k1/k2) xmax = (1 - λp) xmax. Beyond δmax, k2(x - xp) ≥ k1 x holds
// exactly when x ≥ xmax, so raising xp whenever (1 - λp) x exceeds it selects the loading branch
// and updates the history in one comparison. The history keeps k1 xp (N), the "plastic force"
// (1 - λp) × the largest loading force: k1 is fixed for a contact (its R* does not change), and
// keeping the product spares the hot loop a division (docs/measurements.md, "Benchmarks").
// √δ is taken whether or not a branch needs it: a choice between it and 0 on the pair's constants
// would keep the contact blocks (contact_block.hpp) from vectorizing the law.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/config.hpp"
#include "common/option_doc.hpp"
#include "simulate/law_types.hpp"

namespace shapepress::simulate {

// What a user states for the multi-contact law (models.md "Multi-contact adhesive elastic–plastic
// law"). The defaults make it Hertz–Mindlin: λp = 1, kc = 0, F0 = 0, β = 0.
struct MulticontactParameters {
  std::optional<double> loading_stiffness =
      std::nullopt;                 // k1, N/m^1.5; absent: 4/3 E*_L √R* per contact
  double plasticity_ratio = 1.0;    // λp = k1/k2 in (0, 1]; 1: elastic
  double adhesion_stiffness = 0.0;  // kc ≥ 0, N/m^1.5
  double pull_off_force = 0.0;      // F0 ≤ 0, N (constant attraction while touching)
  double prefactor = 0.0;           // β ≥ 0 of the term β ν A_ij P_ij
};

struct MulticontactNormal {
  double force;           // F0 + f_hys + β ν A P - γ vn, > 0 repulsive
  double adhesive_floor;  // F0 - kc x: the most attractive hysteretic force at this overlap
};

struct MulticontactLaw {
  MulticontactParameters parameters;

  static constexpr std::string_view name = "multicontact";
  // The β ν A_ij P_ij term reads the particles' Love–Weber pressure.
  static constexpr bool needs_pair_pressure = true;
  static constexpr std::array<HistoryField, 1> history_fields{
      {{"plastic_force", "N", "k1 δp^{3/2} = (1 - λp) k1 δmax^{3/2}: the plastic overlap"}}};

  struct Constants {
    double loading_stiffness = 0.0;  // k1, N/m^1.5; 0: 4/3 E*_L √R* per contact
    // Without a stated k1: k1 = 4/3 E*_L √R* = loading_coefficient E* √R*, with
    // loading_factor = E*_L / E* (1 when no material states a loading_modulus: Hertz's k1),
    // loading_coefficient = 4/3 × it, and the damping on that loading stiffness
    // loading_damping_factor = √(loading_factor) times Hertz's.
    double loading_factor = 1.0;
    double loading_coefficient = 4.0 / 3.0;
    double loading_damping_factor = 1.0;
    double unloading_factor = 1.0;     // k2/k1 = 1/λp
    double plastic_fraction = 0.0;     // 1 - λp: δp^{3/2} = (1 - k1/k2) δmax^{3/2}
    double adhesion_stiffness = 0.0;   // kc
    double pull_off_force = 0.0;       // F0 ≤ 0
    double multicontact_factor = 0.0;  // 3 β ν π: β ν A_ij P_ij, A_ij = π R* δ, P_ij = 3 p̄
  };

  static std::vector<OptionDoc> options();
  static MulticontactLaw read(const ConfigTable& interaction);
  void write_toml(std::string& out) const;
  void check(const std::string& where) const;
  Constants constants(const Material& a, const Material& b) const;
  static std::string describe(const ElasticPair& p, const Constants& k);

  // Largest tangent stiffness over the Hertz tangent 2 E* √(R* δ) of the pair (timestep.cpp):
  // the loading branch k1 δ^{3/2} has 3/2 k1 √δ, s1 = k1 / (4/3 E* √R*) times Hertz's (E*_L / E*
  // with k1 from the loading modulus, 1 from E*); the unloading branch k2 (δ^{3/2} - δp^{3/2}) has
  // k2/k1 = 1/λp times that (Eq. 6, Giannis 2023); the adhesive branch -kc δ^{3/2} softens and adds
  // nothing. The term β ν π R* δ 3p̄ (Eq. 6, P_ij the mean trace 3p̄) has stiffness 3 β ν π R* p̄ at
  // the step's p̄; with the Love–Weber pressure p̄ = Σ rc Fn / (4π r³) of a sphere holding 12
  // contacts (a dense bed's most) on the loading branch at δ ≤ r/2 with R* ≤ r, p̄ ≤ 4 s1 E* √R*
  // δ^{3/2} / (π r²) and the term's stiffness is at most 3 β ν s1 times Hertz's (the factor holds 3
  // β ν π).
  static double stiffness_ratio(const ElasticPair& p, const Constants& k, double effective_radius) {
    const double loading =
        k.loading_stiffness > 0.0
            ? k.loading_stiffness / (4.0 / 3.0 * p.effective_modulus * std::sqrt(effective_radius))
            : k.loading_factor;
    return loading * k.unloading_factor + loading * k.multicontact_factor / std::numbers::pi;
  }

  // `plastic_force` is the contact's k1 δp^{3/2}, updated here. `pair_pressure` is the pair's
  // mean pressure p̄ = ½ (p_i + p_j) from the previous step's Love–Weber stresses (against a
  // wall the sphere's own p_i), P_ij = 3 p̄ its mean trace; tension (p̄ < 0) is taken as 0: the
  // term models confinement, it does not pull. `sqrt_r_overlap` =
  // √(R* δ) and `damping_root` = √(√(R* δ) m*), already computed by the caller.
  [[gnu::always_inline]] static MulticontactNormal normal(
      const ElasticPair& p, const Constants& k, double overlap, double effective_radius,
      double effective_mass, double sqrt_r_overlap, double damping_root, double vn,
      double pair_pressure, double& plastic_force) {
    // k1 given, or 4/3 E*_L √R* (Hertz's with the loading modulus): then the loading force and its
    // damping stiffness are written like the Hertz branch, and without a loading modulus
    // λp = 1, kc = F0 = β = 0 gives Hertz's bits (the coefficient is 4/3, the factor 1).
    const bool given = k.loading_stiffness > 0.0;
    const double sqrt_overlap = std::sqrt(overlap);
    const double x = overlap * sqrt_overlap;  // δ^{3/2}
    const double loading =
        given ? k.loading_stiffness * x
              : k.loading_coefficient * p.effective_modulus * sqrt_r_overlap * overlap;
    const double candidate = k.plastic_fraction * loading;
    if (candidate > plastic_force) plastic_force = candidate;  // virgin loading
    const double unloading = k.unloading_factor * (loading - plastic_force);
    const double adhesive = -k.adhesion_stiffness * x;
    const double hysteretic = std::max(std::min(loading, unloading), adhesive);
    // Multi-contact term, A_ij = π a² with a² = R* δ, P_ij = 3 p̄; the factor holds 3 β ν π.
    const double confinement =
        k.multicontact_factor * effective_radius * overlap * std::max(pair_pressure, 0.0);
    // Damping on the loading stiffness S = dF/dδ = 3/2 k1 √δ (= 2 E* √(R* δ) for Hertz's k1), so
    // the restitution of a first impact is the input e; unloading branches are not re-damped.
    // With Hertz's k1 this is contact_law.hpp's γn = damping_factor √(2 E* √(R*δ) m*).
    const double gamma_n = given ? p.damping_factor * std::sqrt(1.5 * k.loading_stiffness *
                                                                sqrt_overlap * effective_mass)
                                 : k.loading_damping_factor * p.normal_damping_scale * damping_root;
    return {k.pull_off_force + hysteretic + confinement - gamma_n * vn,
            k.pull_off_force + adhesive};
  }

  // The friction limit is measured from the adhesive floor, Fn - (F0 - kc δ^{3/2}), so an
  // adhesive contact still holds friction (as EEPA does).
  [[gnu::always_inline]] static NormalForce force(const ElasticPair& p, const Constants& k,
                                                  const ContactKinematics& c, double sqrt_r_overlap,
                                                  double damping_root, double vn, double* history) {
    const MulticontactNormal m =
        normal(p, k, c.overlap, c.effective_radius, c.effective_mass, sqrt_r_overlap, damping_root,
               vn, c.pair_pressure, history[0]);
    return {m.force, m.force - m.adhesive_floor};
  }

  // Elastic energy a contact gives back when unloaded along k2 to zero force:
  // ∫_{δp}^{δ} k2 (s^{3/2} - xp) ds (adhesion and the β term left out). For the divergence check;
  // with λp = 1 it is Hertz's 8/15 E* √R* δ^{5/2}.
  static double elastic_energy(const ElasticPair& p, const Constants& k, double effective_radius,
                               double /*radius_first*/, double /*radius_second*/, double overlap,
                               const double* history) {
    const double k1 = k.loading_stiffness > 0.0 ? k.loading_stiffness
                                                : k.loading_coefficient * p.effective_modulus *
                                                      std::sqrt(effective_radius);
    const double plastic_32 = history[0] / k1;                  // δp^{3/2}
    const double plastic = std::cbrt(plastic_32 * plastic_32);  // δp
    if (!(overlap > plastic)) return 0.0;
    const double k2 = k.unloading_factor * k1;
    return k2 * (0.4 * (overlap * overlap * std::sqrt(overlap) -
                        plastic * plastic * std::sqrt(plastic)) -
                 plastic_32 * (overlap - plastic));
  }
};

}  // namespace shapepress::simulate
