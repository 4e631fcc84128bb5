#pragma once
// The contact law as composable sub-models (after LAMMPS gran_sub_mod_*):
//   normal (Hertz) ∘ damping (restitution, LIGGGHTS `gran model hertz`) ∘ tangential (Mindlin
//   spring with history, Coulomb-truncated) ∘ rolling (constant directional torque, CDT).
// Each is a small inline function so the pair loop in forces.cpp inlines the whole law. The normal
// sub-models are the value types of the registry normal_laws.hpp (Hertz, the multi-contact
// elastic–plastic law of paper Eq. 6, …), each composed with the same damping, tangential and
// rolling sub-models.
// Equations: models.md "Hertz–Mindlin with restitution damping" and "Multi-contact ...".
//
// Sign conventions: the normal n points from sphere i to sphere j (for a wall, j is the wall);
// relative velocities are those of j's contact point minus i's; the force returned acts on j
// (i receives its negative).
//
// Choice (docs/models.md): like LIGGGHTS `hertz tangential history`
// without `limitForce`, the damped normal force is not clipped at zero, so it can be attractive
// at the end of a rebound. This is what makes the measured restitution equal the input e exactly
// (a clipped force gives a larger e); contacts end when the overlap vanishes.
#include <array>
#include <cmath>
#include <type_traits>

#include "simulate/law_types.hpp"
#include "simulate/materials.hpp"
#include "simulate/normal_laws.hpp"

namespace shapepress::simulate {

// What a contact remembers between steps: the tangential spring (accumulated tangential
// displacement, world frame) and the normal laws' history fields one after another
// (normal_history_offset<Law>; the multi-contact law's plastic force). The list merge
// (carry_history), checkpoints and snapshots carry every field.
struct ContactHistory {
  double tangential[3] = {0.0, 0.0, 0.0};
  std::array<double, normal_history_size> normal{};
};

template <class Law>
[[gnu::always_inline]] inline double* law_history(ContactHistory& h) {
  return h.normal.data() + normal_history_offset<Law>;
}
template <class Law>
inline const double* law_history(const ContactHistory& h) {
  return h.normal.data() + normal_history_offset<Law>;
}

struct ContactForce {
  double force[3];           // on j; i gets -force
  double rolling_torque[3];  // on i; j gets -rolling_torque
  double normal_force;       // signed, > 0 repulsive (for stress and energy bookkeeping)
};

// Damping sub-model (LIGGGHTS): γ = -2√(5/6) β √(S m*), S = 2E*√(R*δ) (normal) or 8G*√(R*δ)
// (tangential). The Hertz + √δ-scaled damping gives a restitution independent of impact speed.
// PairConstants holds damping_factor × √(2E*) and × √(8G*), so contact_force takes one sqrt
// for both.

// Tangential sub-model: Mindlin spring kt = 8 G* √(R* δ) on the accumulated tangential
// displacement ξ. ξ is first rotated into the current tangent plane keeping its length, then
// incremented by vt dt. If the spring force exceeds μs |Fn| it is truncated to the Coulomb limit
// and ξ is shrunk to match (no damping while sliding), as in LIGGGHTS `tangential history`.
// `friction_load` is the normal law's NormalForce::friction_load: Fn for Hertz, Fn measured from
// the adhesive floor for the multi-contact law.
[[gnu::always_inline]] inline void mindlin_tangential(const PairConstants& p, const double n[3],
                                                      const double vt[3], double kt, double gamma_t,
                                                      double friction_load, double dt,
                                                      ContactHistory& history, double force[3]) {
  double* xi = history.tangential;
  const double length2 = xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2];
  if (length2 > 0.0) {
    const double along_normal = xi[0] * n[0] + xi[1] * n[1] + xi[2] * n[2];
    double t[3] = {xi[0] - along_normal * n[0], xi[1] - along_normal * n[1],
                   xi[2] - along_normal * n[2]};
    const double t2 = t[0] * t[0] + t[1] * t[1] + t[2] * t[2];
    const double scale = t2 > 0.0 ? std::sqrt(length2 / t2) : 0.0;
    for (int k = 0; k < 3; ++k)
      xi[k] = t[k] * scale;
  }
  for (int k = 0; k < 3; ++k)
    xi[k] += vt[k] * dt;
  // Compared squared: a sticking contact (most of them) then needs no square root.
  const double xi2 = xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2];
  const double limit = p.sliding_friction * std::fabs(friction_load);
  if (kt * kt * xi2 > limit * limit) {
    const double spring = kt * std::sqrt(xi2);
    const double ratio = limit / spring;  // spring > limit >= 0
    for (int k = 0; k < 3; ++k) {
      xi[k] *= ratio;
      force[k] = -kt * xi[k];
    }
  } else {
    for (int k = 0; k < 3; ++k)
      force[k] = -kt * xi[k] - gamma_t * vt[k];
  }
}

// Rolling sub-model: constant directional torque (Ai et al. 2011 model A, LIGGGHTS `cdt`),
// τ_i = -μr R* |Fn| ωr/|ωr| with ωr the relative rotation in the tangent plane. Chatter guard:
// below ωc = μr R* |Fn| dt / I* (the rotation the full torque removes in one step) the torque is
// scaled by |ωr|/ωc, so it stops the relative rolling instead of reversing it every step.
[[gnu::always_inline]] inline void cdt_rolling(const PairConstants& p, const ContactKinematics& c,
                                               double normal_force, double dt, double torque[3]) {
  torque[0] = torque[1] = torque[2] = 0.0;
  if (p.rolling_friction <= 0.0) return;
  const double* n = c.normal;
  const double* w = c.relative_rotation;
  const double along = w[0] * n[0] + w[1] * n[1] + w[2] * n[2];
  const double wr[3] = {w[0] - along * n[0], w[1] - along * n[1], w[2] - along * n[2]};
  const double wr_norm = std::sqrt(wr[0] * wr[0] + wr[1] * wr[1] + wr[2] * wr[2]);
  const double magnitude = p.rolling_friction * c.effective_radius * std::fabs(normal_force);
  if (wr_norm == 0.0 || magnitude == 0.0) return;
  const double guard = magnitude * dt * c.inverse_inertia_sum;
  const double scale = magnitude / (wr_norm > guard ? wr_norm : guard);
  for (int k = 0; k < 3; ++k)
    torque[k] = -scale * wr[k];
}

// The law of a pair whose normal law is known only at run time: PairConstants::law picks it per
// contact. The pair loop takes it only for a scene that mixes laws (forces.cpp).
struct AnyNormalLaw {};

template <class Law>
[[gnu::always_inline]] inline NormalForce normal_force_of(const PairConstants& p,
                                                          const ContactKinematics& c,
                                                          double sqrt_r_overlap,
                                                          double damping_root, double vn,
                                                          ContactHistory& history) {
  if constexpr (std::is_same_v<Law, AnyNormalLaw>) {
    return with_normal_law(p.law, [&]<class L>() {
      return normal_force_of<L>(p, c, sqrt_r_overlap, damping_root, vn, history);
    });
  } else {
    return Law::force(p, p.constants_of<Law>(), c, sqrt_r_overlap, damping_root, vn,
                      law_history<Law>(history));
  }
}

// The whole law for one touching contact, with the normal law `Law` (or the pair's own with
// AnyNormalLaw). Updates `history`.
template <class Law = AnyNormalLaw>
[[gnu::always_inline]] inline ContactForce contact_force(const ContactKinematics& c,
                                                         const PairConstants& p,
                                                         ContactHistory& history, double dt) {
  ContactForce out;
  const double* n = c.normal;
  const double* v = c.relative_velocity;
  const double vn = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];  // < 0 approaching
  const double vt[3] = {v[0] - vn * n[0], v[1] - vn * n[1], v[2] - vn * n[2]};
  const double sqrt_r_overlap = std::sqrt(c.effective_radius * c.overlap);

  // Both damping coefficients share √(√(R*δ) m*) (restitution_damping with S = 2E*√(R*δ) and
  // kt = 8G*√(R*δ)); the pair constants hold the rest, so one sqrt serves both.
  const double damping_root = std::sqrt(sqrt_r_overlap * c.effective_mass);
  const NormalForce normal = normal_force_of<Law>(p, c, sqrt_r_overlap, damping_root, vn, history);
  const double normal_force = normal.force;
  const double kt = 8.0 * p.effective_shear_modulus * sqrt_r_overlap;
  const double gamma_t = p.tangential_damping_scale * damping_root;
  double tangential[3];
  mindlin_tangential(p, n, vt, kt, gamma_t, normal.friction_load, dt, history, tangential);
  for (int k = 0; k < 3; ++k)
    out.force[k] = normal_force * n[k] + tangential[k];
  cdt_rolling(p, c, normal_force, dt, out.rolling_torque);
  out.normal_force = normal_force;
  return out;
}

// Elastic normal energy of a contact under its pair's law (energy checks); `radius_second` 0: a
// wall.
inline double normal_elastic_energy(const PairConstants& p, double effective_radius,
                                    double radius_first, double radius_second, double overlap,
                                    const ContactHistory& history) {
  return with_normal_law(p.law, [&]<class L>() {
    return L::elastic_energy(p, p.constants_of<L>(), effective_radius, radius_first, radius_second,
                             overlap, law_history<L>(history));
  });
}

// Whether a pair's law reads the particles' pressure P_ij (the engine then keeps it).
inline bool normal_law_needs_pair_pressure(const PairConstants& p) {
  return with_normal_law(p.law, [&]<class L>() { return L::needs_pair_pressure; });
}

// The largest tangent stiffness of the pair's law over Hertz's at R* (timestep.cpp).
inline double normal_stiffness_ratio(const PairConstants& p, double effective_radius) {
  return with_normal_law(p.law, [&]<class L>() {
    return L::stiffness_ratio(p, p.constants_of<L>(), effective_radius);
  });
}

// Named access to single laws, for tests and reports.
inline double hertz_elastic_energy(const PairConstants& p, double effective_radius,
                                   double overlap) {
  return HertzLaw::elastic_energy(p, {}, effective_radius, 0.0, 0.0, overlap, nullptr);
}
inline double& plastic_force(ContactHistory& h) {
  return law_history<MulticontactLaw>(h)[0];
}
inline double plastic_force(const ContactHistory& h) {
  return law_history<MulticontactLaw>(h)[0];
}
[[gnu::always_inline]] inline MulticontactNormal multicontact_normal(
    const PairConstants& p, double overlap, double effective_radius, double effective_mass,
    double sqrt_r_overlap, double damping_root, double vn, double pair_pressure,
    double& plastic_force) {
  return MulticontactLaw::normal(p, p.constants_of<MulticontactLaw>(), overlap, effective_radius,
                                 effective_mass, sqrt_r_overlap, damping_root, vn, pair_pressure,
                                 plastic_force);
}
inline double multicontact_elastic_energy(const PairConstants& p, double effective_radius,
                                          double overlap, double plastic_force) {
  return MulticontactLaw::elastic_energy(p, p.constants_of<MulticontactLaw>(), effective_radius,
                                         0.0, 0.0, overlap, &plastic_force);
}

}  // namespace shapepress::simulate
