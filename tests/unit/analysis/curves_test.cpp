#include "analysis/curves.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.hpp"

namespace shapepress::analysis {
namespace {

Curve sampled(double (*f)(double), double lower, double upper, int n, std::string label = "f") {
  Curve c{linear_grid(lower, upper, n), {}, std::move(label)};
  for (double x : c.x)
    c.y.push_back(f(x));
  return c;
}

TEST(Curves, InterpolationIsExactOnLinesAndHoldsEndValues) {
  const Curve line{{0.0, 1.0, 3.0}, {1.0, 3.0, 7.0}, "2x+1"};
  EXPECT_DOUBLE_EQ(interpolate(line, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(interpolate(line, 2.0), 5.0);
  EXPECT_DOUBLE_EQ(interpolate(line, 3.0), 7.0);
  EXPECT_DOUBLE_EQ(interpolate(line, -1.0), 1.0);  // no extrapolation
  EXPECT_DOUBLE_EQ(interpolate(line, 9.0), 7.0);
}

TEST(Curves, ResamplingErrorShrinksQuadraticallyWithSpacing) {
  auto f = [](double x) { return std::sin(x); };
  const std::vector<double> fine = linear_grid(0.0, 3.0, 301);
  double previous = 0.0;
  for (int n : {11, 21, 41}) {
    const Curve coarse = sampled(+f, 0.0, 3.0, n);
    const Curve r = resample(coarse, fine);
    double worst = 0.0;
    for (std::size_t i = 0; i < fine.size(); ++i)
      worst = std::max(worst, std::abs(r.y[i] - std::sin(fine[i])));
    // Linear interpolation error ≤ h²/8 max|f''| = h²/8 for sin.
    const double h = 3.0 / (n - 1);
    EXPECT_LE(worst, h * h / 8.0 + 1e-15);
    if (previous > 0.0) {
      EXPECT_NEAR(previous / worst, 4.0, 0.4);  // halving h quarters it
    }
    previous = worst;
  }
}

TEST(Curves, CompareGivesKnownRelativeErrors) {
  // y = 1.1 x against y_ref = x: 10 % everywhere; y = x(1 + 0.1 x) on [1, 2]: max 20 % at x = 2.
  const Curve ref = sampled([](double x) { return x; }, 0.0, 2.0, 21, "ref");
  const Curve scaled = sampled([](double x) { return 1.1 * x; }, 0.0, 2.0, 21, "scaled");
  CurveDifference d = compare_curves(scaled, ref, 0.0, 2.0, 101);
  EXPECT_NEAR(d.rms_relative, 0.1, 1e-12);
  EXPECT_NEAR(d.max_relative, 0.1, 1e-12);
  EXPECT_EQ(d.points, 100);  // x = 0 has y_ref = 0 and is skipped
  const Curve bent = sampled([](double x) { return x * (1 + 0.1 * x); }, 0.0, 2.0, 201, "bent");
  d = compare_curves(bent, ref, 1.0, 2.0, 101);
  EXPECT_NEAR(d.max_relative, 0.2, 1e-9);  // bent is sampled finely but interpolated linearly
  EXPECT_NEAR(d.at_max_x, 2.0, 1e-12);
  // mean of (0.1 x)² over [1, 2] = 0.01·7/3; the 101-point grid is a trapezoid-like mean.
  EXPECT_NEAR(d.rms_relative, std::sqrt(0.01 * 7.0 / 3.0), 2e-3);
  EXPECT_THROW(compare_curves(bent, ref, 1.0, 3.0), InputError);  // outside both curves
}

TEST(Curves, SpreadOfAFamilyIsMaxMinusMinOverMean) {
  const std::vector<Curve> family = {{{0.0, 1.0}, {0.0, 9.0}, "a"},
                                     {{0.0, 1.0}, {0.0, 10.0}, "b"},
                                     {{0.0, 1.0}, {0.0, 11.0}, "c"}};
  EXPECT_NEAR(spread_at(family, 1.0), 0.2, 1e-12);  // (11 − 9)/10
  EXPECT_NEAR(spread_at(family, 0.5), 0.2, 1e-12);  // scaled family: same spread everywhere
  EXPECT_EQ(spread_at(family, 0.0), 0.0);           // zero mean: reported as no spread
  const std::vector<double> s = spread_at(family, std::vector<double>{0.25, 1.0});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_NEAR(s[0], 0.2, 1e-12);
}

TEST(Curves, MonotonePrefixStopsWhereTheCurveTurnsBack) {
  const Curve load_unload{{0.0, 1.0, 2.0, 2.0, 1.5, 1.0}, {0, 1, 4, 5, 2, 0}, "cycle"};
  const Curve prefix = monotone_prefix(load_unload);
  ASSERT_EQ(prefix.x.size(), 3u);
  EXPECT_DOUBLE_EQ(prefix.y.back(), 5.0);  // the repeated x keeps its last value
  EXPECT_NO_THROW(prefix.check());
}

TEST(Curves, CheckNamesTheBadCurve) {
  const Curve bad{{0.0, 1.0, 1.0}, {0.0, 1.0, 2.0}, "repeated-x"};
  try {
    bad.check();
    FAIL() << "a repeated x must be rejected";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("repeated-x"), std::string::npos);
  }
  EXPECT_THROW((Curve{{0.0}, {1.0}, "short"}.check()), InputError);
  EXPECT_THROW((Curve{{0.0, 1.0}, {1.0}, "sizes"}.check()), InputError);
}

}  // namespace
}  // namespace shapepress::analysis
