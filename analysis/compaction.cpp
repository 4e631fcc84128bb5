#include "analysis/compaction.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "common/error.hpp"

namespace shapepress::analysis {

void PunchCurve::check() const {
  const std::size_t n = gap.size();
  if (time.size() != n || top_force.size() != n || stress.size() != n ||
      solid_fraction.size() != n || phase.size() != n)
    throw InputError("punch curve: columns of different lengths");
  if (n < 3) throw InputError(fmt::format("punch curve: {} rows, at least 3 needed", n));
  if (!(reference_gap > 0.0))
    throw InputError(
        fmt::format("punch curve: reference gap H0 = {} m, must be > 0", reference_gap));
  if (phase.front() != static_cast<int>(PunchPhase::load))
    throw InputError("punch curve: the first row is not in the loading phase (phase 0)");
}

LinearFit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = std::min(x.size(), y.size());
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    mx += x[i], my += y[i];
  mx /= static_cast<double>(n), my /= static_cast<double>(n);
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  if (n < 2 || !(sxx > 0.0))
    throw ComputationError(fmt::format("line fit: {} points without two distinct x values", n));
  LinearFit fit;
  fit.slope = sxy / sxx;
  fit.intercept = my - fit.slope * mx;
  fit.r_squared = syy > 0.0 ? sxy * sxy / (sxx * syy) : 1.0;
  fit.points = static_cast<int>(n);
  return fit;
}

void FitWindows::check() const {
  auto check_window = [](const char* name, double lower, double upper) {
    if (!(lower >= 0.0 && lower < upper && upper <= 1.0))
      throw InputError(
          fmt::format("{} window [{}, {}] of the peak stress: expected 0 <= lower < upper <= 1",
                      name, lower, upper));
  };
  check_window("Heckel", heckel_lower, heckel_upper);
  check_window("Kawakita", kawakita_lower, kawakita_upper);
}

std::vector<std::size_t> loading_rows(const PunchCurve& curve) {
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < curve.phase.size(); ++i) {
    if (curve.phase[i] != static_cast<int>(PunchPhase::load)) break;
    rows.push_back(i);
  }
  return rows;
}

namespace {

// Loading rows whose stress lies in [lower, upper] (and is positive).
std::vector<std::size_t> window_rows(const PunchCurve& curve, double lower, double upper) {
  std::vector<std::size_t> rows;
  for (std::size_t i : loading_rows(curve))
    if (curve.stress[i] > 0.0 && curve.stress[i] >= lower && curve.stress[i] <= upper)
      rows.push_back(i);
  return rows;
}

}  // namespace

HeckelFit fit_heckel(const PunchCurve& curve, double stress_lower, double stress_upper) {
  std::vector<double> p, y;
  for (std::size_t i : window_rows(curve, stress_lower, stress_upper)) {
    const double d = curve.solid_fraction[i];
    if (!(d > 0.0 && d < 1.0)) continue;  // ln(1/(1−D)) undefined at full density
    p.push_back(curve.stress[i]);
    y.push_back(std::log(1.0 / (1.0 - d)));
  }
  if (p.size() < 3)
    throw ComputationError(
        fmt::format("Heckel fit: {} loading points between {:.4g} and {:.4g} Pa, at least 3 needed",
                    p.size(), stress_lower, stress_upper));
  const LinearFit line = fit_line(p, y);
  HeckelFit fit;
  fit.k = line.slope;
  fit.a = line.intercept;
  fit.yield_pressure = line.slope > 0.0 ? 1.0 / line.slope : HUGE_VAL;
  fit.r_squared = line.r_squared;
  fit.points = line.points;
  fit.stress_lower = *std::min_element(p.begin(), p.end());
  fit.stress_upper = *std::max_element(p.begin(), p.end());
  return fit;
}

KawakitaFit fit_kawakita(const PunchCurve& curve, double stress_lower, double stress_upper) {
  std::vector<double> p, p_over_c;
  // V0 is the powder's apparent volume when the punch starts pressing it, not the strain's H0
  // (which may be where the bed would be at a reference density it never had).
  const double v0 = curve.gap.front();
  for (std::size_t i : window_rows(curve, stress_lower, stress_upper)) {
    const double c = (v0 - curve.gap[i]) / v0;
    if (!(c > 0.0)) continue;
    p.push_back(curve.stress[i]);
    p_over_c.push_back(curve.stress[i] / c);
  }
  if (p.size() < 3)
    throw ComputationError(fmt::format(
        "Kawakita fit: {} loading points between {:.4g} and {:.4g} Pa, at least 3 needed", p.size(),
        stress_lower, stress_upper));
  const LinearFit line = fit_line(p, p_over_c);
  KawakitaFit fit;
  fit.a = 1.0 / line.slope;             // slope = 1/a
  fit.b = line.slope / line.intercept;  // intercept = 1/(a b) → b = (1/a)/intercept
  fit.r_squared = line.r_squared;
  fit.points = line.points;
  fit.stress_lower = *std::min_element(p.begin(), p.end());
  fit.stress_upper = *std::max_element(p.begin(), p.end());
  return fit;
}

double punch_work(const PunchCurve& curve, std::size_t first, std::size_t last) {
  double work = 0.0;
  for (std::size_t i = first + 1; i <= last && i < curve.gap.size(); ++i)
    work += 0.5 * (curve.top_force[i] + curve.top_force[i - 1]) * (curve.gap[i - 1] - curve.gap[i]);
  return work;
}

CompactionMetrics analyse_compaction(const PunchCurve& curve, const FitWindows& windows) {
  curve.check();
  windows.check();
  CompactionMetrics m;
  m.reference_gap = curve.reference_gap;
  m.density_scale = curve.density_scale;
  m.max_kinetic_to_work = curve.max_kinetic_to_work;
  m.mean_force_imbalance = curve.mean_force_imbalance;
  const std::size_t n = curve.gap.size();
  const std::size_t peak = static_cast<std::size_t>(
      std::max_element(curve.stress.begin(), curve.stress.end()) - curve.stress.begin());
  m.peak_stress = curve.stress[peak];
  m.peak_force = curve.top_force[peak];
  m.solid_fraction_at_peak = curve.solid_fraction[peak];
  m.strain_at_peak = (curve.reference_gap - curve.gap[peak]) / curve.reference_gap;
  m.minimum_gap = *std::min_element(curve.gap.begin(), curve.gap.end());
  if (!(m.peak_stress > 0.0))
    throw ComputationError("punch curve: the stress never becomes positive (no compaction)");

  // Phases follow each other in order: load, hold, unload, done.
  auto first_of = [&](PunchPhase phase) {
    for (std::size_t i = 0; i < n; ++i)
      if (curve.phase[i] >= static_cast<int>(phase)) return i;
    return n;
  };
  const std::size_t unload_start = first_of(PunchPhase::unload);
  // The step into the first unload row already opens the gap: it belongs to unloading.
  m.work_of_compaction = punch_work(curve, 0, unload_start == n ? n - 1 : unload_start - 1);
  // A run that ends after its hold has a last row "done" but never unloaded: no recovery.
  const bool unloads = std::any_of(curve.phase.begin(), curve.phase.end(),
                                   [](int p) { return p == static_cast<int>(PunchPhase::unload); });
  if (unload_start < n && unloads) {
    m.unloaded = true;
    m.unloaded_gap = curve.gap[n - 1];  // the punch stops where the force vanished
    m.elastic_recovery = (m.unloaded_gap - m.minimum_gap) / m.minimum_gap;
    m.work_of_unloading = -punch_work(curve, unload_start - 1, n - 1);
  }
  m.heckel =
      fit_heckel(curve, windows.heckel_lower * m.peak_stress, windows.heckel_upper * m.peak_stress);
  m.kawakita = fit_kawakita(curve, windows.kawakita_lower * m.peak_stress,
                            windows.kawakita_upper * m.peak_stress);
  return m;
}

}  // namespace shapepress::analysis
