#pragma once
// Curves y(x) sampled at increasing x, and the comparisons convergence and speed–accuracy
// charts are made of: interpolation, resampling, RMS and maximum relative error between two
// curves over an x-range, and the spread of a family of curves.
#include <string>
#include <vector>

namespace shapepress::analysis {

struct Curve {
  std::vector<double> x;  // strictly increasing after check()
  std::vector<double> y;
  std::string label;
  // InputError naming the label when sizes differ, fewer than 2 points, or x not increasing.
  void check() const;
};

// Linear interpolation; outside [x.front(), x.back()] the end value is held (no extrapolation).
double interpolate(const Curve& curve, double x);

// The part of a curve where x is strictly increasing from the start up to its largest x (a
// loading branch out of a load–unload record); equal x values keep the last sample.
Curve monotone_prefix(const Curve& curve);

// n equally spaced x values from lower to upper (n ≥ 2).
std::vector<double> linear_grid(double lower, double upper, int n);
Curve resample(const Curve& curve, const std::vector<double>& grid);

struct CurveDifference {
  double rms_relative = 0.0;  // √(mean over the grid of ((y − y_ref)/y_ref)²)
  double max_relative = 0.0;  // max over the grid of |y − y_ref|/|y_ref|
  double rms_absolute = 0.0;  // √(mean over the grid of (y − y_ref)²), in y's unit
  double at_max_x = 0.0;      // x where the relative error is largest
  int points = 0;             // grid points used (those with y_ref ≠ 0)
};

// Compares `curve` with `reference` on `points` equally spaced x values over [lower, upper]
// (which must lie inside both curves' x ranges); points where the reference is zero are skipped
// for the relative errors.
CurveDifference compare_curves(const Curve& curve, const Curve& reference, double lower,
                               double upper, int points = 200);

// Spread of a family of curves at x: (max − min)/mean of the interpolated values — how far
// apart seeds or resolutions are, for convergence charts.
double spread_at(const std::vector<Curve>& family, double x);
std::vector<double> spread_at(const std::vector<Curve>& family, const std::vector<double>& xs);

}  // namespace shapepress::analysis
