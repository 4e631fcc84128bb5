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
// keeping the product spares the hot loop a division and, with k1 from E* and kc = 0, any square
// root beyond Hertz's (docs/measurements.md, "Benchmarks").
#include <algorithm>
#include <cmath>

#include "simulate/materials.hpp"

namespace shapepress::simulate {

struct MulticontactNormal {
  double force;           // F0 + f_hys + β ν A P - γ vn, > 0 repulsive
  double adhesive_floor;  // F0 - kc x: the most attractive hysteretic force at this overlap
};

// `plastic_force` is the contact's k1 δp^{3/2}, updated here. `pair_pressure` is P_ij =
// ½ (p_i + p_j) from the previous step's Love–Weber stresses (a wall has p = 0); tension
// (P < 0) is taken as 0: the term models confinement, it does not pull. `sqrt_r_overlap` =
// √(R* δ) and `damping_root` = √(√(R* δ) m*), already computed by the caller.
[[gnu::always_inline]] inline MulticontactNormal multicontact_normal(
    const PairConstants& p, double overlap, double effective_radius, double effective_mass,
    double sqrt_r_overlap, double damping_root, double vn, double pair_pressure,
    double& plastic_force) {
  // k1 given (the paper's calibrated Avicel case) or Hertz's 4/3 E* √R*: then the loading force
  // and its damping stiffness are written like the Hertz branch, and λp = 1, kc = F0 = β = 0
  // gives Hertz's bits.
  const bool given = p.loading_stiffness > 0.0;
  const double sqrt_overlap = given || p.adhesion_stiffness > 0.0 ? std::sqrt(overlap) : 0.0;
  const double x = overlap * sqrt_overlap;  // δ^{3/2} (only where used)
  const double loading =
      given ? p.loading_stiffness * x : 4.0 / 3.0 * p.effective_modulus * sqrt_r_overlap * overlap;
  const double candidate = p.plastic_fraction * loading;
  if (candidate > plastic_force) plastic_force = candidate;  // virgin loading
  const double unloading = p.unloading_factor * (loading - plastic_force);
  const double adhesive = -p.adhesion_stiffness * x;
  const double hysteretic = std::max(std::min(loading, unloading), adhesive);
  // Multi-contact term, A_ij = π a² with a² = R* δ; the factor holds β ν π.
  const double confinement =
      p.multicontact_factor * effective_radius * overlap * std::max(pair_pressure, 0.0);
  // Damping on the loading stiffness S = dF/dδ = 3/2 k1 √δ (= 2 E* √(R* δ) for Hertz's k1), so
  // the restitution of a first impact is the input e; unloading branches are not re-damped.
  // With Hertz's k1 this is contact_law.hpp's γn = damping_factor √(2 E* √(R*δ) m*).
  const double gamma_n =
      given
          ? p.damping_factor * std::sqrt(1.5 * p.loading_stiffness * sqrt_overlap * effective_mass)
          : p.normal_damping_scale * damping_root;
  return {p.pull_off_force + hysteretic + confinement - gamma_n * vn, p.pull_off_force + adhesive};
}

// Elastic energy a multi-contact contact gives back when unloaded along k2 to zero force:
// ∫_{δp}^{δ} k2 (s^{3/2} - xp) ds (adhesion and the β term left out). For the divergence check;
// with λp = 1 it is Hertz's 8/15 E* √R* δ^{5/2}.
inline double multicontact_elastic_energy(const PairConstants& p, double effective_radius,
                                          double overlap, double plastic_force) {
  const double k1 = p.loading_stiffness > 0.0
                        ? p.loading_stiffness
                        : 4.0 / 3.0 * p.effective_modulus * std::sqrt(effective_radius);
  const double plastic_32 = plastic_force / k1;               // δp^{3/2}
  const double plastic = std::cbrt(plastic_32 * plastic_32);  // δp
  if (!(overlap > plastic)) return 0.0;
  const double k2 = p.unloading_factor * k1;
  return k2 *
         (0.4 * (overlap * overlap * std::sqrt(overlap) - plastic * plastic * std::sqrt(plastic)) -
          plastic_32 * (overlap - plastic));
}

}  // namespace shapepress::simulate
