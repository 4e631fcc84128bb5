#pragma once
// What the contact laws share: a material, the geometry of one contact, the pair constants every
// normal law reads, and what a normal law returns. The normal laws themselves (hertz_law.hpp,
// multicontact_law.hpp, …) are value types registered in normal_laws.hpp; contact_law.hpp composes
// them with the damping, tangential and rolling sub-models.
#include <optional>
#include <string>

namespace shapepress::simulate {

struct Material {
  std::string name;
  double youngs_modulus = 0.0;  // E, Pa
  double poisson_ratio = 0.0;   // ν
  double density = 0.0;         // ρ, kg/m³ (unused for walls)
  // E of the multi-contact law's loading branch, k1 = 4/3 E*_L √R* (Eq. 6, Giannis 2023), where it
  // is not the elastic E: a loading stiffness calibrated on one size of particle, stated as the
  // modulus it implies, gives every contact its own k1 (a sub-sphere's, a wall's) from its R*,
  // where a k1 copied between sizes would not (docs/models.md, "One material"). Absent: E.
  std::optional<double> loading_modulus = std::nullopt;
};

struct ContactKinematics {
  double normal[3];             // unit, i → j
  double overlap;               // δ > 0
  double relative_velocity[3];  // contact point of j minus contact point of i
  double relative_rotation[3];  // ωi - ωj, for rolling friction
  double effective_radius;      // R* = ri rj / (ri + rj); wall: ri
  double effective_mass;        // m* = mi mj / (mi + mj); wall: mi
  double inverse_inertia_sum;   // 1/I* = 1/Ii + 1/Ij; wall: 1/Ii (chatter guard)
  double pair_pressure;         // ½ (p_i + p_j), a wall: p_i; previous step (multi-contact only)
  double radius_first;          // ri
  double radius_second;         // rj; a wall: 0 (the MDR law splits a pair's overlap by them)
};

// The pair constants of every law (models.md "Hertz–Mindlin with restitution"), computed once per
// pair of materials so the hot loop holds no pow and no logarithm.
struct ElasticPair {
  double effective_modulus = 0.0;        // E*: 1/E* = (1-νi²)/Ei + (1-νj²)/Ej
  double effective_shear_modulus = 0.0;  // G*: 1/G* = (2-νi)/Gi + (2-νj)/Gj
  double damping_factor = 0.0;           // -2 √(5/6) β ≥ 0, β = ln e / √(ln² e + π²)
  // γn = normal_damping_scale √(√(R*δ) m*), γt = tangential_damping_scale √(√(R*δ) m*): the
  // damping of contact_law.hpp with the constant roots taken here, so a contact needs one sqrt.
  double normal_damping_scale = 0.0;      // damping_factor √(2 E*)
  double tangential_damping_scale = 0.0;  // damping_factor √(8 G*)
  double sliding_friction = 0.0;
  double rolling_friction = 0.0;
  // R* of a contact between sub-spheres of two different bodies: the bodies' volume-equivalent
  // radii (SphereState::body_radius) instead of the sub-spheres' (Interaction::contact_radius).
  bool body_contact_radius = false;
};

// A normal law's answer for one touching contact.
struct NormalForce {
  double force = 0.0;          // signed, > 0 repulsive, damping included
  double friction_load = 0.0;  // what the Coulomb limit μs |·| of the tangential spring reads
};

// One value a normal law keeps per contact between steps. Snapshots store it as
// /engine/contact_<name> and /engine/wall_<name> (absent in an older snapshot: 0).
struct HistoryField {
  const char* name;
  const char* unit;
  const char* help;
};

}  // namespace shapepress::simulate
