#include "analysis/advise.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/run_metadata.hpp"

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

// `rung` against `reference` over the advice's window: the curve's RMS, and a compaction rung's
// figures; the error is the largest of them.
AdviceRow compare(const Rung& rung, const Rung& reference, const Advice& advice) {
  AdviceRow row{&rung, RungStatus::off, {}};
  row.versus_reference = compare_curves(rung.curve, reference.curve, advice.from, advice.to);
  row.error = row.versus_reference.rms_relative;
  if (rung.compaction && reference.compaction) {
    const CompactionFigures &x = *rung.compaction, &r = *reference.compaction;
    row.peak_difference = relative(x.peak_stress, r.peak_stress);
    row.recovery_difference = relative(x.elastic_recovery, r.elastic_recovery);
    row.yield_pressure_difference = relative(x.yield_pressure, r.yield_pressure);
    for (double d : {row.peak_difference, row.recovery_difference, row.yield_pressure_difference})
      if (std::isfinite(d)) row.error = std::max(row.error, std::abs(d));
  }
  return row;
}

bool same_setting(const Rung& x, const Rung& y) {
  return x.sub_spheres == y.sub_spheres && x.time_step_fraction == y.time_step_fraction &&
         x.density_scale == y.density_scale;
}

Advice advise(const std::vector<Rung>& rungs, double tolerance, double from, double to) {
  Advice advice;
  advice.tolerance = tolerance;
  advice.from = from;
  advice.to = to;
  for (const Rung& rung : rungs)
    advice.rows.push_back(AdviceRow{
        &rung, rung.end == RunEnd::refused ? RungStatus::refused : RungStatus::diverged, {}});
  // The finest stable rung of each seed, the seeds in the order they first appear.
  std::vector<int> seeds;
  std::map<int, std::size_t> finest_of;
  for (std::size_t k = 0; k < rungs.size(); ++k) {
    if (std::find(seeds.begin(), seeds.end(), rungs[k].seed) == seeds.end())
      seeds.push_back(rungs[k].seed);
    if (!rungs[k].stable()) continue;
    rungs[k].curve.check();
    // The window every stable curve covers (beds of one solid fraction start apart).
    advice.from = std::max(advice.from, rungs[k].curve.x.front());
    advice.to = std::min(advice.to, rungs[k].curve.x.back());
    const auto it = finest_of.find(rungs[k].seed);
    if (it == finest_of.end() || finer(rungs[k], rungs[it->second])) finest_of[rungs[k].seed] = k;
  }
  for (int seed : seeds)
    if (const auto it = finest_of.find(seed); it != finest_of.end()) {
      advice.references.push_back(it->second);
      if (!advice.reference) advice.reference = it->second;
    }
  if (!advice.reference) return advice;
  for (std::size_t r : advice.references)
    if (rungs[r].compaction) advice.from = std::max(advice.from, tenth_of_peak(rungs[r].curve));
  for (std::size_t k = 0; k < rungs.size(); ++k) {
    if (!rungs[k].stable()) continue;
    const std::size_t reference = finest_of.at(rungs[k].seed);
    if (k == reference) {
      advice.rows[k].status = RungStatus::reference;
      continue;
    }
    advice.rows[k] = compare(rungs[k], rungs[reference], advice);
    advice.rows[k].status =
        advice.rows[k].error <= tolerance ? RungStatus::within : RungStatus::off;
  }
  // How far apart the seeds' finest rungs are: the scale below which a difference between
  // settings cannot be told from another packing of the same bed.
  for (std::size_t r = 1; r < advice.references.size(); ++r)
    if (same_setting(rungs[advice.references[r]], rungs[*advice.reference]))
      advice.seed_scatter =
          std::max(advice.seed_scatter.value_or(0.0),
                   compare(rungs[advice.references[r]], rungs[*advice.reference], advice).error);
  // The cheapest setting that holds the answer on every seed (the references always do), by its
  // counted cost summed over the seeds (exact in a double below 2^53 steps of work); its row of
  // the first seed is the pick.
  std::optional<double> pick_cost;
  for (std::size_t k = 0; k < rungs.size(); ++k) {
    if (rungs[k].seed != seeds.front()) continue;
    double cost = 0.0;
    bool holds = true;
    for (std::size_t j = 0; j < rungs.size(); ++j) {
      if (!same_setting(rungs[j], rungs[k])) continue;
      const RungStatus s = advice.rows[j].status;
      holds = holds && (s == RungStatus::within || s == RungStatus::reference);
      // A rung of unknown cost (a run made outside the ladder) is picked only when nothing
      // else holds.
      cost += rungs[j].counted_cost >= 0 ? static_cast<double>(rungs[j].counted_cost) : INFINITY;
    }
    if (!holds) continue;
    const bool cheaper = !pick_cost || cost < *pick_cost ||
                         (cost == *pick_cost &&
                          (rungs[k].sub_spheres < rungs[*advice.pick].sub_spheres ||
                           (rungs[k].sub_spheres == rungs[*advice.pick].sub_spheres &&
                            rungs[k].time_step_fraction > rungs[*advice.pick].time_step_fraction)));
    if (cheaper) {
      pick_cost = cost;
      advice.pick = k;
    }
  }
  return advice;
}

namespace {

// advice.csv's columns, as write_advice_csv writes them and read_advice expects them.
constexpr std::size_t counted_cost_column = 7;
std::vector<std::string> advice_columns() {
  return {"label",
          "status",
          "cause",
          "sub_spheres",
          "time_step_fraction",
          "density_scale",
          "seed",
          "counted_cost",
          "cpu_s",
          "rms_vs_reference",
          "max_vs_reference",
          "peak_vs_reference",
          "recovery_vs_reference",
          "py_vs_reference",
          "peak_stress_Pa",
          "elastic_recovery",
          "yield_pressure_Pa",
          "error",
          "picked"};
}

}  // namespace

void write_advice_csv(const std::filesystem::path& path, const Advice& advice) {
  CsvWriter csv(path, advice_columns());
  csv.comment(fmt::format(
      "shapepress advise: each rung against the reference {} (RMS and largest relative "
      "difference of the curve over {:.3g}-{:.3g}; compaction rungs also the peak stress, "
      "elastic recovery and Py; error the largest), tolerance {:.3g}",
      advice.reference ? advice.rows[*advice.reference].rung->label : std::string("(none)"),
      advice.from, advice.to, advice.tolerance));
  if (advice.seed_scatter)
    csv.comment(
        fmt::format("seeds: each rung against its own seed's finest; the seeds' finest "
                    "rungs differ by up to {:.3g} (the seed-to-seed scatter)",
                    *advice.seed_scatter));
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
                  format_number(rung.density_scale), std::to_string(rung.seed),
                  rung.counted_cost >= 0 ? std::to_string(rung.counted_cost) : "nan",
                  number_or_nan(rung.cpu_seconds >= 0.0, rung.cpu_seconds),
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

namespace {

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t from = 0;
  for (std::size_t at = line.find(','); at != std::string::npos; at = line.find(',', from)) {
    fields.push_back(line.substr(from, at - from));
    from = at + 1;
  }
  fields.push_back(line.substr(from));
  return fields;
}

double field_number(const std::string& text, const std::filesystem::path& csv,
                    std::string_view column) {
  if (text == "nan") return NAN;
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size()) return v;
  } catch (const std::exception&) {
  }
  throw InputError(fmt::format("{}: column {}: '{}' is not a number", csv.string(), column, text));
}

}  // namespace

AdviceRecord read_advice(const std::filesystem::path& folder) {
  const RunRecord run = RunRecord::read(folder / run_metadata_name, "advise");
  AdviceRecord record;
  record.folder = folder;
  const std::filesystem::path csv = folder / "advice.csv";
  std::ifstream in(csv);
  if (!in) throw InputError(csv.string() + ": missing (advise writes it when its rungs are done)");
  const std::vector<std::string> columns = advice_columns();
  auto rungs = std::make_shared<std::vector<Rung>>();
  std::vector<AdviceRow> rows;
  bool header = false, uncounted_costs = false;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f = split_fields(line);
    if (!header) {
      // advice.csv from before the counted cost: its rungs' costs are unknown.
      std::vector<std::string> uncounted = columns;
      uncounted.erase(uncounted.begin() + counted_cost_column);
      uncounted_costs = f == uncounted;
      if (f != columns && !uncounted_costs)
        throw InputError(fmt::format("{}: not advise's columns ({})", csv.string(), line));
      header = true;
      continue;
    }
    if (uncounted_costs && f.size() == columns.size() - 1)
      f.insert(f.begin() + counted_cost_column, "nan");
    if (f.size() != columns.size())
      throw InputError(fmt::format("{}: {} fields in '{}', expected {}", csv.string(), f.size(),
                                   line, columns.size()));
    const auto number = [&](std::size_t i) { return field_number(f[i], csv, columns[i]); };
    Rung rung;
    rung.label = f[0];
    rung.cause = f[2] == "-" ? "" : f[2];
    rung.sub_spheres = static_cast<int>(number(3));
    rung.time_step_fraction = number(4);
    rung.density_scale = number(5);
    rung.seed = static_cast<int>(number(6));
    rung.counted_cost = std::isfinite(number(7)) ? std::llround(number(7)) : -1;
    rung.cpu_seconds = std::isfinite(number(8)) ? number(8) : -1.0;
    AdviceRow row;
    const RungStatus statuses[] = {RungStatus::reference, RungStatus::within, RungStatus::off,
                                   RungStatus::diverged, RungStatus::refused};
    const auto status = std::find_if(std::begin(statuses), std::end(statuses),
                                     [&](RungStatus s) { return f[1] == status_name(s); });
    if (status == std::end(statuses))
      throw InputError(fmt::format("{}: status '{}' of {}", csv.string(), f[1], f[0]));
    row.status = *status;
    rung.end = row.status == RungStatus::diverged  ? RunEnd::diverged
               : row.status == RungStatus::refused ? RunEnd::refused
                                                   : RunEnd::finished;
    row.versus_reference.rms_relative = number(9);
    row.versus_reference.max_relative = number(10);
    row.peak_difference = number(11);
    row.recovery_difference = number(12);
    row.yield_pressure_difference = number(13);
    if (std::isfinite(number(14))) {
      rung.compaction = CompactionFigures{number(14), number(15), number(16)};
      record.compaction = true;
    }
    row.error = number(17);
    if (f[18] == "1") record.advice.pick = rows.size();
    if (row.status == RungStatus::reference) {
      record.advice.references.push_back(rows.size());
      if (!record.advice.reference) record.advice.reference = rows.size();
    }
    rungs->push_back(std::move(rung));
    rows.push_back(row);
  }
  if (!header) throw InputError(csv.string() + ": no header line");
  for (std::size_t k = 0; k < rows.size(); ++k)
    rows[k].rung = &(*rungs)[k];
  record.rungs = std::move(rungs);
  record.advice.rows = std::move(rows);
  const auto fact = [&](const char* key) {
    return run.has(key) ? std::optional<double>(run.number(key)) : std::nullopt;
  };
  record.advice.tolerance = run.number("tolerance");
  record.advice.from = fact("curve_from").value_or(record.advice.from);
  record.advice.to = fact("curve_to").value_or(record.advice.to);
  record.advice.seed_scatter = fact("seed_scatter");
  if (run.has("pick")) record.pick = run.text("pick");
  if (run.has("reference")) record.reference = run.text("reference");
  record.pick_error = fact("pick_error_vs_reference");
  record.cost_saved_factor = fact("cost_saved_factor");
  record.predicted_full_run_counted_cost = fact("predicted_full_run_counted_cost");
  record.cpu_saved_factor = fact("cpu_saved_factor");
  record.predicted_full_run_cpu_s = fact("predicted_full_run_cpu_s");
  if (run.has("full_bodies")) record.full_bodies = static_cast<int>(run.integer("full_bodies"));
  return record;
}

Chart speed_accuracy_chart(const Advice& advice) {
  // A compaction ladder spans decades, from plain spheres hundreds of times off to fine bodies a
  // few percent off: both axes logarithmic there, and the references (zero) left out.
  const bool compaction = std::any_of(advice.rows.begin(), advice.rows.end(),
                                      [](const AdviceRow& r) { return r.rung->compaction; });
  Chart chart{fmt::format("Each rung against the finest (curves over {:.3g}-{:.3g})", advice.from,
                          advice.to),
              "counted cost of the run (sub-sphere-, contact- and bond-steps)",
              compaction ? "largest of curve RMS, peak, recovery, Py differences [%]"
                         : "RMS difference from the finest rung [%]",
              "counted_cost",
              "error_percent",
              {}};
  chart.log_x = chart.log_y = compaction;
  std::map<double, Series> by_fraction;
  double least = INFINITY, most = 0.0;
  for (const AdviceRow& row : advice.rows) {
    if (!row.rung->stable() || (compaction && row.status == RungStatus::reference) ||
        row.rung->counted_cost < 0)
      continue;
    const double cost = static_cast<double>(row.rung->counted_cost);
    Series& s = by_fraction[row.rung->time_step_fraction];
    s.title = fmt::format("step {:.3g} of critical", row.rung->time_step_fraction);
    s.style = SeriesStyle::markers;
    s.x.push_back(cost);
    s.y.push_back(100.0 * row.error);
    least = std::min(least, cost);
    most = std::max(most, cost);
  }
  if (!compaction || !std::isfinite(least)) least = 0.0;
  int colour = 1;
  for (auto& [fraction, series] : by_fraction) {
    series.colour = colour++;
    chart.series.push_back(std::move(series));
  }
  chart.series.push_back(Series{fmt::format("tolerance {:.3g} %", 100.0 * advice.tolerance),
                                {least, most},
                                {100.0 * advice.tolerance, 100.0 * advice.tolerance},
                                SeriesStyle::dashed,
                                8});
  if (advice.seed_scatter)
    chart.series.push_back(Series{
        fmt::format("seed-to-seed scatter of the finest {:.3g} %", 100.0 * *advice.seed_scatter),
        {least, most},
        {100.0 * *advice.seed_scatter, 100.0 * *advice.seed_scatter},
        SeriesStyle::dashed,
        6});
  if (advice.pick && advice.rows[*advice.pick].rung->counted_cost >= 0) {
    const AdviceRow& row = advice.rows[*advice.pick];
    chart.series.push_back(Series{fmt::format("pick: {}", row.rung->label),
                                  {static_cast<double>(row.rung->counted_cost)},
                                  {100.0 * row.error},
                                  SeriesStyle::points,
                                  7});
  }
  return chart;
}

Chart stability_map_chart(const Advice& advice) {
  std::set<int> counts;
  std::set<double> scales;
  for (const AdviceRow& row : advice.rows) {
    counts.insert(row.rung->sub_spheres);
    scales.insert(row.rung->density_scale);
  }
  // The step against what else the ladder varies: the sub-sphere count, else the mass scaling
  // (a bed's ladder at one count); with both, one series per status and mass scaling, so that no
  // rung hides behind another of the same count and step.
  const bool by_scale = counts.size() == 1 && scales.size() > 1;
  const bool split_by_scale = counts.size() > 1 && scales.size() > 1;
  Chart chart{fmt::format("Stability map: within {:.3g} % of the finest, off, or diverged",
                          100.0 * advice.tolerance),
              by_scale ? "mass scaling (run.density_scale)" : "sub-spheres",
              "time step [fraction of the critical step]",
              by_scale ? "density_scale" : "sub_spheres",
              "time_step_fraction",
              {}};
  chart.log_x = by_scale;
  const std::pair<RungStatus, const char*> kinds[] = {
      {RungStatus::reference, "reference (finest stable)"},
      {RungStatus::within, "stable, within tolerance"},
      {RungStatus::off, "stable, off by more"},
      {RungStatus::diverged, "diverged (exit 1)"},
      {RungStatus::refused, "refused by the step checks (exit 2)"}};
  // One series of the rungs of `status` (and of mass scaling `scale`, when given).
  const auto add = [&](std::string title, int colour, RungStatus status,
                       std::optional<double> scale) {
    Series s{std::move(title), {}, {}, SeriesStyle::markers, colour};
    for (const AdviceRow& row : advice.rows)
      if (row.status == status && (!scale || row.rung->density_scale == *scale)) {
        s.x.push_back(by_scale ? row.rung->density_scale : row.rung->sub_spheres);
        s.y.push_back(row.rung->time_step_fraction);
      }
    if (!s.x.empty()) chart.series.push_back(std::move(s));
  };
  int colour = 1;
  for (const auto& [status, title] : kinds) {
    const int status_colour = colour++;
    if (!split_by_scale) {
      add(title, status_colour, status, std::nullopt);
      continue;
    }
    for (const double scale : scales)
      add(fmt::format("{}, density scale {:g}", title, scale), 0, status, scale);
  }
  return chart;
}

}  // namespace shapepress::analysis
