// Compaction metrics on synthetic punch curves built from known laws, so every fitted number has
// an exact expected value.
#include "analysis/compaction.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "common/error.hpp"

namespace shapepress::analysis {
namespace {

constexpr double die_area = 1e-4;      // m²
constexpr double solid_height = 4e-3;  // V_solid / A_die [m]: D = solid_height / H

// A loading branch from stress 0 to p_max whose solid fraction follows `law(P)`.
PunchCurve loading_curve(const std::function<double(double)>& solid_fraction, double p_max,
                         int rows = 200) {
  PunchCurve c;
  for (int i = 0; i < rows; ++i) {
    const double p = p_max * i / (rows - 1);
    const double d = solid_fraction(p);
    c.time.push_back(1e-4 * i);
    c.stress.push_back(p);
    c.top_force.push_back(p * die_area);
    c.solid_fraction.push_back(d);
    c.gap.push_back(solid_height / d);
    c.phase.push_back(0);
  }
  c.reference_gap = c.gap.front();
  c.die_area = die_area;
  return c;
}

TEST(Compaction, HeckelFitRecoversKAndAOfAnExactHeckelCurve) {
  const double k = 1.0 / 50e6, a = 0.5;  // Py = 50 MPa
  const PunchCurve c = loading_curve([&](double p) { return 1.0 - std::exp(-(k * p + a)); }, 100e6);
  const CompactionMetrics m = analyse_compaction(c);
  // The data are exactly linear in (P, ln 1/(1−D)): only rounding separates fit and truth.
  EXPECT_NEAR(m.heckel.k, k, 1e-9 * k);
  EXPECT_NEAR(m.heckel.a, a, 1e-9);
  EXPECT_NEAR(m.heckel.yield_pressure, 50e6, 1e-9 * 50e6);
  EXPECT_NEAR(m.heckel.r_squared, 1.0, 1e-12);
  // The default window is 30–100 % of the peak stress.
  EXPECT_NEAR(m.heckel.stress_lower, 30e6, 100e6 / 199);  // one grid step
  EXPECT_DOUBLE_EQ(m.heckel.stress_upper, 100e6);
}

TEST(Compaction, HeckelWindowSkipsTheCurvedRearrangementPart) {
  const double k = 1.0 / 80e6, a = 0.6;
  // Below 20 MPa the powder rearranges (a steeper, curved law); above it is Heckel-linear.
  auto law = [&](double p) {
    const double linear = k * p + a;
    const double extra = p < 20e6 ? 0.2 * std::pow(1.0 - p / 20e6, 2) : 0.0;
    return 1.0 - std::exp(-(linear - extra));
  };
  const PunchCurve c = loading_curve(law, 100e6);
  const CompactionMetrics m = analyse_compaction(c);  // window starts at 30 MPa
  EXPECT_NEAR(m.heckel.k, k, 1e-9 * k);
  EXPECT_NEAR(m.heckel.a, a, 1e-9);
  // A window reaching into the curved part must see it: the fit is measurably worse.
  const HeckelFit wide = fit_heckel(c, 0.0, 100e6);
  EXPECT_GT(std::abs(wide.k - k), 1e-3 * k);
  EXPECT_LT(wide.r_squared, m.heckel.r_squared);
}

TEST(Compaction, KawakitaFitRecoversAAndBOfAnExactKawakitaCurve) {
  const double a = 0.4, b = 1.0 / 20e6;
  const double h0 = 10e-3;
  // C = a b P/(1 + b P) (Kawakita), H = H0 (1 − C), D = solid_height/H.
  auto law = [&](double p) { return solid_height / (h0 * (1.0 - a * b * p / (1.0 + b * p))); };
  const PunchCurve c = loading_curve(law, 150e6);
  ASSERT_NEAR(c.reference_gap, h0, 1e-15);
  const CompactionMetrics m = analyse_compaction(c);
  EXPECT_NEAR(m.kawakita.a, a, 1e-9);  // exact data: rounding only
  EXPECT_NEAR(m.kawakita.b, b, 1e-8 * b);
  EXPECT_NEAR(m.kawakita.r_squared, 1.0, 1e-12);
  EXPECT_GE(m.kawakita.stress_lower, 0.05 * 150e6);  // the default window's lower end
}

// Linear loading F = k (H0 − H) to H_min, a hold, then a linear elastic unloading to H_u.
PunchCurve load_hold_unload(double h0, double h_min, double h_unloaded, double stiffness) {
  PunchCurve c;
  c.reference_gap = h0;
  c.die_area = die_area;
  auto add = [&](double h, double f, int phase) {
    c.time.push_back(1e-4 * static_cast<double>(c.time.size()));
    c.gap.push_back(h);
    c.top_force.push_back(f);
    c.stress.push_back(f / die_area);
    c.solid_fraction.push_back(solid_height / h);
    c.phase.push_back(phase);
  };
  const double f_max = stiffness * (h0 - h_min);
  for (int i = 0; i <= 100; ++i) {
    const double h = h0 - (h0 - h_min) * i / 100.0;
    add(h, stiffness * (h0 - h), 0);
  }
  for (int i = 0; i < 10; ++i)
    add(h_min, f_max, 1);
  for (int i = 1; i <= 50; ++i) {
    const double h = h_min + (h_unloaded - h_min) * i / 50.0;
    add(h, f_max * (h_unloaded - h) / (h_unloaded - h_min), 2);
  }
  add(h_unloaded, 0.0, 3);
  return c;
}

TEST(Compaction, PeakRecoveryAndWorkOfALinearLoadUnloadCycle) {
  const double h0 = 10e-3, h_min = 7e-3, h_u = 7.3e-3, stiffness = 2e6;  // N/m
  const PunchCurve c = load_hold_unload(h0, h_min, h_u, stiffness);
  const CompactionMetrics m = analyse_compaction(c);
  const double f_max = stiffness * (h0 - h_min);
  EXPECT_DOUBLE_EQ(m.peak_force, f_max);
  EXPECT_DOUBLE_EQ(m.peak_stress, f_max / die_area);
  EXPECT_DOUBLE_EQ(m.minimum_gap, h_min);
  EXPECT_NEAR(m.strain_at_peak, 0.3, 1e-12);
  EXPECT_NEAR(m.solid_fraction_at_peak, solid_height / h_min, 1e-12);
  ASSERT_TRUE(m.unloaded);
  EXPECT_DOUBLE_EQ(m.unloaded_gap, h_u);
  EXPECT_NEAR(m.elastic_recovery, (h_u - h_min) / h_min, 1e-12);
  // Trapezoids integrate piecewise-linear F(H) exactly: triangle areas.
  EXPECT_NEAR(m.work_of_compaction, 0.5 * f_max * (h0 - h_min), 1e-12 * f_max * h0);
  EXPECT_NEAR(m.work_of_unloading, 0.5 * f_max * (h_u - h_min), 1e-12 * f_max * h0);
}

TEST(Compaction, NoUnloadPhaseMeansNoRecovery) {
  const PunchCurve c =
      loading_curve([](double p) { return 1.0 - std::exp(-(p / 40e6 + 0.5)); }, 80e6);
  const CompactionMetrics m = analyse_compaction(c);
  EXPECT_FALSE(m.unloaded);
  EXPECT_GT(m.work_of_compaction, 0.0);
  EXPECT_EQ(m.work_of_unloading, 0.0);
}

TEST(Compaction, LineFitOfNoisyDataHasRSquaredBelowOne) {
  const std::vector<double> x = {0, 1, 2, 3, 4}, y = {1, 3.2, 4.9, 7.1, 9.0};
  const LinearFit f = fit_line(x, y);
  EXPECT_NEAR(f.slope, 2.0, 0.05);  // the points scatter ±0.2 around y = 2x + 1
  EXPECT_NEAR(f.intercept, 1.0, 0.2);
  EXPECT_LT(f.r_squared, 1.0);
  EXPECT_GT(f.r_squared, 0.99);
  EXPECT_THROW(fit_line({1, 1, 1}, {1, 2, 3}), ComputationError);
}

TEST(Compaction, BadCurvesAndWindowsAreInputErrors) {
  PunchCurve c = load_hold_unload(10e-3, 7e-3, 7.3e-3, 2e6);
  c.reference_gap = 0.0;
  EXPECT_THROW(analyse_compaction(c), InputError);
  c = load_hold_unload(10e-3, 7e-3, 7.3e-3, 2e6);
  c.stress.pop_back();
  EXPECT_THROW(analyse_compaction(c), InputError);
  c = load_hold_unload(10e-3, 7e-3, 7.3e-3, 2e6);
  EXPECT_THROW(analyse_compaction(c, FitWindows{0.5, 0.4, 0.05, 1.0}), InputError);
  EXPECT_THROW(analyse_compaction(c, FitWindows{0.3, 1.0, 0.05, 1.5}), InputError);
}

}  // namespace
}  // namespace shapepress::analysis
