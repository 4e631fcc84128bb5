#pragma once
// Curves y(x) sampled at increasing x, and the comparisons convergence and speed–accuracy
// charts are made of: interpolation, resampling, RMS and maximum relative error between two
// curves over an x-range, and the spread of a family of curves.
#include <cstddef>
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

// What a load–unload record left (a plate rig's, a FEM's): the largest force, and where the
// unloading force fell to zero (the plates left the particle). That is the zero of the secant
// through the last two unloading rows with force, kept within the increment before the first row
// without; b itself when one unloading row has force only; NaN when no unloading row is without
// force (not unloaded, or stopped before the plates let go). Rows from `first_unloading` on are
// the unloading's, the row before it the loading's last; a force at most 1e-9 of the peak is none
// (a curve read from CalculiX carries round-off where nothing touches). A purely elastic particle
// leaves 0 within that increment, a plastic one its permanent flattening.
struct UnloadingResidual {
  double peak_force = 0.0;            // [N]
  double residual_approach = 0.0;     // [m]
  double residual_deformation = 0.0;  // residual approach over the height
  double resolution = 0.0;            // the increment it lies in, in deformation
};
UnloadingResidual unloading_residual(const std::vector<double>& deformation,
                                     const std::vector<double>& approach,
                                     const std::vector<double>& force, std::size_t first_unloading);

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
