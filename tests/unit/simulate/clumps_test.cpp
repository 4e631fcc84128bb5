// Rigid clumps (CMS, clumps.hpp): the union's mass properties, the inputs a clump refuses, and
// the engine's rigid-body motion of a clump.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "common/error.hpp"
#include "simulate/clumps.hpp"
#include "simulate/engine.hpp"

namespace shapepress::simulate {
namespace {

MaterialTable rubber() {
  return MaterialTable({{"rubber", 18.5e6, 0.46, 2000.0}}, {{"rubber", "rubber", 0.7, 0.5, 0.0}});
}

double norm(const Vector3& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

TEST(ClumpGeometry, OneSphereHasTheSphereVolumeAndInertia) {
  const double r = 2e-3;
  const std::vector<Vector3> c = {{1e-3, -2e-3, 5e-3}};
  const std::vector<double> radii = {r};
  const ClumpGeometry g = clump_geometry(c, radii, "ball");
  const double volume = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  // 128 voxels across: the midpoint rule's error is well under 1 %.
  EXPECT_NEAR(g.volume, volume, 0.01 * volume);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(g.centre[k], c[0][k], 0.01 * r);
    EXPECT_NEAR(g.principal_moments[k], 0.4 * volume * r * r, 0.01 * 0.4 * volume * r * r);
  }
}

// Two equal spheres of radius r at ±d/2 on x, overlapping (d < 2r): the union's volume and
// moments by slices normal to x (disc radius ρ² = r² − (x − d/2)² on x > 0, mirrored), summed
// on a fine grid — exact integrands, so this is the analytic value to 1e-8.
struct Dumbbell {
  double volume = 0.0, axial = 0.0, transverse = 0.0;  // per unit density
};
Dumbbell dumbbell_union(double r, double d) {
  const double a = 0.5 * d, top = a + r;
  const int n = 200000;
  const double h = top / n;
  Dumbbell out;
  for (int k = 0; k < n; ++k) {
    const double x = (k + 0.5) * h;
    const double rho2 = std::max(0.0, r * r - (x - a) * (x - a));
    out.volume += 2.0 * std::numbers::pi * rho2 * h;
    out.axial += 2.0 * 0.5 * std::numbers::pi * rho2 * rho2 * h;
    out.transverse +=
        2.0 * (0.25 * std::numbers::pi * rho2 * rho2 + std::numbers::pi * rho2 * x * x) * h;
  }
  return out;
}

TEST(ClumpGeometry, DumbbellUnionMatchesTheAnalyticInertiaWithinOnePercent) {
  const double r = 1e-3, d = 1.2e-3;
  const std::vector<Vector3> c = {{-0.5 * d, 0.0, 0.0}, {0.5 * d, 0.0, 0.0}};
  const std::vector<double> radii = {r, r};
  const ClumpGeometry g = clump_geometry(c, radii, "dumbbell");
  const Dumbbell exact = dumbbell_union(r, d);
  const double two_balls = 2.0 * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  EXPECT_LT(exact.volume, 0.95 * two_balls);  // the overlap matters: summing spheres is wrong
  EXPECT_NEAR(g.volume, exact.volume, 0.01 * exact.volume);
  // Ascending: the axial moment is the smallest, the two transverse ones equal.
  EXPECT_NEAR(g.principal_moments[0], exact.axial, 0.01 * exact.axial);
  EXPECT_NEAR(g.principal_moments[1], exact.transverse, 0.01 * exact.transverse);
  EXPECT_NEAR(g.principal_moments[2], exact.transverse, 0.01 * exact.transverse);
  // The smallest-moment axis is x.
  const Vector3 axis = rotate_to_world(g.axes, {1.0, 0.0, 0.0});
  EXPECT_NEAR(std::abs(axis[0]), 1.0, 1e-6);
}

TEST(ClumpGeometry, RefusesZeroVolumeAndDisconnectedFills) {
  const std::vector<Vector3> two = {{0.0, 0.0, 0.0}, {1e-3, 0.0, 0.0}};
  EXPECT_THROW(clump_geometry(two, std::vector<double>{1e-3, 0.0}, "zero"), InputError);
  EXPECT_THROW(clump_geometry(std::vector<Vector3>{}, std::vector<double>{}, "empty"), InputError);
  // 3 mm apart, radii 1 mm: two groups that do not overlap.
  const std::vector<Vector3> apart = {{0.0, 0.0, 0.0}, {0.5e-3, 0.0, 0.0}, {3e-3, 0.0, 0.0}};
  try {
    clump_geometry(apart, std::vector<double>{1e-3, 1e-3, 1e-3}, "apart");
    FAIL() << "a disconnected fill was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("apart"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("sub-sphere 2"), std::string::npos) << e.what();
  }
}

// An asymmetric clump: a big sphere with three smaller ones on different arms.
std::vector<Vector3> arms_centres() {
  return {{0.0, 0.0, 0.0}, {1.6e-3, 0.0, 0.0}, {0.0, 1.1e-3, 0.0}, {0.0, 0.0, -0.7e-3}};
}
std::vector<double> arms_radii() {
  return {1e-3, 0.7e-3, 0.6e-3, 0.5e-3};
}

TEST(Clumps, AddClumpKeepsTheSubSpheresWhereTheyWere) {
  SphereState s;
  ClumpSet k;
  const auto c = arms_centres();
  add_clump(s, k, c, arms_radii(), 2000.0, 0, "arms");
  ASSERT_EQ(s.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(s.position.x[i], c[i][0], 1e-15);
    EXPECT_NEAR(s.position.y[i], c[i][1], 1e-15);
    EXPECT_NEAR(s.position.z[i], c[i][2], 1e-15);
    EXPECT_EQ(s.mass[i], 0.0);  // the body carries the mass
    EXPECT_EQ(s.body[i], 0);
  }
  EXPECT_NEAR(k.mass[0], 2000.0 * k.volume[0], 1e-18);
  const Vector3& inertia = k.rotation[0].principal_inertia;
  EXPECT_LT(inertia[0], inertia[1]);
  EXPECT_LT(inertia[1], inertia[2]);
}

TEST(Clumps, SubSpheresOfOneClumpNeverTouchEachOther) {
  SphereState s;
  ClumpSet k;
  add_clump(s, k, arms_centres(), arms_radii(), 2000.0, 0, "arms");
  Engine engine(s, Box{}, rubber(), {}, EngineSettings{1e-6, {0, 0, 0}, 1e-4}, {}, k);
  engine.step();
  EXPECT_EQ(engine.sphere_contacts(), 0);  // they overlap by up to 0.4 mm
  EXPECT_EQ(engine.state().force.x, SphereArray<double>(4, 0.0));
}

TEST(Clumps, ABondOnAClumpSubSphereIsRefused) {
  SphereState s;
  ClumpSet k;
  add_clump(s, k, arms_centres(), arms_radii(), 2000.0, 0, "arms");
  BondSet bonds;
  bonds.first = {0};
  bonds.second = {1};
  for (auto* v :
       {&bonds.radius, &bonds.normal_spring, &bonds.shear_spring, &bonds.twist_spring,
        &bonds.bend_spring, &bonds.tensile_strength, &bonds.shear_strength, &bonds.damping_ratio})
    v->assign(1, 1.0);
  bonds.history.resize(1);
  bonds.intact = {1};
  EXPECT_THROW(Engine(s, Box{}, rubber(), {}, EngineSettings{1e-6, {0, 0, 0}, 1e-4}, bonds, k),
               InputError);
}

// The engine's clump integration on a free body: energy and angular momentum conserved to 1e-6
// over 1e5 steps (the principal-axis splitting is symplectic: the energy error stays bounded),
// and a spin near the intermediate axis flips (Dzhanibekov), as the bare integrator does
// (rigid_body_test.cpp). The centre moves at constant velocity.
TEST(Clumps, TorqueFreeClumpInTheEngineConservesEnergyAndAngularMomentum) {
  SphereState s;
  ClumpSet k;
  add_clump(s, k, arms_centres(), arms_radii(), 2000.0, 0, "arms");
  const Vector3 inertia = k.rotation[0].principal_inertia;
  // Spin mostly about the intermediate axis, a little about the others: unstable.
  const double omega = 50.0;  // rad/s
  k.rotation[0].body_angular_momentum = {1e-3 * omega * inertia[0], omega * inertia[1],
                                         1e-3 * omega * inertia[2]};
  k.velocity.x[0] = 0.01;
  const double dt = 1e-5;  // ω dt = 5e-4, as rigid_body_test.cpp
  Engine engine(s, Box{}, rubber(), {}, EngineSettings{dt, {0, 0, 0}, 1e-4}, {}, k);
  const double e0 = engine.energy().kinetic;
  const Vector3 l0 = angular_momentum(engine.clumps().rotation[0]);
  const double x0 = engine.clumps().centre.x[0];
  double worst_energy = 0.0, worst_momentum = 0.0;
  bool flipped = false;
  const int steps = 100000;
  for (int n = 0; n < steps; ++n) {
    engine.step();
    if (n % 100 != 0) continue;
    const RigidRotation& body = engine.clumps().rotation[0];
    worst_energy = std::max(worst_energy, std::abs(engine.energy().kinetic - e0) / e0);
    const Vector3 l = angular_momentum(body);
    worst_momentum =
        std::max(worst_momentum, norm({l[0] - l0[0], l[1] - l0[1], l[2] - l0[2]}) / norm(l0));
    flipped = flipped || body.body_angular_momentum[1] < -0.9 * omega * inertia[1];
  }
  EXPECT_LT(worst_energy, 1e-6);
  EXPECT_LT(worst_momentum, 1e-6);
  EXPECT_TRUE(flipped) << "no intermediate-axis flip in " << steps * dt << " s";
  EXPECT_NEAR(engine.clumps().centre.x[0] - x0, 0.01 * steps * dt, 1e-12);
  // Sub-spheres move with the body: v_i = v + ω × r_i.
  const Vector3 w = engine.clumps().angular_velocity(0);
  const SphereState& state = engine.state();
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Vector3 r = {state.position.x[i] - engine.clumps().centre.x[0],
                       state.position.y[i] - engine.clumps().centre.y[0],
                       state.position.z[i] - engine.clumps().centre.z[0]};
    EXPECT_NEAR(state.velocity.y[i], w[2] * r[0] - w[0] * r[2], 1e-9);
    EXPECT_EQ(state.angular_velocity.z[i], w[2]);
  }
}

}  // namespace
}  // namespace shapepress::simulate
