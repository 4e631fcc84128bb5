#include "analysis/bed_size.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include <fmt/format.h>

#include "common/csv.hpp"
#include "common/error.hpp"

namespace shapepress::analysis {

const char* figure_name(BedFigure figure) {
  switch (figure) {
    case BedFigure::peak_stress:
      return "peak_stress";
    case BedFigure::elastic_recovery:
      return "elastic_recovery";
    case BedFigure::yield_pressure:
      break;
  }
  return "yield_pressure";
}

double figure_of(const BedRun& run, BedFigure figure) {
  switch (figure) {
    case BedFigure::peak_stress:
      return run.peak_stress;
    case BedFigure::elastic_recovery:
      return run.elastic_recovery;
    case BedFigure::yield_pressure:
      break;
  }
  return run.yield_pressure;
}

namespace {

void check_run(const BedRun& run) {
  const auto bad = [&](std::string_view what, double value) {
    return InputError(fmt::format("bed ladder: run {}: {} is {}", run.label, what, value));
  };
  if (run.bodies < 1) throw bad("bodies", run.bodies);
  if (run.sub_spheres < 1) throw bad("sub_spheres", run.sub_spheres);
  if (!(std::isfinite(run.peak_stress) && run.peak_stress > 0.0))
    throw bad("peak_stress", run.peak_stress);
  if (!(std::isfinite(run.elastic_recovery) && run.elastic_recovery >= 0.0))
    throw bad("elastic_recovery", run.elastic_recovery);
  if (std::isnan(run.yield_pressure) || run.yield_pressure <= 0.0)
    throw bad("yield_pressure", run.yield_pressure);
}

// Over the runs' finite values of `figure` (Py of a bed that never yields is left out).
SeedStatistics statistics(const std::vector<BedRun>& ladder, const std::vector<std::size_t>& runs,
                          BedFigure figure) {
  SeedStatistics s;
  double sum = 0.0;
  for (std::size_t k : runs)
    if (const double v = figure_of(ladder[k], figure); std::isfinite(v)) {
      sum += v;
      ++s.seeds;
    }
  if (s.seeds == 0) return {NAN, NAN, 0};
  s.mean = sum / s.seeds;
  if (s.seeds < 2) {
    s.standard_deviation = NAN;
    return s;
  }
  double squares = 0.0;
  for (std::size_t k : runs)
    if (const double v = figure_of(ladder[k], figure); std::isfinite(v))
      squares += (v - s.mean) * (v - s.mean);
  s.standard_deviation = std::sqrt(squares / (s.seeds - 1));
  return s;
}

}  // namespace

BedSizeAdvice advise_bed_size(const std::vector<BedRun>& ladder, double tolerance) {
  if (ladder.empty()) throw InputError("bed ladder: no runs to judge");
  if (!(tolerance > 0.0)) throw InputError(fmt::format("bed ladder: tolerance {}", tolerance));
  for (const BedRun& run : ladder)
    check_run(run);
  BedSizeAdvice advice;
  advice.tolerance = tolerance;
  std::map<std::pair<int, int>, std::vector<std::size_t>> groups;
  for (std::size_t k = 0; k < ladder.size(); ++k)
    groups[{ladder[k].bodies, ladder[k].sub_spheres}].push_back(k);
  for (const auto& [key, runs] : groups) {
    BedSetting setting;
    setting.bodies = key.first;
    setting.sub_spheres = key.second;
    setting.runs = runs;
    for (BedFigure f : bed_figures)
      setting.figures[static_cast<int>(f)] = statistics(ladder, runs, f);
    double height = 0.0, cost = 0.0;
    bool cost_known = true;
    for (std::size_t k : runs) {
      height += ladder[k].bed_height_diameters;
      cost += static_cast<double>(ladder[k].counted_cost);
      cost_known = cost_known && ladder[k].counted_cost >= 0;
    }
    setting.bed_height_diameters = height / static_cast<double>(runs.size());
    setting.cost_per_run = cost_known ? cost / static_cast<double>(runs.size()) : -1.0;
    advice.settings.push_back(std::move(setting));
  }
  // std::map ordered them by bodies, then sub-spheres: the last is the largest, finest bed.
  advice.reference = advice.settings.size() - 1;
  BedSetting& reference = advice.settings[advice.reference];
  reference.reference = true;
  for (BedSetting& setting : advice.settings) {
    setting.bias = 0.0;
    setting.bias_standard_error = 0.0;
    setting.scatter = 0.0;
    for (BedFigure f : bed_figures) {
      const SeedStatistics &own = setting.figures[static_cast<int>(f)],
                           &ref = reference.figures[static_cast<int>(f)];
      if (own.seeds == 0 || ref.seeds == 0) continue;  // Py where neither yields
      const double bias = std::abs(own.mean - ref.mean) / ref.mean;
      const double error =
          &setting == &reference
              ? 0.0
              : std::sqrt(own.standard_deviation * own.standard_deviation / own.seeds +
                          ref.standard_deviation * ref.standard_deviation / ref.seeds) /
                    ref.mean;
      if (bias >= setting.bias) {
        setting.bias = bias;
        setting.bias_standard_error = error;
      }
      // NaN (one seed) wins the max: the scatter is then unknown.
      const double scatter = own.standard_deviation / own.mean;
      setting.scatter = std::isnan(scatter) || std::isnan(setting.scatter)
                            ? NAN
                            : std::max(setting.scatter, scatter);
    }
    setting.seeds_needed =
        std::isnan(setting.scatter)
            ? static_cast<int>(setting.runs.size())
            : std::max(1,
                       static_cast<int>(std::ceil(
                           (setting.scatter / tolerance) * (setting.scatter / tolerance) - 1e-9)));
    setting.predicted_cost =
        setting.cost_per_run >= 0.0 ? setting.cost_per_run * setting.seeds_needed : -1.0;
    setting.holds = setting.bias <= tolerance;
    setting.resolved =
        setting.reference || (std::isfinite(setting.bias_standard_error) &&
                              setting.bias + 2.0 * setting.bias_standard_error <= tolerance);
  }
  for (std::size_t k = 0; k < advice.settings.size(); ++k) {
    const BedSetting& s = advice.settings[k];
    if (!s.holds) continue;
    if (!advice.pick) {
      advice.pick = k;
      continue;
    }
    const BedSetting& best = advice.settings[*advice.pick];
    // An unknown cost loses to any known one; ties go to the smaller, coarser bed, which the
    // settings' order (bodies, then sub-spheres) already puts first.
    const double cost = s.predicted_cost < 0.0 ? INFINITY : s.predicted_cost;
    const double best_cost = best.predicted_cost < 0.0 ? INFINITY : best.predicted_cost;
    if (cost < best_cost) advice.pick = k;
  }
  return advice;
}

void write_bed_size_csv(const std::filesystem::path& path, const BedSizeAdvice& advice) {
  std::vector<std::string> columns{"bodies", "sub_spheres", "seeds", "bed_height_diameters"};
  for (BedFigure f : bed_figures) {
    columns.push_back(fmt::format("{}_mean", figure_name(f)));
    columns.push_back(fmt::format("{}_sd", figure_name(f)));
  }
  for (const char* c : {"bias", "bias_standard_error", "scatter", "seeds_needed", "cost_per_run",
                        "predicted_cost", "reference", "holds", "resolved", "picked"})
    columns.emplace_back(c);
  CsvWriter csv(path, columns);
  const BedSetting& reference = advice.settings[advice.reference];
  csv.comment(fmt::format(
      "shapepress advise --bed-runs: each setting's seeds against the reference ({} bodies of {} "
      "sub-spheres); bias = largest |mean - reference mean| / reference mean of the peak stress "
      "(Pa), elastic recovery and Heckel Py (Pa); scatter = largest seed standard deviation / "
      "mean; seeds_needed = ceil((scatter / tolerance)^2); "
      "predicted_cost = counted cost of one run x seeds_needed; tolerance {:.3g}",
      reference.bodies, reference.sub_spheres, advice.tolerance));
  for (std::size_t k = 0; k < advice.settings.size(); ++k) {
    const BedSetting& s = advice.settings[k];
    std::vector<double> row{static_cast<double>(s.bodies), static_cast<double>(s.sub_spheres),
                            static_cast<double>(s.runs.size()), s.bed_height_diameters};
    for (const SeedStatistics& f : s.figures) {
      row.push_back(f.mean);
      row.push_back(f.standard_deviation);
    }
    row.insert(row.end(),
               {s.bias, s.bias_standard_error, s.scatter, static_cast<double>(s.seeds_needed),
                s.cost_per_run < 0.0 ? NAN : s.cost_per_run,
                s.predicted_cost < 0.0 ? NAN : s.predicted_cost, s.reference ? 1.0 : 0.0,
                s.holds ? 1.0 : 0.0, s.resolved ? 1.0 : 0.0, advice.pick == k ? 1.0 : 0.0});
    csv.row(row);
  }
  csv.commit();
}

Chart bed_size_chart(const BedSizeAdvice& advice, BedFigure figure) {
  const bool stress = figure != BedFigure::elastic_recovery;
  const double unit = stress ? 1e-6 : 100.0;
  const std::string label = figure == BedFigure::peak_stress      ? "peak stress [MPa]"
                            : figure == BedFigure::yield_pressure ? "Heckel Py [MPa]"
                                                                  : "elastic recovery [%]";
  const std::string column = figure == BedFigure::peak_stress      ? "peak_stress_MPa"
                             : figure == BedFigure::yield_pressure ? "yield_pressure_MPa"
                                                                   : "elastic_recovery_percent";
  Chart chart{fmt::format("{} against bed size (mean of the seeds, ± their standard deviation)",
                          label.substr(0, label.find(" ["))),
              "bodies",
              label,
              "bodies",
              column,
              {}};
  std::map<int, Series> by_count;
  for (const BedSetting& s : advice.settings) {
    const SeedStatistics& f = s.figures[static_cast<int>(figure)];
    if (f.seeds == 0) continue;
    Series& series = by_count[s.sub_spheres];
    series.title = s.sub_spheres == 1 ? std::string("spheres")
                                      : fmt::format("{} sub-spheres per body", s.sub_spheres);
    series.x.push_back(s.bodies);
    series.y.push_back(f.mean * unit);
    series.y_error.push_back(std::isfinite(f.standard_deviation) ? f.standard_deviation * unit
                                                                 : 0.0);
  }
  for (auto& [count, series] : by_count)
    chart.series.push_back(std::move(series));
  chart.log_x = true;
  return chart;
}

Chart bed_speed_accuracy_chart(const BedSizeAdvice& advice) {
  const BedSetting& reference = advice.settings[advice.reference];
  Chart chart{"Bed size and resolution: error against cost",
              "predicted counted cost (runs x seeds needed)",
              "largest relative difference from the reference",
              "predicted_counted_cost",
              "bias",
              {}};
  Series bodies{
      fmt::format("bodies, at {} sub-spheres", reference.sub_spheres), {}, {}, SeriesStyle::lines};
  Series counts{
      fmt::format("sub-spheres, at {} bodies", reference.bodies), {}, {}, SeriesStyle::dashed};
  double low = INFINITY, high = 0.0;
  for (const BedSetting& s : advice.settings) {
    if (s.predicted_cost <= 0.0) continue;
    low = std::min(low, s.predicted_cost);
    high = std::max(high, s.predicted_cost);
    const double bias = s.bias;  // the reference: zero, on both series
    if (s.sub_spheres == reference.sub_spheres) {
      bodies.x.push_back(s.predicted_cost);
      bodies.y.push_back(bias);
      bodies.y_error.push_back(std::isfinite(s.bias_standard_error) ? s.bias_standard_error : 0.0);
    }
    if (s.bodies == reference.bodies) {
      counts.x.push_back(s.predicted_cost);
      counts.y.push_back(bias);
      counts.y_error.push_back(std::isfinite(s.bias_standard_error) ? s.bias_standard_error : 0.0);
    }
  }
  chart.series.push_back(std::move(bodies));
  chart.series.push_back(std::move(counts));
  if (high > 0.0)
    chart.series.push_back({fmt::format("tolerance {:.3g}", advice.tolerance),
                            {low, high},
                            {advice.tolerance, advice.tolerance},
                            SeriesStyle::dashed,
                            8});
  chart.log_x = true;
  return chart;
}

}  // namespace shapepress::analysis
