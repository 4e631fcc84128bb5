#include "analysis/plate_study.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "analysis/plate_analysis.hpp"
#include "analysis/sphere_plates.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"

namespace shapepress::analysis {
namespace {

// A column of a plate run along the loading (deformation increasing), from (0, 0).
Curve loading_curve(const PlateCurve& c, const std::vector<double>& column,
                    const std::string& label) {
  Curve curve{{0.0}, {0.0}, label};  // both plates touch at zero force
  for (std::size_t i = 0; i < c.deformation.size(); ++i)
    if (c.deformation[i] > curve.x.back()) {
      curve.x.push_back(c.deformation[i]);
      curve.y.push_back(column[i]);
    }
  return curve;
}

Curve loading_curve(const PlateCurve& c, const std::string& label) {
  return loading_curve(c, c.top_force, label);
}

// The standard error of a mean of fills along the loading, sd/√K (zero for one fill).
Curve standard_error_curve(const PlateCurve& c) {
  std::vector<double> error(c.deformation.size(), 0.0);
  if (!c.top_force_sd.empty())
    for (std::size_t i = 0; i < error.size(); ++i)
      error[i] = c.top_force_sd[i] / std::sqrt(static_cast<double>(c.fills));
  return loading_curve(c, error, "standard error");
}

int steps_within(const PlateStudyRow& row, double tolerance, double errors) {
  return static_cast<int>(
      std::count_if(row.steps.begin(), row.steps.end(), [&](const PlateStep& s) {
        return std::fabs(s.versus_finest) < tolerance + errors * s.versus_finest_error;
      }));
}

// The FEM runs by element count, each against the finest; every BMS row against it too.
void add_fem_rows(const std::vector<LoadedRun>& runs, PlateStudy& study) {
  std::vector<const LoadedRun*> fem;
  for (const LoadedRun& run : runs)
    if (run.plate && run.plate->particle == "fem" && run.plate->elements > 0) fem.push_back(&run);
  if (fem.empty()) return;
  std::stable_sort(fem.begin(), fem.end(), [](const LoadedRun* a, const LoadedRun* b) {
    return a->plate->elements < b->plate->elements;
  });
  const Curve finest = loading_curve(*fem.back()->plate, fem.back()->label);
  const double to = std::min(study.to, finest.x.back());
  for (const LoadedRun* run : fem) {
    FemStudyRow row{
        run->label, run->plate->elements, run->plate->cpu_seconds, run->plate->wall_seconds, {}};
    row.versus_finest_fem =
        compare_curves(loading_curve(*run->plate, run->label), finest, study.from,
                       std::min(to, run->plate->deformation.back()));
    study.fem.push_back(row);
  }
  for (PlateStudyRow& row : study.rows)
    for (const LoadedRun& run : runs)
      if (run.label == row.label && run.plate)
        row.versus_fem = compare_curves(loading_curve(*run.plate, run.label), finest, study.from,
                                        std::min(to, run.plate->deformation.back()));
}

}  // namespace

std::optional<PlateStudy> plate_study(const std::vector<LoadedRun>& runs,
                                      std::optional<double> poisson_ratio, double from, double to) {
  std::vector<const LoadedRun*> members;
  for (const LoadedRun& run : runs)
    // CMS clumps have their own study; an FEM run is a reference curve, not a count of spheres.
    if (run.plate && run.plate->sub_spheres > 0 && run.plate->particle != "cms" &&
        run.plate->particle != "fem")
      members.push_back(&run);
  // A study compares sub-sphere counts: it needs two agglomerates (N > 1), not only single
  // spheres (the demo's Hertz and multi-contact spheres are N = 1 each).
  const auto agglomerates = std::count_if(
      members.begin(), members.end(), [](const LoadedRun* r) { return r->plate->sub_spheres > 1; });
  if (agglomerates < 2) return std::nullopt;
  PlateStudy study;
  const LoadedRun* finest =
      *std::max_element(members.begin(), members.end(), [](const LoadedRun* a, const LoadedRun* b) {
        return a->plate->sub_spheres < b->plate->sub_spheres;
      });
  study.finest = finest->label;
  double reach = to;
  for (const LoadedRun* run : members)
    reach = std::min(reach, run->plate->deformation.back());
  study.from = from;
  study.to = reach;
  const Curve reference = loading_curve(*finest->plate, finest->label);
  const Curve reference_error = standard_error_curve(*finest->plate);
  for (const LoadedRun* run : members) {
    PlateStudyRow row;
    row.label = run->label;
    row.sub_spheres = run->plate->sub_spheres;
    row.fills = run->plate->fills;
    row.cpu_seconds = run->plate->cpu_seconds;
    row.wall_seconds = run->plate->wall_seconds;
    const Curve curve = loading_curve(*run->plate, run->label);
    const Curve error = standard_error_curve(*run->plate);
    row.versus_finest = compare_curves(curve, reference, study.from, study.to);
    // The convergence test: every 1 % step of deformation in the window.
    for (int step = static_cast<int>(std::ceil(study.from * 100 - 1e-9));
         step <= static_cast<int>(std::floor(study.to * 100 + 1e-9)); ++step) {
      const double x = step / 100.0;
      const double f = interpolate(reference, x);
      if (f == 0.0) continue;
      PlateStep s;
      s.deformation = x;
      s.force = interpolate(curve, x);
      s.force_error = interpolate(error, x);
      s.versus_finest = s.force / f - 1.0;
      // Of a ratio of two independent means: (σa/b)² + (a σb/b²)².
      const double fe = interpolate(reference_error, x);
      s.versus_finest_error =
          run == finest ? 0.0 : std::hypot(s.force_error / f, s.force * fe / (f * f));
      row.max_step_versus_finest = std::max(row.max_step_versus_finest, std::fabs(s.versus_finest));
      row.steps.push_back(s);
    }
    if (poisson_ratio) {
      const ElasticSphere sphere = infer_sphere(*run->plate, *poisson_ratio);
      std::vector<double> approaches;
      for (double d : curve.x)
        approaches.push_back(2.0 * sphere.radius * d);
      const Curve tatara{curve.x, tatara_plate_forces(sphere, approaches), "Tatara"};
      row.versus_tatara = compare_curves(curve, tatara, study.from, study.to);
    }
    study.rows.push_back(std::move(row));
  }
  add_fem_rows(runs, study);
  return study;
}

namespace {

// Every agglomerate against the finest at the 1 % steps, the next-finest with a band of two
// standard errors of the difference (means of fills), and the ±2 % convergence criterion's lines.
Chart plate_convergence_chart(const PlateStudy& study) {
  Chart chart{"Convergence: each N against the finest N at 1 % steps",
              "deformation [%]",
              "force against the finest N [%]",
              "deformation_percent",
              "difference_percent",
              {}};
  std::vector<const PlateStudyRow*> rows;
  for (const PlateStudyRow& row : study.rows)
    if (row.sub_spheres > 1 && row.label != study.finest) rows.push_back(&row);
  std::sort(rows.begin(), rows.end(), [](const PlateStudyRow* a, const PlateStudyRow* b) {
    return a->sub_spheres < b->sub_spheres;
  });
  int colour = 1;
  for (const PlateStudyRow* row : rows) {
    Series s{
        fmt::format("N = {} ({} fill{})", row->sub_spheres, row->fills, row->fills > 1 ? "s" : ""),
        {},
        {},
        SeriesStyle::lines,
        colour++};
    for (const PlateStep& step : row->steps)
      s.x.push_back(100 * step.deformation), s.y.push_back(100 * step.versus_finest);
    chart.series.push_back(s);
  }
  if (!rows.empty() && rows.back()->fills > 1) {
    const PlateStudyRow& next = *rows.back();
    Series low{fmt::format("N = {}, ±2 standard errors", next.sub_spheres),
               {},
               {},
               SeriesStyle::dashed,
               colour - 1};
    Series high{"", {}, {}, SeriesStyle::dashed, colour - 1};
    for (const PlateStep& step : next.steps) {
      low.x.push_back(100 * step.deformation);
      low.y.push_back(100 * (step.versus_finest - 2 * step.versus_finest_error));
      high.x.push_back(100 * step.deformation);
      high.y.push_back(100 * (step.versus_finest + 2 * step.versus_finest_error));
    }
    chart.series.push_back(low), chart.series.push_back(high);
  }
  Series plus{"±2 % (convergence criterion)",
              {100 * study.from, 100 * study.to},
              {2.0, 2.0},
              SeriesStyle::dashed,
              8};
  Series minus{"", {100 * study.from, 100 * study.to}, {-2.0, -2.0}, SeriesStyle::dashed, 8};
  chart.series.push_back(plus), chart.series.push_back(minus);
  return chart;
}

}  // namespace

std::vector<Chart> plate_study_charts(const PlateStudy& study) {
  Chart cost{"CPU time against the number of sub-spheres (paper Fig. 2b)",
             "sub-spheres N",
             "CPU time to 40 % [s]",
             "sub_spheres",
             "cpu_s",
             {}};
  Series bms{"BMS, CPU seconds", {}, {}, SeriesStyle::lines, 1};
  Series wall{"BMS, wall seconds", {}, {}, SeriesStyle::dashed, 2};
  for (const PlateStudyRow& row : study.rows)
    if (row.sub_spheres > 1 && row.cpu_seconds >= 0.0) {
      bms.x.push_back(row.sub_spheres), bms.y.push_back(row.cpu_seconds);
      wall.x.push_back(row.sub_spheres), wall.y.push_back(row.wall_seconds);
    }
  const auto by_x = [](Series& s) {
    std::vector<std::size_t> order(s.x.size());
    for (std::size_t i = 0; i < order.size(); ++i)
      order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return s.x[a] < s.x[b]; });
    Series sorted = s;
    for (std::size_t i = 0; i < order.size(); ++i)
      sorted.x[i] = s.x[order[i]], sorted.y[i] = s.y[order[i]];
    s = sorted;
  };
  by_x(bms), by_x(wall);
  cost.series = {bms, wall};
  if (!study.fem.empty()) {
    // The paper's Fig. 2b sets the FEM's elements beside the BMS sub-spheres on one axis.
    cost.title = "CPU time against resolution: BMS sub-spheres, FEM elements (paper Fig. 2b)";
    cost.x_label = "sub-spheres N (BMS) or elements (FEM)";
    Series fem{"FEM (CalculiX), CPU seconds", {}, {}, SeriesStyle::lines, 4};
    for (const FemStudyRow& row : study.fem)
      fem.x.push_back(row.elements), fem.y.push_back(row.cpu_seconds);
    cost.series.push_back(fem);
  }
  Chart accuracy{fmt::format("Speed against accuracy: RMS force error over {:.0f}-{:.0f} % "
                             "deformation",
                             100 * study.from, 100 * study.to),
                 "CPU time [s]",
                 "RMS relative force error [%]",
                 "cpu_s",
                 "rms_percent",
                 {}};
  // One line per comparison through the BMS runs in order of cost (labelled by N in the CSV),
  // and the single Hertz sphere as its own points.
  Series finest{"BMS vs the finest N", {}, {}, SeriesStyle::lines, 1};
  Series tatara{"BMS vs Tatara", {}, {}, SeriesStyle::dashed, 2};
  Series hertz{"Hertz sphere vs the finest N and vs Tatara", {}, {}, SeriesStyle::points, 3};
  for (const PlateStudyRow& row : study.rows) {
    if (row.sub_spheres <= 1) {
      hertz.x.push_back(row.cpu_seconds), hertz.y.push_back(100 * row.versus_finest.rms_relative);
      if (row.versus_tatara)
        hertz.x.push_back(row.cpu_seconds),
            hertz.y.push_back(100 * row.versus_tatara->rms_relative);
      continue;
    }
    if (row.label != study.finest)
      finest.x.push_back(row.cpu_seconds), finest.y.push_back(100 * row.versus_finest.rms_relative);
    if (row.versus_tatara)
      tatara.x.push_back(row.cpu_seconds),
          tatara.y.push_back(100 * row.versus_tatara->rms_relative);
  }
  by_x(finest), by_x(tatara);
  accuracy.series = {finest, tatara};
  if (!hertz.x.empty()) accuracy.series.push_back(hertz);
  if (!study.fem.empty()) {
    Series bms_fem{"BMS vs the finest FEM", {}, {}, SeriesStyle::dashed, 4};
    Series fem{"FEM vs the finest FEM", {}, {}, SeriesStyle::lines, 5};
    for (const PlateStudyRow& row : study.rows)
      if (row.sub_spheres > 1 && row.versus_fem)
        bms_fem.x.push_back(row.cpu_seconds),
            bms_fem.y.push_back(100 * row.versus_fem->rms_relative);
    for (std::size_t i = 0; i + 1 < study.fem.size(); ++i)
      fem.x.push_back(study.fem[i].cpu_seconds),
          fem.y.push_back(100 * study.fem[i].versus_finest_fem.rms_relative);
    by_x(bms_fem), by_x(fem);
    if (!bms_fem.x.empty()) accuracy.series.push_back(bms_fem);
    if (!fem.x.empty()) accuracy.series.push_back(fem);
  }
  return {cost, accuracy, plate_convergence_chart(study)};
}

void write_plate_study_csv(const std::filesystem::path& path, const PlateStudy& study) {
  CsvWriter csv(
      path, {"label", "sub_spheres", "fills", "cpu_s", "wall_s", "rms_vs_finest", "max_vs_finest",
             "max_step_vs_finest", "steps", "steps_within_2pc", "steps_within_2pc_2se",
             "rms_vs_tatara", "max_vs_tatara", "rms_vs_finest_fem"});
  csv.comment(fmt::format("relative force errors over deformation [{:.4g}, {:.4g}]; finest: {}",
                          study.from, study.to, study.finest));
  csv.comment("max_step_vs_finest: largest relative difference at the 1 % deformation steps");
  csv.comment(
      "steps_within_2pc: 1 % steps within 2 % of the finest; steps_within_2pc_2se: within 2 % "
      "plus two standard errors of the difference (means of fills: plate_steps.csv)");
  for (const PlateStudyRow& r : study.rows)
    csv.row_text({r.label, fmt::format("{}", r.sub_spheres), fmt::format("{}", r.fills),
                  format_number(r.cpu_seconds), format_number(r.wall_seconds),
                  format_number(r.versus_finest.rms_relative),
                  format_number(r.versus_finest.max_relative),
                  format_number(r.max_step_versus_finest), fmt::format("{}", r.steps.size()),
                  fmt::format("{}", steps_within(r, 0.02, 0.0)),
                  fmt::format("{}", steps_within(r, 0.02, 2.0)),
                  r.versus_tatara ? format_number(r.versus_tatara->rms_relative) : "",
                  r.versus_tatara ? format_number(r.versus_tatara->max_relative) : "",
                  r.versus_fem ? format_number(r.versus_fem->rms_relative) : ""});
  csv.commit();
}

void write_fem_study_csv(const std::filesystem::path& path, const PlateStudy& study) {
  if (study.fem.empty()) return;
  CsvWriter csv(path,
                {"label", "elements", "cpu_s", "wall_s", "rms_vs_finest_fem", "max_vs_finest_fem"});
  csv.comment(fmt::format(
      "FEM runs (fem-plate) against the finest, {}, over deformation [{:.4g}, {:.4g}]; the BMS "
      "runs against it: plate_study.csv rms_vs_finest_fem",
      study.fem.back().label, study.from, study.to));
  for (const FemStudyRow& r : study.fem)
    csv.row_text({r.label, fmt::format("{}", r.elements), format_number(r.cpu_seconds),
                  format_number(r.wall_seconds), format_number(r.versus_finest_fem.rms_relative),
                  format_number(r.versus_finest_fem.max_relative)});
  csv.commit();
}

void write_plate_steps_csv(const std::filesystem::path& path, const PlateStudy& study) {
  CsvWriter csv(path, {"label", "sub_spheres", "fills", "deformation", "force_N", "force_se_N",
                       "vs_finest", "vs_finest_se"});
  csv.comment(fmt::format(
      "every run at the 1 % steps; vs_finest = F / F_finest - 1 against {}; the standard errors "
      "are those of means of fills (top_force_sd_N / sqrt(fills)), 0 for one fill",
      study.finest));
  for (const PlateStudyRow& r : study.rows)
    for (const PlateStep& s : r.steps)
      csv.row_text({r.label, fmt::format("{}", r.sub_spheres), fmt::format("{}", r.fills),
                    format_number(s.deformation), format_number(s.force),
                    format_number(s.force_error), format_number(s.versus_finest),
                    format_number(s.versus_finest_error)});
  csv.commit();
}

namespace {

constexpr double not_reached = std::numeric_limits<double>::quiet_NaN();

ConvergenceRun convergence_run(const LoadedRun& run, const std::vector<double>& deformations) {
  const PlateCurve& c = *run.plate;
  ConvergenceRun out;
  out.label = run.label;
  out.sub_spheres = c.sub_spheres;
  out.cpu_seconds = c.cpu_seconds;
  const Curve curve = loading_curve(c, run.label);
  out.reached = curve.x.back();
  for (double d : deformations)
    // A run that stops a rounding short of a deformation (0.39999 for 40 %) still reaches it.
    out.force.push_back(d <= out.reached + 1e-3 ? interpolate(curve, d) : not_reached);
  for (std::size_t i = 0; i < c.top_force.size(); ++i) {
    out.finite = out.finite && std::isfinite(c.top_force[i]);
    if (i < c.contacts.size()) out.finite = out.finite && std::isfinite(c.contacts[i]);
    if (i == 0 || c.deformation[i] <= c.deformation[i - 1]) continue;  // loading rows only
    if (c.top_force[i] < 0.99 * c.top_force[i - 1]) ++out.force_drops;
    if (i < c.contacts.size() && c.contacts[i] < c.contacts[i - 1]) ++out.contact_drops;
  }
  return out;
}

// (max − min)/mean of the finite values; NaN with fewer than two.
double spread_of(const std::vector<double>& values) {
  double low = HUGE_VAL, high = -HUGE_VAL, sum = 0.0;
  int n = 0;
  for (double v : values)
    if (std::isfinite(v)) low = std::min(low, v), high = std::max(high, v), sum += v, ++n;
  if (n < 2 || sum == 0.0) return not_reached;
  return (high - low) / std::fabs(sum / n);
}

std::string percent_label(double deformation) {
  return fmt::format("{:.0f} %", 100.0 * deformation);
}

}  // namespace

std::optional<ConvergenceStudy> convergence_study(const std::vector<LoadedRun>& runs,
                                                  const std::map<std::string, int>& spread_from,
                                                  std::vector<double> deformations) {
  std::map<std::string, std::vector<const LoadedRun*>> by_method;
  for (const LoadedRun& run : runs)
    if (run.plate && run.plate->sub_spheres > 1 && !run.plate->particle.empty())
      by_method[run.plate->particle].push_back(&run);
  if (by_method["cms"].size() < 2) return std::nullopt;
  ConvergenceStudy study;
  study.deformations = std::move(deformations);
  for (auto& [method, members] : by_method) {
    if (members.size() < 2) continue;
    std::stable_sort(members.begin(), members.end(), [](const LoadedRun* a, const LoadedRun* b) {
      return a->plate->sub_spheres < b->plate->sub_spheres;
    });
    MethodConvergence m;
    m.method = method;
    for (const LoadedRun* run : members)
      m.runs.push_back(convergence_run(*run, study.deformations));
    for (std::size_t k = 0; k < m.runs.size(); ++k)
      for (std::size_t d = 0; d < study.deformations.size(); ++d)
        m.runs[k].change.push_back(
            k == 0 ? not_reached : spread_of({m.runs[k - 1].force[d], m.runs[k].force[d]}));
    const auto given = spread_from.find(method);
    m.spread_from =
        given != spread_from.end() ? given->second : m.runs[m.runs.size() - 2].sub_spheres;
    for (const ConvergenceRun& r : m.runs)
      if (r.sub_spheres >= m.spread_from) ++m.spread_runs, m.spread_to = r.sub_spheres;
    if (m.spread_runs < 2)
      throw InputError(fmt::format(
          "--spread-from {}={}: {} run(s) of {} have N >= {}, the spread needs two (runs have N "
          "up to {})",
          method, m.spread_from, m.spread_runs, method, m.spread_from, m.runs.back().sub_spheres));
    for (std::size_t d = 0; d < study.deformations.size(); ++d) {
      std::vector<double> values;
      for (const ConvergenceRun& r : m.runs)
        if (r.sub_spheres >= m.spread_from) values.push_back(r.force[d]);
      m.spread.push_back(spread_of(values));
    }
    study.methods.push_back(std::move(m));
  }
  for (const auto& [method, n] : spread_from)
    if (std::none_of(study.methods.begin(), study.methods.end(),
                     [&](const MethodConvergence& m) { return m.method == method; }))
      throw InputError(
          fmt::format("--spread-from {}={}: no two plate runs with particle = {} among the runs",
                      method, n, method));
  return study;
}

std::vector<Chart> convergence_charts(const ConvergenceStudy& study,
                                      const std::vector<LoadedRun>& runs,
                                      std::optional<double> poisson_ratio) {
  Chart force{"Rigid multi-sphere (CMS) sphere: force vs deformation for every N",
              "deformation Delta/(2R)",
              "plate force [N]",
              "deformation",
              "force_N",
              {}};
  Chart contacts{"CMS: sub-sphere contacts with the plates (drops are the force dropouts)",
                 "deformation Delta/(2R)",
                 "contacts",
                 "deformation",
                 "contacts",
                 {}};
  // The finest run of every method: the CMS ladder is drawn whole, the others by their best.
  std::map<std::string, const LoadedRun*> finest;
  const LoadedRun* longest_cms = nullptr;
  for (const LoadedRun& run : runs) {
    if (!run.plate || run.plate->sub_spheres <= 1) continue;
    const PlateCurve& c = *run.plate;
    if (c.particle == "cms") {
      force.series.push_back({fmt::format("CMS N = {}", c.sub_spheres), c.deformation, c.top_force,
                              SeriesStyle::lines});
      if (!c.contacts.empty())
        contacts.series.push_back({fmt::format("CMS N = {}", c.sub_spheres), c.deformation,
                                   c.contacts, SeriesStyle::lines});
      if (!longest_cms || c.deformation.back() > longest_cms->plate->deformation.back())
        longest_cms = &run;
      continue;
    }
    const LoadedRun*& best = finest[c.particle.empty() ? std::string("?") : c.particle];
    if (!best || c.sub_spheres > best->plate->sub_spheres) best = &run;
  }
  for (const auto& [method, run] : finest)
    force.series.push_back({fmt::format("{} N = {} (finest)", method == "bms" ? "BMS" : method,
                                        run->plate->sub_spheres),
                            run->plate->deformation, run->plate->top_force, SeriesStyle::lines});
  if (longest_cms) {
    // The theories of the whole sphere, from the Hertz column the CMS run carries.
    const PlateCurve& c = *longest_cms->plate;
    const Curve hertz = monotone_prefix({c.deformation, c.hertz_force, "Hertz"});
    force.series.push_back({"Hertz", hertz.x, hertz.y, SeriesStyle::dashed});
    if (poisson_ratio) {
      const ElasticSphere sphere = infer_sphere(c, *poisson_ratio);
      std::vector<double> approaches;
      for (double d : hertz.x)
        approaches.push_back(2 * sphere.radius * d);
      force.series.push_back({fmt::format("Tatara (nu = {})", *poisson_ratio), hertz.x,
                              tatara_plate_forces(sphere, approaches), SeriesStyle::dashed});
    }
  }
  Chart change{"Change of the force from the next coarser N (converging: falls towards 0)",
               "sub-spheres N",
               "|F(N) - F(N_previous)| / mean [%]",
               "sub_spheres",
               "change_percent",
               {}};
  Chart spread{"Spread (max - min)/mean of the force across N",
               "deformation Delta/(2R) [%]",
               "spread across N [%]",
               "deformation_percent",
               "spread_percent",
               {}};
  int colour = 0;
  for (const MethodConvergence& m : study.methods) {
    const std::string name = m.method == "bms" ? "BMS" : m.method == "cms" ? "CMS" : m.method;
    const SeriesStyle style = m.method == "cms" ? SeriesStyle::lines : SeriesStyle::dashed;
    for (std::size_t d = 0; d < study.deformations.size(); ++d) {
      Series s{fmt::format("{} at {}", name, percent_label(study.deformations[d])),
               {},
               {},
               style,
               static_cast<int>(d) + 1};
      for (const ConvergenceRun& r : m.runs)
        if (std::isfinite(r.change[d]))
          s.x.push_back(r.sub_spheres), s.y.push_back(100.0 * r.change[d]);
      change.series.push_back(std::move(s));
    }
    Series s{
        fmt::format("{}, N = {}-{} ({} runs)", name, m.spread_from, m.spread_to, m.spread_runs),
        {},
        {},
        style,
        ++colour};
    for (std::size_t d = 0; d < study.deformations.size(); ++d)
      s.x.push_back(100.0 * study.deformations[d]), s.y.push_back(100.0 * m.spread[d]);
    spread.series.push_back(std::move(s));
  }
  return {force, contacts, change, spread};
}

void write_convergence_csv(const std::filesystem::path& folder, const ConvergenceStudy& study) {
  std::vector<std::string> columns = {"method", "label", "sub_spheres", "cpu_s", "max_deformation"};
  for (double d : study.deformations)
    columns.push_back(fmt::format("force_{:.0f}pct_N", 100 * d));
  for (double d : study.deformations)
    columns.push_back(fmt::format("change_{:.0f}pct", 100 * d));
  for (const char* c : {"force_drops", "contact_drops"})
    columns.emplace_back(c);
  CsvWriter runs(folder / "convergence_runs.csv", columns);
  runs.comment(
      "force at fixed deformations of the loading branch; change = |F - F(next coarser "
      "N)| / mean of the two");
  runs.comment(
      "force_drops: loading rows with F < 0.99 F(previous row); contact_drops: rows "
      "with fewer contacts than the row before");
  for (const MethodConvergence& m : study.methods)
    for (const ConvergenceRun& r : m.runs) {
      std::vector<std::string> row = {m.method, r.label, fmt::format("{}", r.sub_spheres),
                                      format_number(r.cpu_seconds), format_number(r.reached)};
      for (double f : r.force)
        row.push_back(std::isfinite(f) ? format_number(f) : "");
      for (double c : r.change)
        row.push_back(std::isfinite(c) ? format_number(c) : "");
      row.push_back(fmt::format("{}", r.force_drops));
      row.push_back(fmt::format("{}", r.contact_drops));
      runs.row_text(row);
    }
  runs.commit();
  CsvWriter spread(
      folder / "convergence_spread.csv",
      {"method", "from_sub_spheres", "to_sub_spheres", "runs", "deformation", "spread"});
  spread.comment("spread = (max - min)/mean of the loading force over the runs with N in range");
  for (const MethodConvergence& m : study.methods)
    for (std::size_t d = 0; d < study.deformations.size(); ++d)
      spread.row_text({m.method, fmt::format("{}", m.spread_from), fmt::format("{}", m.spread_to),
                       fmt::format("{}", m.spread_runs), format_number(study.deformations[d]),
                       std::isfinite(m.spread[d]) ? format_number(m.spread[d]) : ""});
  spread.commit();
}

}  // namespace shapepress::analysis
