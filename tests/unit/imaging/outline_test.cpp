// Outline geometry against shapes whose answers are known exactly, with ImageJ's definitions
// (area = pixel count, traced perimeter with the corner correction, Feret = hull calipers).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "imaging/measure.hpp"
#include "imaging/outline.hpp"

namespace shapepress::imaging {
namespace {

LabelImage label_image(int width, int height, const std::function<bool(int, int)>& inside) {
  LabelImage labels{width, height, 1, std::vector<std::int32_t>(width * height, 0)};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      labels.labels[y * width + x] = inside(x, y) ? 1 : 0;
  return labels;
}

TEST(Outline, SinglePixelIsAUnitSquare) {
  auto corners = trace_outline([](int x, int y) { return x == 3 && y == 4; }, 3, 4);
  ASSERT_EQ(corners.size(), 4u);
  EXPECT_DOUBLE_EQ(polygon_area(corners), 1.0);
}

TEST(Outline, AxisAlignedSquareMatchesImageJ) {
  // A 10×10 square: ImageJ reports Area 100, Perim. 4·10 − 4(2 − √2) = 37.657 (one corner
  // correction per corner), Feret 10√2, MinFeret 10, Solidity 1.
  LabelImage labels =
      label_image(20, 20, [](int x, int y) { return x >= 5 && x < 15 && y >= 5 && y < 15; });
  auto particles = measure_particles(labels);
  ASSERT_EQ(particles.size(), 1u);
  const ParticleMeasurement& m = particles[0];
  EXPECT_DOUBLE_EQ(m.area, 100.0);
  EXPECT_NEAR(m.perimeter, 40.0 - 4.0 * (2.0 - std::numbers::sqrt2), 1e-12);
  EXPECT_NEAR(m.feret.max, 10.0 * std::numbers::sqrt2, 1e-12);
  EXPECT_NEAR(m.feret.min, 10.0, 1e-12);
  // Both diagonals are maxima: either angle is right.
  EXPECT_TRUE(std::abs(m.feret.max_angle - 45.0) < 1e-9 ||
              std::abs(m.feret.max_angle - 135.0) < 1e-9)
      << m.feret.max_angle;
  EXPECT_DOUBLE_EQ(m.solidity, 1.0);
  EXPECT_NEAR(m.circularity, 4 * std::numbers::pi * 100 / std::pow(m.perimeter, 2), 1e-12);
  EXPECT_NEAR(m.centroid.x, 10.0, 1e-12);
  EXPECT_NEAR(m.centroid.y, 10.0, 1e-12);
  // Equal-area moment ellipse of a square is a circle of the same area.
  EXPECT_NEAR(m.ellipse_major, m.ellipse_minor, 1e-9);
  EXPECT_NEAR(std::numbers::pi / 4 * m.ellipse_major * m.ellipse_minor, 100.0, 1e-9);
}

TEST(Outline, RectangleFeretAndEllipseOrientation) {
  // 30 × 8 rectangle: Feret max = diagonal, min = 8 (short side), major axis along x (0°).
  LabelImage labels =
      label_image(40, 20, [](int x, int y) { return x >= 5 && x < 35 && y >= 6 && y < 14; });
  const ParticleMeasurement m = measure_particles(labels).at(0);
  EXPECT_NEAR(m.feret.max, std::hypot(30.0, 8.0), 1e-12);
  EXPECT_NEAR(m.feret.min, 8.0, 1e-12);
  EXPECT_NEAR(m.feret_imagej_ratio, 8.0 / std::hypot(30.0, 8.0), 1e-12);
  // ASR from the pixel-edge midpoints: a sharp corner is cut by half a pixel (0.25 px of the
  // 31 px diagonal), a shape corners in SEM images never have.
  EXPECT_NEAR(m.aspect_ratio, 8.0 / std::hypot(30.0, 8.0), 0.005);
  EXPECT_NEAR(m.feret.min_angle, 90.0, 1e-9);  // caliper across the short side is vertical
  EXPECT_NEAR(std::fmod(m.ellipse_angle, 180.0), 0.0, 1e-9);
}

TEST(Outline, LShapeSolidityAndConvexity) {
  // An L of three 10×10 squares: area 300, convex hull = 20×20 square minus a right triangle
  // of legs 10 → 350; solidity 300/350.
  LabelImage labels = label_image(30, 30, [](int x, int y) {
    bool in_box = x >= 5 && x < 25 && y >= 5 && y < 25;
    return in_box && !(x >= 15 && y < 15);
  });
  const ParticleMeasurement m = measure_particles(labels).at(0);
  EXPECT_DOUBLE_EQ(m.area, 300.0);
  EXPECT_NEAR(m.solidity, 300.0 / 350.0, 1e-12);
  EXPECT_LT(m.convexity, 1.0);
  EXPECT_GT(m.convexity, 0.8);
}

TEST(Outline, DiagonallyTouchingPixelsAreOneParticle) {
  // 8-connectivity, as ImageJ's wand: a diagonal staircase traces as one outline.
  auto inside = [](int x, int y) { return x >= 0 && x < 4 && y == x; };
  auto corners = trace_outline(inside, 0, 0);
  EXPECT_DOUBLE_EQ(polygon_area(corners), 4.0);
}

TEST(Outline, DigitalDiscIsNearlyRound) {
  // A disc of radius 25 px: circularity and ASR close to 1, area = pixel count.
  const double r = 25.0;
  int count = 0;
  LabelImage labels = label_image(64, 64, [&](int x, int y) {
    bool in = std::hypot(x + 0.5 - 32, y + 0.5 - 32) < r;
    count += in;
    return in;
  });
  const ParticleMeasurement m = measure_particles(labels).at(0);
  EXPECT_DOUBLE_EQ(m.area, count);
  EXPECT_NEAR(m.equivalent_diameter, 2 * r, 0.2);  // digitisation: area within ~1 %
  // ImageJ 1.53t measures this very disc (tests/data/imaging/shapes_imagej.csv, particle 1)
  // as Perim. 164.267, Circ. 0.920: the traced perimeter overestimates a digital circle.
  EXPECT_NEAR(m.perimeter, 164.267, 5e-4);
  EXPECT_NEAR(m.circularity, 0.920, 5e-4);
  EXPECT_GT(m.aspect_ratio, 0.97);  // hull of pixel corners: ±1 px in 51
  EXPECT_LT(m.fourier[2], 0.01);
}

TEST(Outline, RotatingCalipersOnARotatedRectangle) {
  // Exact rectangle 40 × 10 rotated by 30°: Feret max = diagonal, min = 10, min caliper
  // direction perpendicular to the long side.
  const double a = std::numbers::pi / 6;
  std::vector<Point2> corners;
  for (auto [u, v] : {std::pair{-20.0, -5.0}, {20.0, -5.0}, {20.0, 5.0}, {-20.0, 5.0}})
    corners.push_back({u * std::cos(a) - v * std::sin(a), u * std::sin(a) + v * std::cos(a)});
  Feret f = feret_diameters(convex_hull(corners));
  EXPECT_NEAR(f.max, std::hypot(40.0, 10.0), 1e-9);
  EXPECT_NEAR(f.min, 10.0, 1e-9);
  // y down: +30° on screen is −30° (150°) with y up; the short side's normal is at 60°.
  EXPECT_NEAR(f.min_angle, 60.0, 1e-6);
}

}  // namespace
}  // namespace shapepress::imaging
