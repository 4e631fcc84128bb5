#pragma once
// The kinematics of a sphere pair and the Hertz–Mindlin law over a block of touching pairs laid
// out as structure of arrays, so that the compiler vectorizes the law across contacts (the pair
// loop of forces.cpp copies a block's inputs in, calls hertz_contact_block, and adds the results
// in list order). Each lane performs the scalar law's IEEE operations in the scalar order (no
// FMA, no reassociation), so every clone of the block (SSE2, AVX2, AVX-512) and the scalar
// pair loop give the same bits (tests/unit/simulate/contact_block_test.cpp).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "simulate/contact_law.hpp"
#include "simulate/materials.hpp"

namespace shapepress::simulate {

// One end of a sphere pair as the pair loop reads it: the velocity and spin predicted for the end
// of the step (Engine::pack_spheres), the mass and 1/I.
struct PairEnd {
  double velocity[3];
  double spin[3];
  double mass;
  double inverse_inertia;
};

// A touching pair's kinematics and the distances from each centre to the contact point,
// rci = ri - δ/2 (first) and rcj = rj - δ/2 (second).
struct PairKinematics {
  ContactKinematics contact;
  double arm_first;
  double arm_second;
};

// From the separation d = x_second - x_first (nearest image) and the two ends. The normal points
// from first to second; relative velocities are those of second's contact point minus first's.
[[gnu::always_inline]] inline PairKinematics pair_kinematics(const double d[3], double ri,
                                                             double rj, const PairEnd& a,
                                                             const PairEnd& b) {
  PairKinematics out;
  ContactKinematics& c = out.contact;
  const double reach = ri + rj;
  const double distance = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  const double inv_d = 1.0 / distance;
  c.normal[0] = d[0] * inv_d;
  c.normal[1] = d[1] * inv_d;
  c.normal[2] = d[2] * inv_d;
  c.overlap = std::max(reach - distance, 0.0);  // > 0 when selected; guards a contracted d²
  const double* n = c.normal;
  const double rci = ri - 0.5 * c.overlap, rcj = rj - 0.5 * c.overlap;
  const double* wi = a.spin;
  const double* wj = b.spin;
  // Contact point velocities: v + ω × (arm), arm = +rci n for first, -rcj n for second.
  const double vcix = a.velocity[0] + rci * (wi[1] * n[2] - wi[2] * n[1]);
  const double vciy = a.velocity[1] + rci * (wi[2] * n[0] - wi[0] * n[2]);
  const double vciz = a.velocity[2] + rci * (wi[0] * n[1] - wi[1] * n[0]);
  const double vcjx = b.velocity[0] - rcj * (wj[1] * n[2] - wj[2] * n[1]);
  const double vcjy = b.velocity[1] - rcj * (wj[2] * n[0] - wj[0] * n[2]);
  const double vcjz = b.velocity[2] - rcj * (wj[0] * n[1] - wj[1] * n[0]);
  c.relative_velocity[0] = vcjx - vcix;
  c.relative_velocity[1] = vcjy - vciy;
  c.relative_velocity[2] = vcjz - vciz;
  c.relative_rotation[0] = wi[0] - wj[0];
  c.relative_rotation[1] = wi[1] - wj[1];
  c.relative_rotation[2] = wi[2] - wj[2];
  // R* = ri rj / (ri + rj) and m* = mi mj / (mi + mj) with one division.
  const double mass_sum = a.mass + b.mass;
  const double inverse = 1.0 / (reach * mass_sum);
  c.effective_radius = ri * rj * mass_sum * inverse;
  c.effective_mass = a.mass * b.mass * reach * inverse;
  c.inverse_inertia_sum = a.inverse_inertia + b.inverse_inertia;
  c.pair_pressure = 0.0;  // P_ij of Eq. 6: the multi-contact law's, set by its caller
  c.radius_first = ri;
  c.radius_second = rj;
  out.arm_first = rci;
  out.arm_second = rcj;
  return out;
}

// R* of a touching pair whose interaction states `contact_radius = "body"`: between sub-spheres of
// two different bodies the bodies' R* = Ri Rj / (Ri + Rj) of their volume-equivalent radii, else 0
// (the pair keeps its spheres' R*, pair_kinematics); two plain spheres (each its own body radius)
// keep theirs to the bit. A contact of two bodies' surfaces has their curvature, not that of the
// sub-spheres that touch: with the sub-spheres' R* a body-to-body contact is √(R*_bodies /
// R*_sub-spheres) times softer than the particles' at the same overlap, and the bodies are
// crushed through each other (docs/models.md, "Contacts between bodies").
[[gnu::always_inline]] inline double body_contact_radius(bool on, const std::int32_t* body,
                                                         const double* body_radius,
                                                         const double* radius, int i, int j) {
  if (!on || body[i] == body[j]) return 0.0;
  const double ri = body_radius[i], rj = body_radius[j];
  if (ri == radius[i] && rj == radius[j]) return 0.0;
  return ri * rj / (ri + rj);
}

// The torques of a contact force F on second (first gets -F) at arms rci n and -rcj n:
// τi = (rci n) × (-F) = -rci (n × F), τj = (-rcj n) × F = -rcj (n × F), plus the rolling torque
// (on first; second gets its negative).
[[gnu::always_inline]] inline void contact_torques(const double n[3], const ContactForce& f,
                                                   double rci, double rcj, double first[3],
                                                   double second[3]) {
  const double cx = n[1] * f.force[2] - n[2] * f.force[1];
  const double cy = n[2] * f.force[0] - n[0] * f.force[2];
  const double cz = n[0] * f.force[1] - n[1] * f.force[0];
  first[0] = -rci * cx + f.rolling_torque[0];
  first[1] = -rci * cy + f.rolling_torque[1];
  first[2] = -rci * cz + f.rolling_torque[2];
  second[0] = -rcj * cx - f.rolling_torque[0];
  second[1] = -rcj * cy - f.rolling_torque[1];
  second[2] = -rcj * cz - f.rolling_torque[2];
}

// Up to `capacity` touching pairs of one pair constant, one array per quantity ([axis][lane] for
// vectors). About 19 KiB: a block's inputs and results stay in L1 between the copy in, the law
// and the sums.
struct ContactBlock {
  static constexpr int capacity = 64;
  alignas(64) double separation[3][capacity];  // x_second - x_first, nearest image
  alignas(64) double radius_first[capacity];
  alignas(64) double radius_second[capacity];
  // The bodies' R* (body_contact_radius), 0: the spheres'.
  alignas(64) double body_radius[capacity];
  alignas(64) double velocity_first[3][capacity];  // predicted (PairEnd)
  alignas(64) double spin_first[3][capacity];
  alignas(64) double velocity_second[3][capacity];
  alignas(64) double spin_second[3][capacity];
  alignas(64) double mass_first[capacity];
  alignas(64) double mass_second[capacity];
  alignas(64) double inverse_inertia_first[capacity];
  alignas(64) double inverse_inertia_second[capacity];
  alignas(64) double spring[3][capacity];  // ContactHistory::tangential: in, and updated
  // The multi-contact law's P_ij = ½ (p_i + p_j) (in) and its history, k1 δp^{3/2} (in, and
  // updated); the Hertz law reads neither.
  alignas(64) double pair_pressure[capacity];
  alignas(64) double plastic_force[capacity];
  // Out: the force on second and the torques on each end; Fn and δ for the Love–Weber sums.
  alignas(64) double force[3][capacity];
  alignas(64) double torque_first[3][capacity];
  alignas(64) double torque_second[3][capacity];
  alignas(64) double normal_force[capacity];
  alignas(64) double overlap[capacity];
};

// Hertz–Mindlin (contact_force<HertzLaw>) on lanes [0, count) of `block`, all with pair constants
// `pair`: the forces, torques and updated springs. Clones for AVX-512 and AVX2 are picked at load
// time where the CPU has them.
void hertz_contact_block(ContactBlock& block, int count, const PairConstants& pair, double dt);
// The same with the multi-contact law (contact_force<MulticontactLaw>, Eq. 6 Giannis 2023).
void multicontact_contact_block(ContactBlock& block, int count, const PairConstants& pair,
                                double dt);

}  // namespace shapepress::simulate
