#include "geometry/descriptors.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "geometry/icosphere.hpp"
#include "geometry/random.hpp"

namespace shapepress::geometry {
namespace {

TEST(Descriptors, BoxOfARotatedEllipsoidGivesItsAxes) {
  TriangleMesh m = ellipsoid_mesh(Vec3(3.0, 2.0, 1.0), 4);
  Rng rng(3);
  const Mat3 rotation = random_rotation(rng);
  for (Vec3& v : m.vertices)
    v = rotation * v;
  const ShapeDescriptors d = describe(m);
  // Vertices lie on the ellipsoid; the box touches its extreme points within the mesh's
  // resolution (level 4: ~2 % of the radius between vertices).
  EXPECT_NEAR(d.L_m, 6.0, 0.03);
  EXPECT_NEAR(d.I_m, 4.0, 0.03);
  EXPECT_NEAR(d.S_m, 2.0, 0.03);
  EXPECT_NEAR(d.asr, 1.0 / 3.0, 0.01);
  EXPECT_NEAR(d.elongation, 2.0 / 3.0, 0.01);
  EXPECT_NEAR(d.flatness, 0.5, 0.01);
  EXPECT_NEAR(d.convexity, 1.0, 1e-9);  // a convex mesh is its own hull
  EXPECT_LT(d.sphericity, 1.0);
}

TEST(Descriptors, SphereIsRoundFromEveryDirection) {
  const ShapeDescriptors d = describe(icosphere(4));
  EXPECT_NEAR(d.sphericity, 1.0, 0.01);
  EXPECT_NEAR(d.asr, 1.0, 0.02);
  EXPECT_EQ(d.projected_asr.size(), 64u);
  for (double a : d.projected_asr)
    EXPECT_NEAR(a, 1.0, 0.02);                                // polyhedral silhouette
  EXPECT_NEAR(d.projected_equivalent_diameter_m, 2.0, 0.01);  // Cauchy: sqrt(A/π)
}

TEST(Descriptors, FeretOfASquareSilhouette) {
  // A 1 x 2 x 10 box seen along its long axis: a 1 x 2 rectangle, Feret min 1, max sqrt(5).
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i)
    corners.emplace_back(i & 1 ? 1.0 : 0.0, i & 2 ? 2.0 : 0.0, i & 4 ? 10.0 : 0.0);
  const Feret f = projected_feret(corners, Vec3::UnitZ());
  EXPECT_NEAR(f.min, 1.0, 1e-12);
  EXPECT_NEAR(f.max, std::sqrt(5.0), 1e-12);
}

TEST(Descriptors, ProjectedAsrOfAnEllipsoidIsAboveItsBoxAsr) {
  // Silhouettes of an ellipsoid are ellipses with axis ratio between S/L and 1: the projected
  // ASR an image measures is larger than the 3D ASR, which is why the generator calibrates it.
  const ShapeDescriptors d = describe(ellipsoid_mesh(Vec3(1.0, 0.7, 0.5), 4), {256, 5});
  for (double a : d.projected_asr)
    EXPECT_GE(a, 0.5 - 0.01);
  EXPECT_GT(d.projected_asr_mean, d.asr + 0.1);
}

TEST(Descriptors, DeterministicForASeed) {
  TriangleMesh m = ellipsoid_mesh(Vec3(1.0, 0.8, 0.6), 3);
  const ShapeDescriptors a = describe(m, {16, 9}), b = describe(m, {16, 9});
  EXPECT_EQ(a.L_m, b.L_m);
  EXPECT_EQ(a.projected_asr, b.projected_asr);
}

}  // namespace
}  // namespace shapepress::geometry
