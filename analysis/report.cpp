#include "analysis/report.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "analysis/curves.hpp"
#include "analysis/measured_curve.hpp"
#include "analysis/plate_analysis.hpp"
#include "analysis/plate_study.hpp"
#include "analysis/plot.hpp"
#include "analysis/report_html.hpp"
#include "analysis/runs.hpp"
#include "common/atomic_file.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/provenance.hpp"

namespace shapepress::analysis {
namespace {

constexpr double mega = 1e6;

// What a run pressed, in words: "500 spheres", "20 BMS bodies of 100 sub-spheres", "Hertz
// sphere", "BMS of 545 sub-spheres".
std::string what_was_pressed(const LoadedRun& run) {
  if (run.bed) {
    const BedFacts& bed = *run.bed;
    const long per_body = std::lround(bed.sub_spheres_per_body);
    if (bed.particle_kind == "sphere") return fmt::format("{} spheres", bed.bodies);
    if (bed.particle_kind == "bms")
      return fmt::format("{} BMS bodies of {} sub-spheres", bed.bodies, per_body);
    if (bed.particle_kind == "cms")
      return fmt::format("{} CMS clumps of {} sub-spheres", bed.bodies, per_body);
    return fmt::format("{} {} bodies", bed.bodies, bed.particle_kind);
  }
  if (!run.plate) return {};
  const PlateCurve& c = *run.plate;
  std::string what;
  if (c.particle == "sphere")
    what = c.normal_law == "hertz"          ? "Hertz sphere"
           : c.normal_law == "multicontact" ? "multi-contact sphere"
                                            : "sphere";
  else if (c.particle == "fem")
    what = fmt::format("FEM of {} elements", c.elements);
  else if (c.particle == "bms" || c.particle == "cms")
    what = fmt::format("{} of {} sub-spheres", c.particle == "bms" ? "BMS" : "CMS", c.sub_spheres);
  else
    what = c.particle;
  // No comma: a label is a cell of the report's CSV tables, which readers split on commas.
  if (c.fills > 1) what += fmt::format(" (mean of {} fills)", c.fills);
  return what;
}

std::vector<LoadedRun> load_runs(const ReportOptions& options) {
  std::vector<LoadedRun> runs;
  std::vector<bool> named;  // labelled by their config and what they pressed
  for (const std::filesystem::path& folder : options.runs) {
    LoadedRun run;
    run.files = find_run(folder);
    if (run.files.kind == RunKind::compaction) {
      run.punch = read_punch_curve(run.files.csv);
      run.compaction = analyse_compaction(*run.punch, options.windows);
      run.bed = bed_facts(run.files.metadata, *run.punch);
    } else {
      run.plate = read_plate_curve(run.files.csv);
      double from_fraction = 0.05;  // analyse_plate's: of the deepest deformation
      if (options.plate_compare_from) {
        const double deepest =
            *std::max_element(run.plate->deformation.begin(), run.plate->deformation.end());
        if (!(*options.plate_compare_from < deepest))
          throw InputError(fmt::format("--compare-from {}: {} reaches deformation {} only",
                                       *options.plate_compare_from, run.files.csv.string(),
                                       deepest));
        from_fraction = *options.plate_compare_from / deepest;
      }
      run.plate_metrics = analyse_plate(*run.plate, options.poisson_ratio, from_fraction);
    }
    // A run is named by its config and what it pressed ("compact-demo: 500 spheres"), not by
    // its folder, whose name a Makefile chose ("run", "compact"); a run whose record names no
    // config keeps its folder's name.
    const std::string config = config_name(run.files.metadata);
    named.push_back(!config.empty());
    run.label = config.empty() ? std::filesystem::weakly_canonical(folder).filename().string()
                               : fmt::format("{}: {}", config, what_was_pressed(run));
    runs.push_back(std::move(run));
  }
  // Two runs with one name (one config pressing two packings; folders a/run and b/run) would
  // share a legend entry: they are told apart by their folder and its parent.
  std::vector<bool> shared(runs.size(), false);
  for (std::size_t i = 0; i < runs.size(); ++i)
    for (std::size_t j = 0; j < runs.size(); ++j)
      if (i != j && runs[i].label == runs[j].label) shared[i] = true;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (!shared[i]) continue;
    const auto path = std::filesystem::weakly_canonical(options.runs[i]);
    const std::string folder = (path.parent_path().filename() / path.filename()).string();
    runs[i].label = named[i] ? fmt::format("{} ({})", runs[i].label, folder) : folder;
  }
  return runs;
}

std::vector<double> scaled(const std::vector<double>& values, double factor) {
  std::vector<double> out;
  out.reserve(values.size());
  for (double v : values)
    out.push_back(v * factor);
  return out;
}

// Rows [first, last) of a column.
std::vector<double> rows_of(const std::vector<double>& values, std::size_t first,
                            std::size_t last) {
  return {values.begin() + static_cast<std::ptrdiff_t>(first),
          values.begin() + static_cast<std::ptrdiff_t>(last)};
}

std::size_t unload_start(const PunchCurve& c) {
  for (std::size_t i = 0; i < c.phase.size(); ++i)
    if (c.phase[i] >= static_cast<int>(PunchPhase::unload)) return i;
  return c.phase.size();
}

// The measured curves over the runs, as points in black (gnuplot colour 8 is taken by runs
// only in a report of eight or more).
void add_experiments(Chart& stress_strain, Chart& density,
                     const std::vector<ExperimentComparison>& experiments) {
  for (const ExperimentComparison& e : experiments) {
    const MeasuredCurve& c = e.curve;
    const std::string label = "measured " + c.source.filename().string();
    if (c.axes == MeasuredAxes::stress_strain)
      stress_strain.series.push_back({label, c.x, scaled(c.y, 1 / mega), SeriesStyle::points, 8});
    else
      density.series.push_back({label, scaled(c.x, 1 / mega), c.y, SeriesStyle::points, 8});
  }
}

std::vector<ExperimentComparison> compare_experiments(const std::vector<LoadedRun>& runs,
                                                      const ReportOptions& options) {
  std::vector<ExperimentComparison> comparisons;
  for (const std::filesystem::path& file : options.experiments) {
    ExperimentComparison e{read_measured_curve(file), {}};
    const Curve measured = e.curve.loading();
    for (const LoadedRun& run : runs)
      if (run.punch)
        e.runs.emplace_back(run.label, compare_with_measured(
                                           simulated_loading(*run.punch, e.curve.axes), measured));
    comparisons.push_back(std::move(e));
  }
  return comparisons;
}

// Runs whose peak stresses differ more than tenfold (a bed of softly bonded bodies beside one of
// spheres: 0.014 against 1.4 MPa) share no linear stress axis, on which the weaker run is a flat
// line on zero: their stress axes are logarithmic, from a thousandth of the smallest peak [MPa].
std::optional<double> log_stress_from(const std::vector<LoadedRun>& runs) {
  double smallest = HUGE_VAL, largest = 0.0;
  for (const LoadedRun& run : runs) {
    if (!run.compaction || !(run.compaction->peak_stress > 0.0)) continue;
    smallest = std::min(smallest, run.compaction->peak_stress);
    largest = std::max(largest, run.compaction->peak_stress);
  }
  if (!(largest > 10.0 * smallest)) return std::nullopt;
  return smallest / 1000.0 / mega;
}

std::vector<Chart> compaction_charts(const std::vector<LoadedRun>& runs,
                                     const std::vector<ExperimentComparison>& experiments) {
  Chart stress_strain{"Stress-strain (load solid, unload dashed)",
                      "engineering strain (H0-H)/H0",
                      "punch stress [MPa]",
                      "strain",
                      "stress_MPa",
                      {}};
  Chart density{"Solid fraction vs stress (load solid, unload dashed)",
                "punch stress [MPa]",
                "solid fraction D",
                "stress_MPa",
                "solid_fraction",
                {}};
  Chart heckel{"Heckel plot (points) and fit (dashed)",
               "punch stress P [MPa]",
               "ln(1/(1-D))",
               "stress_MPa",
               "heckel_ln_1_over_1_minus_D",
               {}};
  Chart kawakita{"Kawakita plot (points) and fit (dashed)",
                 "punch stress P [MPa]",
                 "P/C [MPa]",
                 "stress_MPa",
                 "P_over_C_MPa",
                 {}};
  int colour = 0;  // one colour per run across its load/unload and points/fit series
  for (const LoadedRun& run : runs) {
    if (!run.punch) continue;
    ++colour;
    const PunchCurve& c = *run.punch;
    const CompactionMetrics& m = *run.compaction;
    std::vector<double> strain;
    for (double h : c.gap)
      strain.push_back((c.reference_gap - h) / c.reference_gap);
    const std::size_t split = unload_start(c), n = c.gap.size();
    stress_strain.series.push_back({run.label + " load", rows_of(strain, 0, split),
                                    scaled(rows_of(c.stress, 0, split), 1 / mega),
                                    SeriesStyle::lines, colour});
    if (split < n)
      stress_strain.series.push_back({run.label + " unload", rows_of(strain, split - 1, n),
                                      scaled(rows_of(c.stress, split - 1, n), 1 / mega),
                                      SeriesStyle::dashed, colour});
    Series d{run.label, {}, {}, SeriesStyle::lines, colour},
        h{run.label, {}, {}, SeriesStyle::points, colour},
        k{run.label, {}, {}, SeriesStyle::points, colour};
    for (std::size_t i : loading_rows(c)) {
      d.x.push_back(c.stress[i] / mega), d.y.push_back(c.solid_fraction[i]);
      if (c.stress[i] <= 0.0) continue;
      if (c.solid_fraction[i] > 0.0 && c.solid_fraction[i] < 1.0)
        h.x.push_back(c.stress[i] / mega), h.y.push_back(std::log(1 / (1 - c.solid_fraction[i])));
      if (strain[i] > 0.0)
        k.x.push_back(c.stress[i] / mega), k.y.push_back(c.stress[i] / mega / strain[i]);
    }
    density.series.push_back(std::move(d));
    // The unloading on the same axis: beds whose strains count from different heights (spheres
    // and bodies) compared where they are equally dense, the spring-back as the fraction lost.
    if (split < n)
      density.series.push_back(
          {run.label + " unload", scaled(rows_of(c.stress, split - 1, n), 1 / mega),
           rows_of(c.solid_fraction, split - 1, n), SeriesStyle::dashed, colour});
    heckel.series.push_back(std::move(h));
    kawakita.series.push_back(std::move(k));
    // Fit lines over the fitted window: ln(1/(1−D)) = K P + A; P/C = P/a + 1/(a b).
    const double p0 = m.heckel.stress_lower, p1 = m.heckel.stress_upper;
    heckel.series.push_back(
        {fmt::format("{} fit, Py = {:.3g} MPa", run.label, m.heckel.yield_pressure / mega),
         {p0 / mega, p1 / mega},
         {m.heckel.k * p0 + m.heckel.a, m.heckel.k * p1 + m.heckel.a},
         SeriesStyle::dashed,
         colour});
    const double q0 = m.kawakita.stress_lower, q1 = m.kawakita.stress_upper;
    const KawakitaFit& kf = m.kawakita;
    kawakita.series.push_back(
        {fmt::format("{} fit, a = {:.3g}, 1/b = {:.3g} MPa", run.label, kf.a, 1 / kf.b / mega),
         {q0 / mega, q1 / mega},
         {(q0 / kf.a + 1 / (kf.a * kf.b)) / mega, (q1 / kf.a + 1 / (kf.a * kf.b)) / mega},
         SeriesStyle::dashed,
         colour});
  }
  add_experiments(stress_strain, density, experiments);
  if (const std::optional<double> from = log_stress_from(runs)) {
    stress_strain.log_y = true, stress_strain.log_y_from = from;
    for (Chart* chart : {&density, &heckel, &kawakita})
      chart->log_x = true, chart->log_x_from = from;
    kawakita.log_y = true;  // P/C grows with P
    for (Chart* chart : {&stress_strain, &density, &heckel, &kawakita})
      chart->title += " - log stress axis: the runs' peaks differ more than tenfold";
  }
  return {stress_strain, density, heckel, kawakita};
}

// Peak stress, elastic recovery and Heckel Py against the bodies' projected aspect ratio (paper
// §4.4: the shape effect), one marker per compaction run whose bodies' aspect ratio is known;
// nothing with fewer than two.
// Peak stress, elastic recovery and Py of every bed against one of its facts (`x`; beds without
// it are left out), one point per run; empty with fewer than two such beds.
std::vector<Chart> figure_charts(const std::vector<LoadedRun>& runs, const std::string& effect,
                                 const std::string& x_label, const std::string& x_column,
                                 const std::function<std::optional<double>(const BedFacts&)>& x) {
  Chart peak{effect + ": peak stress", x_label, "peak stress [MPa]", x_column,
             "peak_stress_MPa",        {}};
  Chart recovery{effect + ": elastic recovery", x_label, "elastic recovery [%]", x_column,
                 "elastic_recovery_percent",    {}};
  Chart yield{effect + ": Heckel yield pressure",
              x_label,
              "Heckel Py [MPa]",
              x_column,
              "yield_pressure_MPa",
              {}};
  int colour = 0;
  for (const LoadedRun& run : runs) {
    if (!run.bed) continue;
    const std::optional<double> at = x(*run.bed);
    if (!at) continue;
    ++colour;
    const CompactionMetrics& m = *run.compaction;
    peak.series.push_back({run.label, {*at}, {m.peak_stress / mega}, SeriesStyle::markers, colour});
    if (m.unloaded)
      recovery.series.push_back(
          {run.label, {*at}, {100.0 * m.elastic_recovery}, SeriesStyle::markers, colour});
    if (std::isfinite(m.heckel.yield_pressure))
      yield.series.push_back(
          {run.label, {*at}, {m.heckel.yield_pressure / mega}, SeriesStyle::markers, colour});
  }
  if (colour < 2) return {};
  if (log_stress_from(runs)) peak.log_y = yield.log_y = true;
  return {peak, recovery, yield};
}

// The shape effect (paper §4.4, Fig. 8): each bed against its bodies' projected aspect ratio.
std::vector<Chart> shape_effect_charts(const std::vector<LoadedRun>& runs) {
  return figure_charts(runs, "Shape effect", "projected aspect ratio of the bodies (Feret min/max)",
                       "projected_aspect_ratio",
                       [](const BedFacts& bed) { return bed.projected_aspect_ratio; });
}

}  // namespace

std::vector<Chart> bed_size_charts(const std::vector<LoadedRun>& runs) {
  std::map<std::pair<std::string, double>, std::set<std::int64_t>> sizes;
  for (const LoadedRun& run : runs)
    if (run.bed)
      sizes[{run.bed->particle_kind, run.bed->sub_spheres_per_body}].insert(run.bed->bodies);
  const auto varied = [&](const BedFacts& bed) -> std::optional<double> {
    if (sizes.at({bed.particle_kind, bed.sub_spheres_per_body}).size() < 2) return std::nullopt;
    return static_cast<double>(bed.bodies);
  };
  return figure_charts(runs, "Bed size", "bodies in the bed", "bodies", varied);
}

namespace {

// An extra plate curve: deformation and force_N (or top_force_N, as force.csv has it).
Series plate_curve_series(const std::string& label, const std::filesystem::path& path) {
  const CsvTable table = read_csv(path);
  const std::vector<std::string>& names = table.columns;
  const bool force_n = std::find(names.begin(), names.end(), "force_N") != names.end();
  Series series{label, table.column("deformation"),
                table.column(force_n ? "force_N" : "top_force_N"), SeriesStyle::lines};
  if (series.x.empty())
    throw InputError(fmt::format("{}: the plate curve has no rows", path.string()));
  return series;
}

Chart plate_chart(const std::vector<LoadedRun>& runs, std::optional<double> poisson_ratio,
                  const std::vector<std::pair<std::string, std::filesystem::path>>& curves) {
  Chart chart{"Sphere between plates: force vs deformation",
              "deformation Delta/(2R)",
              "plate force [N]",
              "deformation",
              "force_N",
              {}};
  // Runs of one sphere (a study of sub-sphere counts) share their theory curves: draw Hertz and
  // Tatara once per distinct sphere, over the longest of its runs.
  std::vector<std::pair<double, double>> drawn;  // (R, E*) already drawn
  std::vector<const LoadedRun*> order;
  for (const LoadedRun& run : runs)
    if (run.plate) order.push_back(&run);
  std::stable_sort(order.begin(), order.end(), [](const LoadedRun* a, const LoadedRun* b) {
    return a->plate->deformation.back() > b->plate->deformation.back();
  });
  for (const LoadedRun& run : runs)
    if (run.plate)
      chart.series.push_back(
          {run.label + " simulated", run.plate->deformation, run.plate->top_force});
  for (const LoadedRun* run_ptr : order) {
    const LoadedRun& run = *run_ptr;
    const PlateCurve& c = *run.plate;
    const PlateMetrics& m = *run.plate_metrics;
    const bool seen = std::any_of(drawn.begin(), drawn.end(), [&](const auto& d) {
      return std::fabs(d.first - m.radius) <= 1e-6 * m.radius &&
             std::fabs(d.second - m.effective_modulus) <= 1e-6 * m.effective_modulus;
    });
    if (seen) continue;
    drawn.emplace_back(m.radius, m.effective_modulus);
    const Curve hertz = monotone_prefix({c.deformation, c.hertz_force, "Hertz"});
    chart.series.push_back({run.label + " Hertz", hertz.x, hertz.y, SeriesStyle::dashed});
    if (!poisson_ratio) continue;
    const ElasticSphere sphere = infer_sphere(c, *poisson_ratio);
    std::vector<double> approaches;
    for (double d : hertz.x)
      approaches.push_back(2 * sphere.radius * d);
    chart.series.push_back({fmt::format("{} Tatara (nu = {})", run.label, *poisson_ratio), hertz.x,
                            tatara_plate_forces(sphere, approaches), SeriesStyle::dashed});
  }
  for (const auto& [label, path] : curves)
    chart.series.push_back(plate_curve_series(label, path));
  return chart;
}

// Loading stress against strain of every compaction run, compared at 10 strains up to the
// largest strain all of them reach; nothing with fewer than two runs.
std::optional<StressSpread> stress_spread(const std::vector<LoadedRun>& runs) {
  std::vector<Curve> family;
  for (const LoadedRun& run : runs) {
    if (!run.punch) continue;
    const PunchCurve& c = *run.punch;
    Curve loading{{}, {}, run.label};
    for (std::size_t i : loading_rows(c)) {
      loading.x.push_back((c.reference_gap - c.gap[i]) / c.reference_gap);
      loading.y.push_back(c.stress[i]);
    }
    loading = monotone_prefix(loading);
    if (loading.x.size() >= 2) family.push_back(std::move(loading));
  }
  if (family.size() < 2) return std::nullopt;
  double common = HUGE_VAL;
  for (const Curve& c : family)
    common = std::min(common, c.x.back());
  StressSpread spread;
  for (int i = 1; i <= 10; ++i)
    spread.strain.push_back(common * i / 10.0);
  spread.spread = spread_at(family, spread.strain);
  return spread;
}

}  // namespace

ReportResult write_report(const ReportOptions& options) {
  options.windows.check();
  const std::vector<LoadedRun> runs = load_runs(options);
  ensure_output_folder(options.out);
  ReportResult result;
  std::vector<std::pair<std::string, std::filesystem::path>> charts;  // (title, svg)
  for (const LoadedRun& run : runs)
    (run.punch ? result.compaction_runs : result.plate_runs) += 1;
  if (!options.experiments.empty() && result.compaction_runs == 0)
    throw InputError("--experiment: a measured compaction curve needs a compaction run to compare");
  const std::vector<ExperimentComparison> experiments = compare_experiments(runs, options);
  if (result.compaction_runs > 0) {
    const std::vector<Chart> cs = compaction_charts(runs, experiments);
    const char* stems[] = {"stress_strain", "solid_fraction_stress", "heckel", "kawakita"};
    for (std::size_t i = 0; i < cs.size(); ++i)
      charts.emplace_back(cs[i].title, plot_chart(cs[i], options.out / stems[i]).svg);
    write_file_atomically(options.out / "beds.csv", beds_csv(runs));
    const std::vector<Chart> shapes = shape_effect_charts(runs);
    const char* shape_stems[] = {"shape_effect_peak_stress", "shape_effect_elastic_recovery",
                                 "shape_effect_yield_pressure"};
    for (std::size_t i = 0; i < shapes.size(); ++i)
      if (!shapes[i].series.empty())
        charts.emplace_back(shapes[i].title,
                            plot_chart(shapes[i], options.out / shape_stems[i]).svg);
    const std::vector<Chart> sizes = bed_size_charts(runs);
    const char* size_stems[] = {"bed_size_peak_stress", "bed_size_elastic_recovery",
                                "bed_size_yield_pressure"};
    for (std::size_t i = 0; i < sizes.size(); ++i)
      if (!sizes[i].series.empty())
        charts.emplace_back(sizes[i].title, plot_chart(sizes[i], options.out / size_stems[i]).svg);
  }
  if (result.plate_runs > 0 || !options.plate_curves.empty()) {
    const Chart chart = plate_chart(runs, options.poisson_ratio, options.plate_curves);
    charts.emplace_back(chart.title, plot_chart(chart, options.out / "plate_force").svg);
  }
  std::vector<AdviceRecord> advice;
  for (const std::filesystem::path& folder : options.advice) {
    advice.push_back(read_advice(folder));
    const AdviceRecord& record = advice.back();
    // One advise folder's charts by their plain names; several, each with its folder's name.
    const std::string suffix =
        options.advice.size() > 1
            ? fmt::format("_{}", std::filesystem::weakly_canonical(folder).filename().string())
            : std::string();
    const Chart speed = speed_accuracy_chart(record.advice);
    const Chart map = stability_map_chart(record.advice);
    const char* speed_stem = record.compaction ? "bed_speed_accuracy" : "advise_speed_accuracy";
    charts.emplace_back(
        speed.title, plot_chart(speed, options.out / fmt::format("{}{}", speed_stem, suffix)).svg);
    charts.emplace_back(map.title,
                        plot_chart(map, options.out / fmt::format("stability_map{}", suffix)).svg);
  }
  if (const std::optional<PlateStudy> study = plate_study(runs, options.poisson_ratio)) {
    // Several plate runs with sub-sphere counts: cost against N and speed against accuracy.
    const std::vector<Chart> cs = plate_study_charts(*study);
    charts.emplace_back(cs[0].title, plot_chart(cs[0], options.out / "plate_cost").svg);
    charts.emplace_back(cs[1].title, plot_chart(cs[1], options.out / "plate_speed_accuracy").svg);
    charts.emplace_back(cs[2].title, plot_chart(cs[2], options.out / "plate_convergence").svg);
    write_plate_study_csv(options.out / "plate_study.csv", *study);
    write_fem_study_csv(options.out / "fem_study.csv", *study);
    write_plate_steps_csv(options.out / "plate_steps.csv", *study);
  }
  if (const std::optional<ConvergenceStudy> study = convergence_study(runs, options.spread_from)) {
    // Two or more rigid multi-sphere runs: does the force settle as N grows (paper §3.3)?
    const std::vector<Chart> cs = convergence_charts(*study, runs, options.poisson_ratio);
    const char* stems[] = {"cms_force", "cms_contacts", "convergence_change", "convergence_spread"};
    for (std::size_t i = 0; i < cs.size(); ++i)
      if (!cs[i].series.empty())
        charts.emplace_back(cs[i].title, plot_chart(cs[i], options.out / stems[i]).svg);
    write_convergence_csv(options.out, *study);
  }
  for (const auto& chart : charts)
    result.charts.push_back(chart.second);
  const ReportProvenance provenance{options.command_line, shapepress_version(),
                                    shapepress_git_revision()};
  result.metrics = options.out / "metrics.json";
  const std::optional<StressSpread> spread = stress_spread(runs);
  write_file_atomically(
      result.metrics, metrics_json(runs, options.windows, provenance, spread, experiments, advice));
  result.html = options.out / "report.html";
  write_file_atomically(result.html,
                        report_html(runs, charts, provenance, spread, experiments, advice));
  return result;
}

}  // namespace shapepress::analysis
