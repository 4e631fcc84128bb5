#include "geometry/signed_distance.hpp"

#include <gtest/gtest.h>

#include "geometry/random.hpp"

namespace shapepress::geometry {
namespace {

TEST(SignedDistance, SphereIsNegativeInsideAndExact) {
  const SignedDistance s = sphere_distance(2.0, Vec3(1, 0, 0));
  EXPECT_DOUBLE_EQ(s(Vec3(1, 0, 0)), -2.0);
  EXPECT_DOUBLE_EQ(s(Vec3(4, 0, 0)), 1.0);
  EXPECT_NEAR(s.gradient(Vec3(4, 0, 0), 1e-4).norm(), 1.0, 1e-6);  // a distance has |∇d| = 1
}

TEST(SignedDistance, EllipsoidDistanceIsEuclidean) {
  const Vec3 e(3.0, 2.0, 1.0);
  const SignedDistance s = ellipsoid_distance(e);
  // Beyond the end of an axis the closest point is that end.
  EXPECT_NEAR(s(Vec3(5, 0, 0)), 2.0, 1e-9);
  EXPECT_NEAR(s(Vec3(0, 0, 3)), 2.0, 1e-9);
  EXPECT_NEAR(s(Vec3(0, 0, 0)), -1.0, 1e-9);  // centre: depth = smallest semi-axis
  // Off-centre on the long axis the closest point leaves the plane z = 0 (degenerate case):
  // x = 9 * 0.5 / (9 - 1) = 0.5625, z = sqrt(1 - (0.5625/3)^2), distance sqrt(0.96875).
  EXPECT_NEAR(s(Vec3(0.5, 0, 0)), -std::sqrt(0.96875), 1e-9);
  // Against brute force: the minimum distance to dense surface points.
  Rng rng(7);
  std::vector<Vec3> surface;
  for (int i = 0; i < 200000; ++i)
    surface.push_back(random_direction(rng).cwiseProduct(e));
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 p = 4.0 * Vec3(uniform01(rng) - 0.5, uniform01(rng) - 0.5, uniform01(rng) - 0.5);
    double brute = 1e9;
    for (const Vec3& q : surface)
      brute = std::min(brute, (p - q).norm());
    // 200k points on an ellipsoid of area ~48: spacing ~0.015, so brute force overestimates
    // by at most ~0.01.
    EXPECT_NEAR(std::abs(s(p)), brute, 0.012) << p.transpose();
    EXPECT_LE(std::abs(s(p)), brute + 1e-9);
    EXPECT_EQ(s(p) < 0.0, p.cwiseQuotient(e).squaredNorm() < 1.0);
  }
}

TEST(SignedDistance, SurfaceSamplesLieOnTheSurface) {
  const SignedDistance s = ellipsoid_distance(Vec3(3.0, 2.0, 1.0));
  const auto samples = surface_samples(s, 32);
  ASSERT_GT(samples.size(), 500u);
  for (const Vec3& p : samples)
    EXPECT_NEAR(s(p), 0.0, 1e-3);  // two Newton steps from h/2
}

}  // namespace
}  // namespace shapepress::geometry
