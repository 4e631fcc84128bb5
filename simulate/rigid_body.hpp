#pragma once
// Rotation of a rigid body (a CMS clump, paper §2.4) with its principal inertia: the symmetric
// splitting of the free rigid rotor into exact rotations about the body's principal axes
// (Dullweber, Leimkuhler & McLachlan 1997, J. Chem. Phys. 107, 5840; the same splitting as
// NO_SQUISH, Miller et al. 2002, J. Chem. Phys. 116, 8649):
//   R1(h/2) R2(h/2) R3(h) R2(h/2) R1(h/2),
// where Rk(τ) turns the body by τ Lk/Ik about its axis k, which keeps Lk and rotates the other two
// body components of the angular momentum L by the same angle the other way. Each Rk is exact,
// so the map is symplectic and time-reversible and the quaternion stays unit to round-off: the
// energy error stays bounded instead of drifting, and |L| is conserved exactly in exact
// arithmetic. Torques enter as half kicks of the world-frame L around it (velocity Verlet).
//
// Conventions: q rotates body-frame vectors into the world frame, v_world = q v_body q*.
#include <array>

namespace shapepress::simulate {

using Vector3 = std::array<double, 3>;

struct Quaternion {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
};

Quaternion multiply(const Quaternion& a, const Quaternion& b);
Quaternion normalized(const Quaternion& q);
Vector3 rotate_to_world(const Quaternion& q, const Vector3& body);
Vector3 rotate_to_body(const Quaternion& q, const Vector3& world);

// What integrates a clump's rotation: orientation, angular momentum in the body frame (the
// variable the splitting turns), and the principal moments (body frame = principal axes).
struct RigidRotation {
  Quaternion orientation;
  Vector3 body_angular_momentum = {0.0, 0.0, 0.0};  // kg m²/s
  Vector3 principal_inertia = {1.0, 1.0, 1.0};      // I1, I2, I3 > 0, kg m²
};

// L in the world frame, q L_body q*: constant in a torque-free rotation (the test of the
// integrator, since the splitting moves q and L_body, never L_world directly).
Vector3 angular_momentum(const RigidRotation& body);

// ω in the world frame: q (L_body / I) q*.
Vector3 angular_velocity(const RigidRotation& body);
// Rotational kinetic energy Σ Lk² / (2 Ik).
double rotational_energy(const RigidRotation& body);

// The free rotation over `dt` by the symmetric splitting above (no torque).
void rotate_free(RigidRotation& body, double dt);

// Adds `impulse` (torque × time, world frame) to the angular momentum: the half kicks of velocity
// Verlet, L += τ dt/2 before and after rotate_free.
void kick_rotation(RigidRotation& body, const Vector3& impulse);

}  // namespace shapepress::simulate
