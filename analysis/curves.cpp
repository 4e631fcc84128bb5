#include "analysis/curves.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "common/error.hpp"

namespace shapepress::analysis {

void Curve::check() const {
  if (x.size() != y.size())
    throw InputError(
        fmt::format("curve '{}': {} x values but {} y values", label, x.size(), y.size()));
  if (x.size() < 2)
    throw InputError(fmt::format("curve '{}': {} points, at least 2 needed", label, x.size()));
  for (std::size_t i = 1; i < x.size(); ++i)
    if (!(x[i] > x[i - 1]))
      throw InputError(fmt::format("curve '{}': x not increasing at point {} ({} after {})", label,
                                   i, x[i], x[i - 1]));
}

double interpolate(const Curve& curve, double x) {
  const auto& xs = curve.x;
  if (x <= xs.front()) return curve.y.front();
  if (x >= xs.back()) return curve.y.back();
  const auto upper = std::upper_bound(xs.begin(), xs.end(), x);
  const std::size_t i = static_cast<std::size_t>(upper - xs.begin());
  const double t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  return curve.y[i - 1] + t * (curve.y[i] - curve.y[i - 1]);
}

Curve monotone_prefix(const Curve& curve) {
  Curve prefix{{}, {}, curve.label};
  for (std::size_t i = 0; i < curve.x.size(); ++i) {
    if (!prefix.x.empty() && curve.x[i] < prefix.x.back()) break;  // turned back: unloading
    if (!prefix.x.empty() && curve.x[i] == prefix.x.back()) {
      prefix.y.back() = curve.y[i];
      continue;
    }
    prefix.x.push_back(curve.x[i]);
    prefix.y.push_back(curve.y[i]);
  }
  return prefix;
}

std::vector<double> linear_grid(double lower, double upper, int n) {
  if (n < 2) throw InputError(fmt::format("grid of {} points: at least 2 needed", n));
  std::vector<double> grid(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    grid[static_cast<std::size_t>(i)] = lower + (upper - lower) * i / (n - 1);
  return grid;
}

Curve resample(const Curve& curve, const std::vector<double>& grid) {
  Curve out{grid, {}, curve.label};
  out.y.reserve(grid.size());
  for (double x : grid)
    out.y.push_back(interpolate(curve, x));
  return out;
}

CurveDifference compare_curves(const Curve& curve, const Curve& reference, double lower,
                               double upper, int points) {
  curve.check();
  reference.check();
  const double slack = 1e-9 * (upper - lower);
  for (const Curve* c : {&curve, &reference})
    if (lower < c->x.front() - slack || upper > c->x.back() + slack)
      throw InputError(fmt::format("curve '{}' spans x in [{}, {}], the comparison needs [{}, {}]",
                                   c->label, c->x.front(), c->x.back(), lower, upper));
  CurveDifference d;
  double sum_relative = 0.0, sum_absolute = 0.0;
  const std::vector<double> grid = linear_grid(lower, upper, points);
  for (double x : grid) {
    const double y = interpolate(curve, x), y_ref = interpolate(reference, x);
    sum_absolute += (y - y_ref) * (y - y_ref);
    if (y_ref == 0.0) continue;
    const double relative = std::abs(y - y_ref) / std::abs(y_ref);
    sum_relative += relative * relative;
    ++d.points;
    if (relative > d.max_relative) d.max_relative = relative, d.at_max_x = x;
  }
  d.rms_absolute = std::sqrt(sum_absolute / static_cast<double>(grid.size()));
  d.rms_relative = d.points > 0 ? std::sqrt(sum_relative / d.points) : 0.0;
  return d;
}

double spread_at(const std::vector<Curve>& family, double x) {
  if (family.empty()) throw InputError("spread of an empty family of curves");
  double low = HUGE_VAL, high = -HUGE_VAL, sum = 0.0;
  for (const Curve& c : family) {
    const double y = interpolate(c, x);
    low = std::min(low, y), high = std::max(high, y), sum += y;
  }
  const double mean = sum / static_cast<double>(family.size());
  return mean != 0.0 ? (high - low) / std::abs(mean) : 0.0;
}

std::vector<double> spread_at(const std::vector<Curve>& family, const std::vector<double>& xs) {
  std::vector<double> spreads;
  spreads.reserve(xs.size());
  for (double x : xs)
    spreads.push_back(spread_at(family, x));
  return spreads;
}

UnloadingResidual unloading_residual(const std::vector<double>& deformation,
                                     const std::vector<double>& approach,
                                     const std::vector<double>& force,
                                     std::size_t first_unloading) {
  UnloadingResidual result;
  result.residual_approach = result.residual_deformation = NAN;
  for (double f : force)
    result.peak_force = std::max(result.peak_force, f);
  const double none = 1e-9 * result.peak_force;
  for (std::size_t i = std::max<std::size_t>(first_unloading, 1); i < force.size(); ++i) {
    const std::size_t a = i - 1, b = i;
    if (!(force[a] > none) || force[b] > none) continue;
    double w = 1.0;
    if (i >= 2 && force[i - 2] > force[a]) {
      const double slope = (force[i - 2] - force[a]) / (deformation[i - 2] - deformation[a]);
      const double zero = deformation[a] - force[a] / slope;
      w = std::clamp((deformation[a] - zero) / (deformation[a] - deformation[b]), 0.0, 1.0);
    }
    result.residual_deformation = deformation[a] + w * (deformation[b] - deformation[a]);
    result.residual_approach = approach[a] + w * (approach[b] - approach[a]);
    result.resolution = deformation[a] - deformation[b];
    break;
  }
  return result;
}

}  // namespace shapepress::analysis
