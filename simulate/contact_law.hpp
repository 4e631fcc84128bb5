#pragma once
// The contact law as composable sub-models (after LAMMPS gran_sub_mod_*):
//   normal (Hertz) ∘ damping (restitution, LIGGGHTS `gran model hertz`) ∘ tangential (Mindlin
//   spring with history, Coulomb-truncated) ∘ rolling (constant directional torque, CDT).
// Each is a small inline function so the pair loop in forces.cpp inlines the whole law. The
// multi-contact elastic–plastic law (paper Eq. 6) is a second normal sub-model
// (multicontact_law.hpp) composed with the same damping, tangential and rolling sub-models.
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
#include <cmath>

#include "simulate/materials.hpp"
#include "simulate/multicontact_law.hpp"

namespace shapepress::simulate {

// What a contact remembers between steps: the tangential spring (accumulated tangential
// displacement, world frame) and the multi-contact law's plastic overlap as the plastic force
// k1 δp^{3/2} = (1 - λp) k1 δmax^{3/2} (N; it encodes δp and δmax; 0 for Hertz). The list merge
// (carry_history), checkpoints and snapshots carry every field.
struct ContactHistory {
  double tangential[3] = {0.0, 0.0, 0.0};
  double plastic_force = 0.0;
};

struct ContactKinematics {
  double normal[3];             // unit, i → j
  double overlap;               // δ > 0
  double relative_velocity[3];  // contact point of j minus contact point of i
  double relative_rotation[3];  // ωi - ωj, for rolling friction
  double effective_radius;      // R* = ri rj / (ri + rj); wall: ri
  double effective_mass;        // m* = mi mj / (mi + mj); wall: mi
  double inverse_inertia_sum;   // 1/I* = 1/Ii + 1/Ij; wall: 1/Ii (chatter guard)
  double pair_pressure;         // P_ij = ½ (p_i + p_j), previous step (multi-contact law only)
};

struct ContactForce {
  double force[3];           // on j; i gets -force
  double rolling_torque[3];  // on i; j gets -rolling_torque
  double normal_force;       // signed, > 0 repulsive (for stress and energy bookkeeping)
};

// Normal elastic sub-model: Hertz, Fn = 4/3 E* √R* δ^{3/2} = kn δ with kn = 4/3 E* √(R* δ).
// Returns kn; `sqrt_r_overlap` = √(R* δ) so no pow is needed.
inline double hertz_normal_stiffness(const PairConstants& p, double sqrt_r_overlap) {
  return 4.0 / 3.0 * p.effective_modulus * sqrt_r_overlap;
}

// Damping sub-model (LIGGGHTS): γ = -2√(5/6) β √(S m*), S = 2E*√(R*δ) (normal) or 8G*√(R*δ)
// (tangential). The Hertz + √δ-scaled damping gives a restitution independent of impact speed.
// PairConstants holds damping_factor × √(2E*) and × √(8G*), so contact_force takes one sqrt
// for both.

// Tangential sub-model: Mindlin spring kt = 8 G* √(R* δ) on the accumulated tangential
// displacement ξ. ξ is first rotated into the current tangent plane keeping its length, then
// incremented by vt dt. If the spring force exceeds μs |Fn| it is truncated to the Coulomb limit
// and ξ is shrunk to match (no damping while sliding), as in LIGGGHTS `tangential history`.
// `friction_load` is Fn for Hertz; for the adhesive law it is Fn measured from the adhesive
// floor, Fn - (F0 - kc δ^{3/2}), so an adhesive contact still holds friction (as EEPA does).
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

// The whole law for one touching contact. Updates `history`.
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
  double normal_force = 0.0;
  double friction_load = 0.0;
  switch (p.normal_law) {
    case NormalLaw::hertz: {
      const double kn = hertz_normal_stiffness(p, sqrt_r_overlap);
      const double gamma_n = p.normal_damping_scale * damping_root;
      normal_force = kn * c.overlap - gamma_n * vn;
      friction_load = normal_force;
      break;
    }
    case NormalLaw::multicontact: {
      const MulticontactNormal m =
          multicontact_normal(p, c.overlap, c.effective_radius, c.effective_mass, sqrt_r_overlap,
                              damping_root, vn, c.pair_pressure, history.plastic_force);
      normal_force = m.force;
      friction_load = m.force - m.adhesive_floor;
      break;
    }
  }
  const double kt = 8.0 * p.effective_shear_modulus * sqrt_r_overlap;
  const double gamma_t = p.tangential_damping_scale * damping_root;
  double tangential[3];
  mindlin_tangential(p, n, vt, kt, gamma_t, friction_load, dt, history, tangential);
  for (int k = 0; k < 3; ++k)
    out.force[k] = normal_force * n[k] + tangential[k];
  cdt_rolling(p, c, normal_force, dt, out.rolling_torque);
  out.normal_force = normal_force;
  return out;
}

// Elastic energy stored in a Hertz contact, 8/15 E* √R* δ^{5/2} (for the energy checks).
inline double hertz_elastic_energy(const PairConstants& p, double effective_radius,
                                   double overlap) {
  return 8.0 / 15.0 * p.effective_modulus * std::sqrt(effective_radius * overlap) * overlap *
         overlap;
}

// Elastic normal energy of a contact under its pair's law (energy checks).
inline double normal_elastic_energy(const PairConstants& p, double effective_radius, double overlap,
                                    const ContactHistory& history) {
  return p.normal_law == NormalLaw::multicontact
             ? multicontact_elastic_energy(p, effective_radius, overlap, history.plastic_force)
             : hertz_elastic_energy(p, effective_radius, overlap);
}

}  // namespace shapepress::simulate
