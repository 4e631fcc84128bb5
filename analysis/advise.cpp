#include "analysis/advise.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "common/csv.hpp"

namespace shapepress::analysis {

namespace {

// Where a stress–strain curve first reaches a tenth of its peak: from there on its relative
// differences mean something (the quasi-static figures start there too, models.md).
double tenth_of_peak(const Curve& curve) {
  const double peak = *std::max_element(curve.y.begin(), curve.y.end());
  for (std::size_t i = 0; i < curve.y.size(); ++i)
    if (curve.y[i] >= 0.1 * peak) return curve.x[i];
  return curve.x.front();
}

// NaN when either is not finite (Py of a bed that never yields is infinite): such a figure is
// not compared, and the table says so.
double relative(double value, double reference) {
  if (!std::isfinite(value) || !std::isfinite(reference)) return NAN;
  return reference != 0.0 ? (value - reference) / reference : 0.0;
}

// The finer of two stable rungs: more sub-spheres, then the smaller step, then less mass scaling.
bool finer(const Rung& x, const Rung& y) {
  if (x.sub_spheres != y.sub_spheres) return x.sub_spheres > y.sub_spheres;
  if (x.time_step_fraction != y.time_step_fraction)
    return x.time_step_fraction < y.time_step_fraction;
  return x.density_scale < y.density_scale;
}

}  // namespace

const char* status_name(RungStatus status) {
  switch (status) {
    case RungStatus::reference:
      return "reference";
    case RungStatus::within:
      return "within";
    case RungStatus::off:
      return "off";
    case RungStatus::diverged:
      return "diverged";
    case RungStatus::refused:
      break;
  }
  return "refused";
}

Advice advise(const std::vector<Rung>& rungs, double tolerance, double from, double to) {
  Advice advice;
  advice.tolerance = tolerance;
  advice.from = from;
  advice.to = to;
  for (const Rung& rung : rungs)
    advice.rows.push_back(AdviceRow{
        &rung, rung.end == RunEnd::refused ? RungStatus::refused : RungStatus::diverged, {}});
  for (std::size_t k = 0; k < rungs.size(); ++k) {
    if (!rungs[k].stable()) continue;
    rungs[k].curve.check();
    advice.to = std::min(advice.to, rungs[k].curve.x.back());
    if (!advice.reference || finer(rungs[k], rungs[*advice.reference])) advice.reference = k;
  }
  if (!advice.reference) return advice;
  const Rung& finest = rungs[*advice.reference];
  const Curve& reference = finest.curve;
  if (finest.compaction) advice.from = std::max(advice.from, tenth_of_peak(reference));
  for (std::size_t k = 0; k < rungs.size(); ++k) {
    AdviceRow& row = advice.rows[k];
    if (!rungs[k].stable()) continue;
    if (k == *advice.reference) {
      row.status = RungStatus::reference;
      continue;
    }
    row.versus_reference = compare_curves(rungs[k].curve, reference, advice.from, advice.to);
    row.error = row.versus_reference.rms_relative;
    if (rungs[k].compaction && finest.compaction) {
      const CompactionFigures &x = *rungs[k].compaction, &r = *finest.compaction;
      row.peak_difference = relative(x.peak_stress, r.peak_stress);
      row.recovery_difference = relative(x.elastic_recovery, r.elastic_recovery);
      row.yield_pressure_difference = relative(x.yield_pressure, r.yield_pressure);
      for (double d : {row.peak_difference, row.recovery_difference, row.yield_pressure_difference})
        if (std::isfinite(d)) row.error = std::max(row.error, std::abs(d));
    }
    row.status = row.error <= tolerance ? RungStatus::within : RungStatus::off;
  }
  // The cheapest rung that holds the answer; the reference always does.
  const auto cheaper = [&](std::size_t a, std::size_t b) {
    const Rung &x = rungs[a], &y = rungs[b];
    if (x.cpu_seconds != y.cpu_seconds) return x.cpu_seconds < y.cpu_seconds;
    if (x.sub_spheres != y.sub_spheres) return x.sub_spheres < y.sub_spheres;
    return x.time_step_fraction > y.time_step_fraction;
  };
  for (std::size_t k = 0; k < rungs.size(); ++k) {
    const RungStatus s = advice.rows[k].status;
    if (s != RungStatus::within && s != RungStatus::reference) continue;
    if (!advice.pick || cheaper(k, *advice.pick)) advice.pick = k;
  }
  return advice;
}

void write_advice_csv(const std::filesystem::path& path, const Advice& advice) {
  CsvWriter csv(path,
                {"label", "status", "cause", "sub_spheres", "time_step_fraction", "density_scale",
                 "cpu_s", "rms_vs_reference", "max_vs_reference", "peak_vs_reference",
                 "recovery_vs_reference", "py_vs_reference", "peak_stress_Pa", "elastic_recovery",
                 "yield_pressure_Pa", "error", "picked"});
  csv.comment(fmt::format(
      "shapepress advise: each rung against the reference {} (RMS and largest relative "
      "difference of the curve over {:.3g}-{:.3g}; compaction rungs also the peak stress, "
      "elastic recovery and Py; error the largest), tolerance {:.3g}",
      advice.reference ? advice.rows[*advice.reference].rung->label : std::string("(none)"),
      advice.from, advice.to, advice.tolerance));
  const auto number_or_nan = [](bool known, double value) {
    return known ? format_number(value) : std::string("nan");
  };
  for (std::size_t k = 0; k < advice.rows.size(); ++k) {
    const AdviceRow& row = advice.rows[k];
    const Rung& rung = *row.rung;
    const bool stable = rung.stable();
    const bool figures = stable && rung.compaction.has_value();
    const CompactionFigures f = rung.compaction.value_or(CompactionFigures{});
    csv.row_text({rung.label, status_name(row.status), rung.cause.empty() ? "-" : rung.cause,
                  std::to_string(rung.sub_spheres), format_number(rung.time_step_fraction),
                  format_number(rung.density_scale), format_number(rung.cpu_seconds),
                  number_or_nan(stable, row.versus_reference.rms_relative),
                  number_or_nan(stable, row.versus_reference.max_relative),
                  number_or_nan(figures, row.peak_difference),
                  number_or_nan(figures, row.recovery_difference),
                  number_or_nan(figures, row.yield_pressure_difference),
                  number_or_nan(figures, f.peak_stress), number_or_nan(figures, f.elastic_recovery),
                  number_or_nan(figures, f.yield_pressure), number_or_nan(stable, row.error),
                  advice.pick == k ? "1" : "0"});
  }
  csv.commit();
}

Chart speed_accuracy_chart(const Advice& advice) {
  Chart chart{fmt::format("Each rung against the finest ({:.3g}-{:.3g} deformation)", advice.from,
                          advice.to),
              "CPU seconds of the run",
              "difference from the finest rung [%] (compaction: the largest of curve RMS, peak, "
              "recovery, Py)",
              "cpu_s",
              "error_percent",
              {}};
  std::map<double, Series> by_fraction;
  double most = 0.0;
  for (const AdviceRow& row : advice.rows) {
    if (!row.rung->stable()) continue;
    Series& s = by_fraction[row.rung->time_step_fraction];
    s.title = fmt::format("step {:.3g} of critical", row.rung->time_step_fraction);
    s.style = SeriesStyle::markers;
    s.x.push_back(row.rung->cpu_seconds);
    s.y.push_back(100.0 * row.error);
    most = std::max(most, row.rung->cpu_seconds);
  }
  int colour = 1;
  for (auto& [fraction, series] : by_fraction) {
    series.colour = colour++;
    chart.series.push_back(std::move(series));
  }
  chart.series.push_back(Series{fmt::format("tolerance {:.3g} %", 100.0 * advice.tolerance),
                                {0.0, most},
                                {100.0 * advice.tolerance, 100.0 * advice.tolerance},
                                SeriesStyle::dashed,
                                8});
  if (advice.pick) {
    const AdviceRow& row = advice.rows[*advice.pick];
    chart.series.push_back(Series{fmt::format("pick: {}", row.rung->label),
                                  {row.rung->cpu_seconds},
                                  {100.0 * row.error},
                                  SeriesStyle::points,
                                  7});
  }
  return chart;
}

Chart stability_map_chart(const Advice& advice) {
  Chart chart{fmt::format("Stability map: within {:.3g} % of the finest, off, or diverged",
                          100.0 * advice.tolerance),
              "sub-spheres",
              "time step [fraction of the critical step]",
              "sub_spheres",
              "time_step_fraction",
              {}};
  const std::pair<RungStatus, const char*> kinds[] = {
      {RungStatus::reference, "reference (finest stable)"},
      {RungStatus::within, "stable, within tolerance"},
      {RungStatus::off, "stable, off by more"},
      {RungStatus::diverged, "diverged (exit 1)"},
      {RungStatus::refused, "refused by the step checks (exit 2)"}};
  int colour = 1;
  for (const auto& [status, title] : kinds) {
    Series s{title, {}, {}, SeriesStyle::markers, colour++};
    for (const AdviceRow& row : advice.rows)
      if (row.status == status) {
        s.x.push_back(row.rung->sub_spheres);
        s.y.push_back(row.rung->time_step_fraction);
      }
    if (!s.x.empty()) chart.series.push_back(std::move(s));
  }
  return chart;
}

}  // namespace shapepress::analysis
