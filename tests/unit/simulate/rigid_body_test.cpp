// The rigid-body rotation integrator (issue 6, rigid-body tests): a torque-free asymmetric body
// keeps its energy and angular momentum and tumbles about its intermediate axis (the
// Dzhanibekov flip), stays put about its major axis, reverses exactly, and takes torque kicks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "simulate/rigid_body.hpp"

namespace shapepress::simulate {
namespace {

double norm(const Vector3& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

double distance(const Vector3& a, const Vector3& b) {
  return norm({a[0] - b[0], a[1] - b[1], a[2] - b[2]});
}

struct TumbleRecord {
  double max_energy_error = 0.0;
  double max_momentum_error = 0.0;
  int flips = 0;  // sign changes of L along the given body axis
};

TumbleRecord tumble(Vector3 body_momentum, int watched_axis, int steps, double dt) {
  RigidRotation body;
  body.principal_inertia = {1.0, 2.0, 3.0};
  body.orientation = normalized({0.9, 0.1, -0.3, 0.2});  // not aligned with the world axes
  body.body_angular_momentum = body_momentum;
  const double energy = rotational_energy(body);
  const Vector3 momentum = angular_momentum(body);
  TumbleRecord r;
  double last = body.body_angular_momentum[watched_axis];
  for (int k = 0; k < steps; ++k) {
    rotate_free(body, dt);
    r.max_energy_error =
        std::max(r.max_energy_error, std::fabs(rotational_energy(body) / energy - 1.0));
    r.max_momentum_error =
        std::max(r.max_momentum_error, distance(angular_momentum(body), momentum) / norm(momentum));
    const double now = body.body_angular_momentum[watched_axis];
    if ((now > 0.0) != (last > 0.0)) ++r.flips;
    last = now;
  }
  return r;
}

TEST(RigidRotation, TorqueFreeAsymmetricBodyConservesEnergyAndMomentumAndFlips) {
  // |L| = 1 along the intermediate axis (I2 = 2) with a 1e-3 nudge: ω = 0.5 rad/s, the flip
  // grows at λ = ω √((I2-I1)(I3-I2)/(I1 I3)) ≈ 0.29 /s, so 100 s hold a few flips.
  const TumbleRecord r = tumble({1e-3, 1.0, 1e-3}, 1, 100000, 1e-3);
  std::printf("intermediate axis: %d flips in 1e5 steps, energy error %.2e, |dL|/|L| %.2e\n",
              r.flips, r.max_energy_error, r.max_momentum_error);
  EXPECT_LT(r.max_energy_error, 1e-6);
  EXPECT_LT(r.max_momentum_error, 1e-6);
  EXPECT_GE(r.flips, 2) << "the intermediate axis must be unstable";
}

TEST(RigidRotation, MajorAxisIsStable) {
  const TumbleRecord r = tumble({1e-3, 1e-3, 1.0}, 2, 100000, 1e-3);
  EXPECT_EQ(r.flips, 0);
  EXPECT_LT(r.max_energy_error, 1e-6);
  EXPECT_LT(r.max_momentum_error, 1e-6);
}

TEST(RigidRotation, RunsBackwardToWhereItStarted) {
  RigidRotation body;
  body.principal_inertia = {0.3, 1.1, 2.0};
  body.body_angular_momentum = {0.2, -0.7, 0.4};
  const RigidRotation start = body;
  for (int k = 0; k < 5000; ++k)
    rotate_free(body, 1e-2);
  EXPECT_GT(distance(body.body_angular_momentum, start.body_angular_momentum), 0.1);
  for (int k = 0; k < 5000; ++k)
    rotate_free(body, -1e-2);
  EXPECT_LT(distance(body.body_angular_momentum, start.body_angular_momentum), 1e-10);
  EXPECT_NEAR(body.orientation.w, start.orientation.w, 1e-10);
  EXPECT_NEAR(body.orientation.x, start.orientation.x, 1e-10);
}

TEST(RigidRotation, FreeSpinAboutAPrincipalAxisTurnsAtLOverI) {
  RigidRotation body;
  body.principal_inertia = {2.0, 3.0, 4.0};
  body.body_angular_momentum = {0.0, 0.0, 4.0};  // ω = 1 rad/s about z
  for (int k = 0; k < 1000; ++k)
    rotate_free(body, 1e-3);
  // After 1 s the body turned by exactly 1 rad about z: x_body points at (cos 1, sin 1, 0).
  const Vector3 x = rotate_to_world(body.orientation, {1.0, 0.0, 0.0});
  EXPECT_NEAR(x[0], std::cos(1.0), 1e-12);
  EXPECT_NEAR(x[1], std::sin(1.0), 1e-12);
  const Vector3 omega = angular_velocity(body);
  EXPECT_NEAR(omega[2], 1.0, 1e-14);
}

TEST(RigidRotation, TorqueKicksAddWorldFrameMomentum) {
  RigidRotation body;
  body.principal_inertia = {1.0, 1.5, 2.5};
  body.orientation = normalized({0.5, 0.5, -0.5, 0.1});
  const Vector3 torque = {0.0, 0.3, 0.0};
  const double dt = 1e-3;
  for (int k = 0; k < 2000; ++k) {  // velocity Verlet: half kick, rotate, half kick
    kick_rotation(body, {0.5 * dt * torque[0], 0.5 * dt * torque[1], 0.5 * dt * torque[2]});
    rotate_free(body, dt);
    kick_rotation(body, {0.5 * dt * torque[0], 0.5 * dt * torque[1], 0.5 * dt * torque[2]});
  }
  const Vector3 l = angular_momentum(body);  // dL/dt = τ for any body: L = τ t
  EXPECT_NEAR(l[0], 0.0, 1e-12);
  EXPECT_NEAR(l[1], 0.6, 1e-12);
  EXPECT_NEAR(l[2], 0.0, 1e-12);
}

TEST(RigidRotation, BodyAndWorldRotationsAreInverse) {
  const Quaternion q = normalized({0.3, -0.4, 0.8, 0.2});
  const Vector3 v = {0.7, -1.2, 2.5};
  EXPECT_LT(distance(rotate_to_body(q, rotate_to_world(q, v)), v), 1e-14);
  EXPECT_NEAR(norm(rotate_to_world(q, v)), norm(v), 1e-14);
}

}  // namespace
}  // namespace shapepress::simulate
