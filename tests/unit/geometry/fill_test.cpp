#include <gtest/gtest.h>
#include "common/error.hpp"

#include <cmath>
#include <numbers>

#include "geometry/sphere_fill.hpp"
#include "geometry/template_quality.hpp"

namespace shapepress::geometry {
namespace {

TEST(BondedFill, HitsTheTargetCountWithTouchingNonOverlappingSpheres) {
  const SignedDistance shape = ellipsoid_distance(Vec3(1.0, 0.84, 0.8));
  BondedFillOptions options;
  options.target_count = 350;
  const SphereTemplate t = fill_bonded(shape, options);
  EXPECT_EQ(t.centres.size(), 350u);
  const double r = t.radii.front();
  double closest = 1e9;
  for (std::size_t i = 0; i < t.centres.size(); ++i) {
    EXPECT_LE(shape(t.centres[i]), -r + 1e-12);  // wholly inside
    for (std::size_t j = i + 1; j < t.centres.size(); ++j)
      closest = std::min(closest, (t.centres[i] - t.centres[j]).norm());
  }
  EXPECT_NEAR(closest, 2.0 * r, 1e-9 * r);  // lattice neighbours touch, none overlap
  EXPECT_TRUE(is_connected(t.centres.size(), t.bonds));
  // FCC interior spheres have 12 touching neighbours; Eq. 10 with m_b = 1.15 bonds exactly those.
  for (const Bond& b : t.bonds) {
    const double d =
        (t.centres[static_cast<std::size_t>(b[0])] - t.centres[static_cast<std::size_t>(b[1])])
            .norm();
    EXPECT_NEAR(d, 2.0 * r, 1e-9 * r);
  }
}

TEST(BondedFill, HcpAndFixedRadius) {
  const SignedDistance shape = sphere_distance(1.0);
  BondedFillOptions options;
  options.lattice = Lattice::hcp;
  options.sub_sphere_radius = 0.1;
  const SphereTemplate t = fill_bonded(shape, options);
  // Sphere of radius 0.9 for centres holds ~0.74 (0.9/0.1)^3 = 540 spheres: allow lattice and
  // boundary effects of ±15 %.
  EXPECT_GT(t.centres.size(), 460u);
  EXPECT_LT(t.centres.size(), 620u);
  for (double r : t.radii)
    EXPECT_DOUBLE_EQ(r, 0.1);
  EXPECT_TRUE(is_connected(t.centres.size(), t.bonds));
}

TEST(BondedFill, SameSeedSameTemplateOtherSeedOtherOrientation) {
  const SignedDistance shape = ellipsoid_distance(Vec3(1.0, 0.7, 0.5));
  BondedFillOptions options;
  options.target_count = 120;
  const SphereTemplate a = fill_bonded(shape, options), b = fill_bonded(shape, options);
  ASSERT_EQ(a.centres.size(), b.centres.size());
  for (std::size_t i = 0; i < a.centres.size(); ++i)
    EXPECT_EQ(a.centres[i], b.centres[i]);
  options.seed = 2;
  const SphereTemplate c = fill_bonded(shape, options);
  EXPECT_NE(a.centres.front(), c.centres.front());
}

TEST(BondedFill, RejectsBadOptions) {
  BondedFillOptions options;
  options.bond_multiplier = 1.5;
  EXPECT_THROW(options.check(), InputError);
  options = {};
  options.target_count = 0;
  EXPECT_THROW(options.check(), InputError);
}

TEST(Bonds, Equation10AndConnectivity) {
  const std::vector<Vec3> c = {{0, 0, 0}, {2.2, 0, 0}, {5, 0, 0}};
  const std::vector<double> r = {1.0, 1.0, 1.0};
  // |x0 - x1| = 2.2 < 2 * 1.15 = 2.3 bonds; |x1 - x2| = 2.8 does not.
  EXPECT_EQ(pairs_within(c, r, 1.15), (std::vector<Bond>{{0, 1}}));
  EXPECT_FALSE(is_connected(3, pairs_within(c, r, 1.15)));
  EXPECT_TRUE(is_connected(3, pairs_within(c, r, 1.41)));
  EXPECT_EQ(connected_components(3, {{0, 2}}), (std::vector<int>{0, 1, 0}));
}

TEST(MassProperties, UnionCountsOverlapsOnce) {
  // Two unit spheres at distance 1: union volume = 2 V - lens, lens = 5π/12 for d = r = 1.
  const std::vector<Vec3> c = {{0, 0, 0}, {1, 0, 0}};
  const std::vector<double> r = {1.0, 1.0};
  const MassProperties u = union_mass_properties(c, r, 160);
  const double exact = 2.0 * 4.0 / 3.0 * std::numbers::pi - 5.0 * std::numbers::pi / 12.0;
  EXPECT_NEAR(u.volume / exact, 1.0, 2e-3);  // midpoint voxels, 160 cells: ~0.1 % error
  EXPECT_NEAR(u.centre.x(), 0.5, 1e-3);
  const MassProperties sum = sphere_sum_mass_properties(c, r);
  EXPECT_GT(sum.volume / u.volume, 1.1);  // summing would count the lens twice
  // One sphere: I = 2/5 V r² about every axis.
  const MassProperties one = union_mass_properties({{0, 0, 0}}, {1.0}, 160);
  const double expected = 0.4 * (4.0 / 3.0 * std::numbers::pi);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(one.principal_moments[k] / expected, 1.0, 3e-3);
}

}  // namespace
}  // namespace shapepress::geometry
