// A body's volume in a bed (docs/models.md, "A body's volume"): the union of its sub-spheres
// closed by a ball of their median radius. One sphere is its own body; two touching spheres get
// the neck a neighbour of their size cannot enter (its volume by Pappus); the closing
// scales as the body does; the inertia is about the body origin.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "geometry/template_quality.hpp"
#include "geometry/templates_file.hpp"

namespace shapepress::geometry {
namespace {

constexpr double pi = std::numbers::pi;

TEST(BodyVolume, OneSphereIsItsOwnBody) {
  SphereTemplate one;
  one.centres = {Vec3::Zero()};
  one.radii = {2e-5};
  double probe = 0.0;
  const MassProperties m = body_mass_properties(one, &probe);
  const double volume = 4.0 / 3.0 * pi * 8e-15;
  EXPECT_NEAR(m.volume, volume, 1e-12 * volume);
  EXPECT_NEAR(m.inertia(0, 0), 0.4 * volume * 4e-10, 1e-12 * 0.4 * volume * 4e-10);
  EXPECT_EQ(probe, 2e-5);
  // The voxel closing of the same sphere, on its own grid, within a per cent.
  const MassProperties voxel = closed_union_mass_properties(one.centres, one.radii, 2e-5);
  EXPECT_NEAR(voxel.volume, volume, 0.01 * volume);
}

TEST(BodyVolume, TwoTouchingSpheresGetTheirNeckAndNoMore) {
  const double r = 1e-5;
  const std::vector<Vec3> centres = {Vec3(-r, 0, 0), Vec3(r, 0, 0)};
  const std::vector<double> radii = {r, r};
  const double spheres = 2.0 * 4.0 / 3.0 * pi * r * r * r;
  const double capsule = 4.0 / 3.0 * pi * r * r * r + pi * r * r * 2.0 * r;
  const MassProperties open = union_mass_properties(centres, radii, 160);
  const MassProperties closed = closed_union_mass_properties(centres, radii, r);
  EXPECT_NEAR(open.volume, spheres, 0.01 * spheres);
  // A probe of radius r touching both spheres has its centre √3 r off the axis, so the neck it
  // cannot enter is, in a plane through the axis, the equilateral triangle of the three centres
  // (side 2r) less its three 60° sectors: area (√3 − π/2) r², centroid r/√3 off the axis
  // (the triangle's, by symmetry). Swept about the axis (Pappus): 2π r³ (1 − π/(2√3)).
  const double neck = 2.0 * pi * r * r * r * (1.0 - pi / (2.0 * std::sqrt(3.0)));
  EXPECT_NEAR(closed.volume, spheres + neck, 0.01 * (spheres + neck));
  EXPECT_LT(closed.volume, capsule);
  // A larger probe fills more of the neck.
  EXPECT_GT(closed_union_mass_properties(centres, radii, 3.0 * r).volume, closed.volume);
  // The closing scales with the body: ×2 in size, ×8 in volume.
  std::vector<Vec3> twice = centres;
  for (Vec3& c : twice)
    c *= 2.0;
  const MassProperties large = closed_union_mass_properties(twice, {2.0 * r, 2.0 * r}, 2.0 * r);
  EXPECT_NEAR(large.volume / closed.volume, 8.0, 0.08);
}

TEST(BodyVolume, InertiaIsAboutTheBodyOrigin) {
  // Two touching spheres about the origin at their contact: the body's inertia about the axis
  // through both centres is smaller than about the axes across it, by the capsule's shape.
  const double r = 1e-5;
  SphereTemplate pair;
  pair.centres = {Vec3(-r, 0, 0), Vec3(r, 0, 0)};
  pair.radii = {r, r};
  const MassProperties m = body_mass_properties(pair);
  EXPECT_LT(m.inertia(0, 0), m.inertia(1, 1));
  EXPECT_NEAR(m.inertia(1, 1), m.inertia(2, 2), 0.01 * m.inertia(1, 1));
  EXPECT_EQ(m.inertia(0, 1), 0.0);
  // Moved off the origin by d along y, the same spheres' inertia about x grows by V d².
  SphereTemplate moved = pair;
  const double d = 3e-5;
  for (Vec3& c : moved.centres)
    c.y() += d;
  const MassProperties off = body_mass_properties(moved);
  EXPECT_NEAR(off.inertia(0, 0) - m.inertia(0, 0), off.volume * d * d, 0.01 * off.volume * d * d);
}

}  // namespace
}  // namespace shapepress::geometry
