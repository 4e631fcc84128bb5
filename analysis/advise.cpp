#include "analysis/advise.hpp"

#include <algorithm>
#include <map>

#include <fmt/format.h>

#include "common/csv.hpp"

namespace shapepress::analysis {

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
  // The finest stable rung: most sub-spheres, then the smallest step.
  for (std::size_t k = 0; k < rungs.size(); ++k) {
    if (!rungs[k].stable()) continue;
    rungs[k].curve.check();
    advice.to = std::min(advice.to, rungs[k].curve.x.back());
    if (!advice.reference) {
      advice.reference = k;
      continue;
    }
    const Rung& best = rungs[*advice.reference];
    if (rungs[k].sub_spheres > best.sub_spheres ||
        (rungs[k].sub_spheres == best.sub_spheres &&
         rungs[k].time_step_fraction < best.time_step_fraction))
      advice.reference = k;
  }
  if (!advice.reference) return advice;
  const Curve& reference = rungs[*advice.reference].curve;
  for (std::size_t k = 0; k < rungs.size(); ++k) {
    AdviceRow& row = advice.rows[k];
    if (!rungs[k].stable()) continue;
    if (k == *advice.reference) {
      row.status = RungStatus::reference;
      continue;
    }
    row.versus_reference = compare_curves(rungs[k].curve, reference, advice.from, advice.to);
    row.status =
        row.versus_reference.rms_relative <= tolerance ? RungStatus::within : RungStatus::off;
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
  CsvWriter csv(path, {"label", "status", "cause", "sub_spheres", "time_step_fraction", "cpu_s",
                       "rms_vs_reference", "max_vs_reference", "picked"});
  csv.comment(fmt::format(
      "shapepress advise: each rung against the reference {} (RMS and largest relative "
      "difference of the force over deformation {:.3g}-{:.3g}), tolerance {:.3g}",
      advice.reference ? advice.rows[*advice.reference].rung->label : std::string("(none)"),
      advice.from, advice.to, advice.tolerance));
  for (std::size_t k = 0; k < advice.rows.size(); ++k) {
    const AdviceRow& row = advice.rows[k];
    const bool stable = row.rung->stable();
    csv.row_text({row.rung->label, status_name(row.status),
                  row.rung->cause.empty() ? "-" : row.rung->cause,
                  std::to_string(row.rung->sub_spheres),
                  format_number(row.rung->time_step_fraction), format_number(row.rung->cpu_seconds),
                  stable ? format_number(row.versus_reference.rms_relative) : "nan",
                  stable ? format_number(row.versus_reference.max_relative) : "nan",
                  advice.pick == k ? "1" : "0"});
  }
  csv.commit();
}

Chart speed_accuracy_chart(const Advice& advice) {
  Chart chart{fmt::format("Each rung against the finest ({:.3g}-{:.3g} deformation)", advice.from,
                          advice.to),
              "CPU seconds of the run",
              "RMS difference from the finest rung [%]",
              "cpu_s",
              "rms_percent",
              {}};
  std::map<double, Series> by_fraction;
  double most = 0.0;
  for (const AdviceRow& row : advice.rows) {
    if (!row.rung->stable()) continue;
    Series& s = by_fraction[row.rung->time_step_fraction];
    s.title = fmt::format("step {:.3g} of critical", row.rung->time_step_fraction);
    s.style = SeriesStyle::markers;
    s.x.push_back(row.rung->cpu_seconds);
    s.y.push_back(100.0 * row.versus_reference.rms_relative);
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
                                  {100.0 * row.versus_reference.rms_relative},
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
