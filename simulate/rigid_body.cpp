#include "simulate/rigid_body.hpp"

#include <cmath>

namespace shapepress::simulate {

Quaternion multiply(const Quaternion& a, const Quaternion& b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

Quaternion normalized(const Quaternion& q) {
  const double s = 1.0 / std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w * s, q.x * s, q.y * s, q.z * s};
}

Vector3 rotate_to_world(const Quaternion& q, const Vector3& v) {
  // v + 2 u × (u × v + w v), u = (x, y, z): the rotation without building the matrix.
  const Vector3 u = {q.x, q.y, q.z};
  const Vector3 c = {u[1] * v[2] - u[2] * v[1] + q.w * v[0], u[2] * v[0] - u[0] * v[2] + q.w * v[1],
                     u[0] * v[1] - u[1] * v[0] + q.w * v[2]};
  return {v[0] + 2.0 * (u[1] * c[2] - u[2] * c[1]), v[1] + 2.0 * (u[2] * c[0] - u[0] * c[2]),
          v[2] + 2.0 * (u[0] * c[1] - u[1] * c[0])};
}

Vector3 rotate_to_body(const Quaternion& q, const Vector3& v) {
  return rotate_to_world({q.w, -q.x, -q.y, -q.z}, v);
}

Vector3 angular_momentum(const RigidRotation& body) {
  return rotate_to_world(body.orientation, body.body_angular_momentum);
}

void kick_rotation(RigidRotation& body, const Vector3& impulse) {
  const Vector3 body_impulse = rotate_to_body(body.orientation, impulse);
  for (int k = 0; k < 3; ++k)
    body.body_angular_momentum[k] += body_impulse[k];
}

Vector3 angular_velocity(const RigidRotation& body) {
  Vector3 omega = body.body_angular_momentum;
  for (int k = 0; k < 3; ++k)
    omega[k] /= body.principal_inertia[k];
  return rotate_to_world(body.orientation, omega);
}

double rotational_energy(const RigidRotation& body) {
  const Vector3& l = body.body_angular_momentum;
  double energy = 0.0;
  for (int k = 0; k < 3; ++k)
    energy += 0.5 * l[k] * l[k] / body.principal_inertia[k];
  return energy;
}

namespace {

// Rk(τ): the body turns by θ = τ Lk/Ik about its axis k; in the body frame L turns by -θ about
// the same axis (the world-frame L is fixed), so Lk is kept and the other two rotate.
void rotate_about_axis(Quaternion& q, Vector3& l_body, const Vector3& inertia, int k, double tau) {
  const double angle = tau * l_body[k] / inertia[k];
  const double c = std::cos(angle), s = std::sin(angle);
  const int a = (k + 1) % 3, b = (k + 2) % 3;
  const double la = l_body[a], lb = l_body[b];
  l_body[a] = c * la + s * lb;
  l_body[b] = -s * la + c * lb;
  Quaternion turn{std::cos(0.5 * angle), 0.0, 0.0, 0.0};
  const double half_sine = std::sin(0.5 * angle);
  (k == 0 ? turn.x : k == 1 ? turn.y : turn.z) = half_sine;
  q = multiply(q, turn);
}

}  // namespace

void rotate_free(RigidRotation& body, double dt) {
  Quaternion& q = body.orientation;
  Vector3& l = body.body_angular_momentum;
  const Vector3& inertia = body.principal_inertia;
  rotate_about_axis(q, l, inertia, 0, 0.5 * dt);
  rotate_about_axis(q, l, inertia, 1, 0.5 * dt);
  rotate_about_axis(q, l, inertia, 2, dt);
  rotate_about_axis(q, l, inertia, 1, 0.5 * dt);
  rotate_about_axis(q, l, inertia, 0, 0.5 * dt);
  // Each turn is unit to round-off; renormalising keeps long runs from drifting by ulps.
  q = normalized(q);
}

}  // namespace shapepress::simulate
