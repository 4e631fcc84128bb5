// Fourier descriptors (Mollon & Zhao normalisation) on outlines with known spectra.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "imaging/fourier.hpp"
#include "imaging/measure.hpp"

namespace shapepress::imaging {
namespace {

std::vector<Point2> star_polygon(const std::function<double(double)>& r, int n = 2000) {
  std::vector<Point2> polygon;
  for (int k = 0; k < n; ++k) {
    double t = 2 * std::numbers::pi * k / n;
    polygon.push_back({r(t) * std::cos(t), r(t) * std::sin(t)});
  }
  return polygon;
}

TEST(Fourier, DiscHasNoHarmonics) {
  double r0 = 0;
  auto d =
      fourier_descriptors(radius_function(star_polygon([](double) { return 10.0; }), {0, 0}), &r0);
  EXPECT_NEAR(r0, 10.0, 1e-3);  // chord sag of a 2000-gon
  EXPECT_DOUBLE_EQ(d[0], 1.0);
  for (int n = 1; n <= fourier_max_order; ++n)
    EXPECT_LT(d[n], 1e-5) << "n = " << n;
}

TEST(Fourier, SingleHarmonicIsRecovered) {
  // r = 20 (1 + 0.1 cos(3θ + 0.4) + 0.02 cos(8θ)): D3 = 0.1, D8 = 0.02, the rest zero.
  auto r = [](double t) {
    return 20.0 * (1 + 0.1 * std::cos(3 * t + 0.4) + 0.02 * std::cos(8 * t));
  };
  double r0 = 0;
  auto d = fourier_descriptors(radius_function(star_polygon(r), {0, 0}), &r0);
  EXPECT_NEAR(r0, 20.0, 1e-3);
  EXPECT_NEAR(d[3], 0.1, 1e-4);  // polygon chords: error O(1/n²)
  EXPECT_NEAR(d[8], 0.02, 1e-4);
  EXPECT_LT(d[2], 1e-4);
  EXPECT_LT(d[5], 1e-4);
}

TEST(Fourier, EllipseD2MatchesTheRadiusFunctionIntegral) {
  // Ellipse a = 2, b = 1: D2 = 2|c2|/c0 of r(θ) = ab/√(b²cos²θ + a²sin²θ), integrated here
  // independently with 100000 midpoint samples.
  const double a = 2.0, b = 1.0;
  auto r = [&](double t) { return a * b / std::hypot(b * std::cos(t), a * std::sin(t)); };
  double c0 = 0, c2 = 0;
  const int n = 100000;
  for (int k = 0; k < n; ++k) {
    double t = 2 * std::numbers::pi * (k + 0.5) / n;
    c0 += r(t) / n;
    c2 += r(t) * std::cos(2 * t) / n;
  }
  const double analytic = 2 * std::abs(c2) / c0;
  auto d = fourier_descriptors(radius_function(star_polygon(r), {0, 0}), nullptr);
  EXPECT_NEAR(d[2], analytic, 1e-3 * analytic);  // 256 samples of a smooth function
  EXPECT_GT(analytic, 0.3);                      // guards the test itself: a real elongation
}

TEST(Fourier, ReentrantOutlineKeepsTheOuterEnvelope) {
  // A ray that crosses a polygon several times takes the farthest crossing: an L-shape's
  // radius never drops into the notch.
  std::vector<Point2> l_shape = {{-1, -1}, {1, -1}, {1, 0}, {0, 0}, {0, 1}, {-1, 1}};
  auto r = radius_function(l_shape, {-0.5, -0.5}, 64);
  for (double v : r)
    EXPECT_GT(v, 0.0);
}

}  // namespace
}  // namespace shapepress::imaging
