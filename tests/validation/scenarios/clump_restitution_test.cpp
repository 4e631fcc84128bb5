// The restitution of rigid clumps (CMS) in head-on impacts against the input coefficient (issue
// 21, point 4): a clump's sub-sphere contact must damp with the bodies' masses, not with the
// clump's mass shared over its sub-spheres, or a collision of clumps of n sub-spheres rebounds
// with about √n times too little damping (models.md, "Damping of a clump's contacts").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <vector>

#include "scenes.hpp"
#include "simulate/clumps.hpp"

namespace shapepress::scenarios {
namespace {

using testing::one_material;

Vector3 cross(const Vector3& a, const Vector3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// A ball of radius R as a clump of `count` sub-spheres: one sphere of R for count = 1, else a
// core of 0.6 R and count - 1 shell spheres of 0.4 R centred 0.6 R out on Fibonacci directions,
// turned so that one shell sphere lies on +x (the impact axis): one sub-sphere takes the impact.
// Centres relative to the ball's centre.
std::vector<Vector3> ball_centres(int count, double radius, std::vector<double>& radii) {
  radii.clear();
  if (count == 1) {
    radii.push_back(radius);
    return {{0.0, 0.0, 0.0}};
  }
  const int shell = count - 1;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  std::vector<Vector3> directions;
  for (int i = 0; i < shell; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / shell;
    const double s = std::sqrt(1.0 - z * z);
    directions.push_back({s * std::cos(golden * i), s * std::sin(golden * i), z});
  }
  // Rodrigues' rotation taking directions[0] onto +x.
  const Vector3 a = directions[0], b = {1.0, 0.0, 0.0};
  const Vector3 k = cross(a, b);
  const double sine = std::sqrt(k[0] * k[0] + k[1] * k[1] + k[2] * k[2]);
  const double cosine = a[0];
  const Vector3 axis = {k[0] / sine, k[1] / sine, k[2] / sine};
  std::vector<Vector3> centres = {{0.0, 0.0, 0.0}};
  radii.push_back(0.6 * radius);
  for (const Vector3& d : directions) {
    const Vector3 kd = cross(axis, d);
    const double kdot = axis[0] * d[0] + axis[1] * d[1] + axis[2] * d[2];
    Vector3 r;
    for (int c = 0; c < 3; ++c)
      r[c] = d[c] * cosine + kd[c] * sine + axis[c] * kdot * (1.0 - cosine);
    centres.push_back({0.6 * radius * r[0], 0.6 * radius * r[1], 0.6 * radius * r[2]});
    radii.push_back(0.4 * radius);
  }
  return centres;
}

constexpr double ball_radius = 0.5e-3, impact_speed = 0.05;  // slow: the overlap stays ~1 % of R

// A step that resolves the impact of the smallest sub-spheres with 0.05 Rayleigh times (as the
// sphere restitution test, contact_physics_test.cpp).
double impact_time_step(const MaterialTable& table, int count) {
  return 0.25 * testing::default_time_step(table, count == 1 ? ball_radius : 0.4 * ball_radius);
}

// Runs until the bodies part; the relative normal speed after over before.
double rebound(Engine& engine, double approach, const std::function<double(const Engine&)>& gap) {
  bool touched = false;
  for (int k = 0; k < 400000; ++k) {
    engine.step();
    const bool touching = engine.sphere_contacts() + engine.wall_contacts() > 0;
    touched = touched || touching;
    if (touched && !touching) break;
  }
  EXPECT_TRUE(touched);
  return gap(engine) / approach;
}

// Clump A (n sub-spheres) at the origin moving +x, clump B (A turned half round, m sub-spheres,
// or a plain sphere when m = 0) 2R + 1 µm along x moving −x.
double clump_clump_restitution(double e, int n, int m) {
  const MaterialTable table = one_material(e, 0.5);
  SphereState s;
  ClumpSet clumps;
  std::vector<double> radii;
  const std::vector<Vector3> a = ball_centres(n, ball_radius, radii);
  add_clump(s, clumps, a, radii, 1541.0, 0, "a");
  const double offset = 2.0 * ball_radius + 1e-6;
  if (m > 0) {
    std::vector<Vector3> centres = ball_centres(m, ball_radius, radii);
    for (Vector3& c : centres)
      c = {offset - c[0], -c[1], c[2]};
    add_clump(s, clumps, centres, radii, 1541.0, 0, "b");
  } else {
    s.add_sphere(offset, 0.0, 0.0, ball_radius, 1541.0, 0);
    s.velocity.x[s.size() - 1] = -impact_speed;
  }
  clumps.velocity.x[0] = impact_speed;
  if (m > 0) clumps.velocity.x[1] = -impact_speed;
  const double dt = impact_time_step(table, std::max(n, m == 0 ? 1 : m));
  Engine engine(std::move(s), Box{}, table, {}, EngineSettings{dt, {0, 0, 0}, 0.05 * ball_radius},
                {}, std::move(clumps));
  return rebound(engine, 2.0 * impact_speed, [m](const Engine& en) {
    const double va = en.clumps().velocity.x[0];
    const double vb = m > 0 ? en.clumps().velocity.x[1] : en.state().velocity.x.back();
    return vb - va;
  });
}

// Clump of n sub-spheres falling (no gravity) onto a plate: one sub-sphere takes the impact.
double clump_wall_restitution(double e, int n) {
  const MaterialTable table = one_material(e, 0.5);
  SphereState s;
  ClumpSet clumps;
  std::vector<double> radii;
  std::vector<Vector3> centres = ball_centres(n, ball_radius, radii);
  for (Vector3& c : centres)  // the +x sub-sphere turned to −z, the ball just above the plate
    c = {c[2], c[1], ball_radius + 1e-6 - c[0]};
  add_clump(s, clumps, centres, radii, 1541.0, 0, "a");
  clumps.velocity.z[0] = -impact_speed;
  Engine engine(std::move(s), Box{}, table, {PlaneWall{0.0, 1, 0.0, 0}},
                EngineSettings{impact_time_step(table, n), {0, 0, 0}, 0.05 * ball_radius}, {},
                std::move(clumps));
  return rebound(engine, impact_speed, [](const Engine& en) { return en.clumps().velocity.z[0]; });
}

TEST(ClumpRestitution, HeadOnClumpImpactsGiveTheInputCoefficient) {
  // Table 4's Avicel restitution and a lively one. Tolerance 3 %: the law is exact for one
  // contact in continuous time (the sphere test holds 1 %); a clump's impact point sits off its
  // centre of mass by the union's asymmetry (< 1 % of R here), which turns a little of the
  // rebound into spin.
  for (double e : {0.352, 0.7}) {
    for (int n : {1, 13, 89}) {
      const double clumps = clump_clump_restitution(e, n, n);
      const double sphere = clump_clump_restitution(e, n, 0);
      const double wall = clump_wall_restitution(e, n);
      std::printf("e = %.3f, n = %2d: clump-clump %.4f, clump-sphere %.4f, clump-wall %.4f\n", e, n,
                  clumps, sphere, wall);
      EXPECT_NEAR(clumps / e, 1.0, 0.03) << "clump-clump, n = " << n;
      EXPECT_NEAR(sphere / e, 1.0, 0.03) << "clump-sphere, n = " << n;
      EXPECT_NEAR(wall / e, 1.0, 0.03) << "clump-wall, n = " << n;
    }
  }
}

}  // namespace
}  // namespace shapepress::scenarios
