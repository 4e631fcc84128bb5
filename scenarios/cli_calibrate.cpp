#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/command_options.hpp"
#include "common/config.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "common/run_metadata.hpp"
#include "common/units.hpp"
#include "scenarios/bms_particle.hpp"
#include "scenarios/calibrate.hpp"
#include "scenarios/calibrate_compaction.hpp"
#include "scenarios/cli.hpp"
#include "scenarios/run_facts.hpp"

namespace shapepress::scenarios {
namespace {

struct CalibrateCli {
  std::string config;
  std::string reference;
  std::string x_column;  // plate: deformation; compaction: from the reference's column names
  std::string y_column;  // plate: F_tatara_N
  std::string fit;       // plate: modulus,shear_ratio; compaction: loading_stiffness
  std::string start;     // "name=value,..."
  int count = 0;
  int fills = 0;
  std::string from;  // plate: 0.05; compaction: the whole reference
  std::string to;    // plate: 0.40
  int max_evaluations = 40;
  std::string method = "bobyqa";
  double initial_factor = 0.0;  // plate: 4; compaction: 2
  std::string packing;
  double density_scale = 0.0;    // 0: the config's
  double target_recovery = 0.0;  // percent; 0: none
  std::string out;
  std::string resume;
};

// How a calibration was started, in OUT/calibrate.json: `--resume OUT` runs it again with the
// same arguments from the same folder, refusing a config or reference that changed since.
constexpr const char* invocation_name = "calibrate.json";

// The file a --reference names: the CSV itself, or a fem-plate run folder's force.csv.
std::filesystem::path reference_file(const std::string& reference) {
  return std::filesystem::is_directory(reference) ? std::filesystem::path(reference) / "force.csv"
                                                  : std::filesystem::path(reference);
}

// calibrate's options, bound once: parsed, recorded for --resume (with the SHA-256 of the
// reference and the bed: the evaluations a resume reuses were run against them), written into
// run.json and documented (docs/stages.md).
CommandOptions calibrate_command(CalibrateCli& cli) {
  CommandOptions options("calibrate");
  options
      .text("--config", &cli.config,
            "plate config with [bms] and [bond], or compact config (with [punch]); the start "
            "values")
      .config()
      .text("--reference", &cli.reference,
            "reference curve CSV: plate force (e.g. the Tatara curve); compaction stress-strain "
            "or solid fraction-stress, the unit in each column name (strain_%, stress_MPa); or a "
            "fem-plate run folder (its force.csv: deformation, top_force_N; a 3D run: the mean "
            "of both plates)")
      .hashed(reference_file)
      .text("--x-column", &cli.x_column,
            "x column of the reference (plate: deformation; compaction: found by name)")
      .text("--y-column", &cli.y_column,
            "y column of the reference (plate: F_tatara_N [N]; compaction: found by name)")
      .text("--fit", &cli.fit,
            "parameters, comma-separated. Plate (default modulus,shear_ratio): modulus, "
            "shear_ratio, normal_stiffness, shear_stiffness, contact_modulus, radius_multiplier, "
            "and of elastic_plastic bonds yield_stress, shear_yield_stress, hardening_ratio "
            "(against a reference that unloads: a fem-plate run with plate.unload). "
            "Compaction (default loading_stiffness): loading_stiffness, loading_modulus, "
            "youngs_modulus, plasticity_ratio, multicontact_prefactor, and the bodies' bonds: "
            "normal_stiffness, shear_stiffness or modulus, and of elastic_plastic bonds "
            "yield_stress, shear_yield_stress, hardening_ratio")
      .text("--start", &cli.start,
            "start values replacing the config's, in SI units: name=value,... (e.g. "
            "modulus=3e6,contact_modulus=1.85e9)")
      .whole("--count", &cli.count, "plate: sub-spheres (overrides bms.count)")
      .range(Range::closed(1, 1000000))
      .whole("--fills", &cli.fills,
             "plate: fit the mean curve of this many fills (seeds seed, seed + 1, …; overrides "
             "bms.fills)")
      .range(Range::closed(1, 1000))
      .text("--from", &cli.from,
            "objective window, lowest x: plate deformation (0.05); compaction strain or stress "
            "with unit, e.g. 0.3 or 5MPa (default: all)")
      .text("--to", &cli.to, "objective window, highest x (plate: 0.40)")
      .whole("--max-evaluations", &cli.max_evaluations, "runs at most")
      .show_default()
      .text("--method", &cli.method,
            "the search: bobyqa (NLopt's BOBYQA, a quadratic model: fewer runs for one or two "
            "parameters) or nelder-mead (went further with three; runs its first simplex and "
            "shrinks side by side); docs/stages.md, \"Search method\"")
      .choices({"bobyqa", "nelder-mead"})
      .show_default()
      .number("--initial-factor", &cli.initial_factor,
              "first step: each parameter times this factor (Nelder-Mead's simplex edge, "
              "BOBYQA's trust region; plate 4, compaction 2; smaller when the start is already "
              "close)")
      .range(Range::closed(1.01, 100.0))
      .text("--packing", &cli.packing,
            "compaction: the bed every evaluation presses (pack's packed.h5, or spheres); "
            "default the config's [generate] bed, settled once")
      .hashed()
      .number("--density-scale", &cli.density_scale,
              "compaction: mass scaling of the evaluations only (a cheaper scene); "
              "calibrated.toml keeps the config's run.density_scale")
      .range(Range::positive())
      .number("--target-recovery", &cli.target_recovery,
              "compaction: the elastic recovery (percent) the bed must also reach after "
              "unloading, beside the reference curve: the objective becomes "
              "sqrt((e_curve^2 + e_recovery^2)/2), e_recovery relative to the target")
      .range(Range{0.0, 100.0, false, false})
      .text("--out", &cli.out,
            "output folder (calibrated.toml, calibration.csv, evaluations.csv, force.csv or "
            "punch.csv, run.json)")
      .output();
  return options;
}

// The table reads the fields it is bound to: a copy binds a running calibration's.
nlohmann::ordered_json options_json(CalibrateCli cli) {
  return calibrate_command(cli).json();
}

// The evaluations of an interrupted calibration (its evaluations.csv), for the search to reuse.
std::vector<CalibrationEvaluation> known_evaluations(const std::filesystem::path& out,
                                                     const std::vector<std::string>& parameters) {
  std::vector<CalibrationEvaluation> known;
  const std::filesystem::path path = out / "evaluations.csv";
  if (!std::filesystem::exists(path)) return known;
  const CsvTable table = read_csv(path);
  std::vector<std::vector<double>> columns;
  for (const std::string& name : parameters)
    columns.push_back(table.column(name));
  const std::vector<double> rms = table.column("rms_relative"), wall = table.column("wall_s");
  for (std::size_t r = 0; r < rms.size(); ++r) {
    CalibrationEvaluation e;
    for (const std::vector<double>& c : columns)
      e.values.push_back(c[r]);
    e.rms_relative = rms[r];
    e.wall_seconds = wall[r];
    known.push_back(std::move(e));
  }
  return known;
}

// evaluations.csv, rewritten whole after every evaluation (atomically: a killed calibration
// leaves every finished evaluation for --resume), values with 17 digits so they read back to
// the same doubles.
class EvaluationLog {
 public:
  EvaluationLog(std::filesystem::path path, std::vector<std::string> parameters,
                std::string comment)
      : path_(std::move(path)), parameters_(std::move(parameters)), comment_(std::move(comment)) {}
  void add(const CalibrationEvaluation& e) {
    std::vector<std::string> row = {std::to_string(rows_.size() + 1)};
    for (double v : e.values)
      row.push_back(fmt::format("{:.17g}", v));
    row.push_back(fmt::format("{:.17g}", e.rms_relative));
    row.push_back(fmt::format("{:.4g}", e.wall_seconds));
    rows_.push_back(std::move(row));
    std::vector<std::string> columns = {"evaluation"};
    columns.insert(columns.end(), parameters_.begin(), parameters_.end());
    columns.insert(columns.end(), {"rms_relative", "wall_s"});
    CsvWriter csv(path_, columns);
    csv.comment(comment_);
    for (const std::vector<std::string>& r : rows_)
      csv.row_text(r);
    csv.commit();
  }
  std::size_t size() const { return rows_.size(); }

 private:
  std::filesystem::path path_;
  std::vector<std::string> parameters_;
  std::string comment_;
  std::vector<std::vector<std::string>> rows_;
};

// Table 1 of Giannis et al. 2023 (the rubber sphere), for the side-by-side report, and Table 4's
// (Avicel PH 200) beside it on the console.
constexpr double paper_normal_stiffness = 1.15e6;      // N/m^3
constexpr double paper_shear_stiffness = 1.25e6;       // N/m^3
constexpr double paper_avicel_normal_stiffness = 8e8;  // N/m^3
constexpr double paper_avicel_shear_stiffness = 9e8;   // N/m^3

std::vector<std::string> split_names(const std::string& text) {
  std::vector<std::string> names;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) names.push_back(item);
  return names;
}

// What the command line brought beside the stage's options.
struct Invocation {
  std::string command_line;
  bool resumed = false;
  bool quiet = false;
};

void write_invocation(const std::filesystem::path& out, CalibrateCli cli,
                      const Invocation& invocation) {
  if (invocation.resumed) return;  // it is the first start's
  shapepress::write_invocation(out / invocation_name,
                               calibrate_command(cli).invocation(invocation.command_line));
}

std::vector<std::pair<std::string, double>> start_values(const std::string& text) {
  std::vector<std::pair<std::string, double>> start;
  for (const std::string& item : split_names(text)) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw InputError("--start '" + item + "': expected name=value (e.g. modulus=5e6)");
    try {
      start.emplace_back(item.substr(0, eq), std::stod(item.substr(eq + 1)));
    } catch (const std::exception&) {
      throw InputError("--start '" + item + "': the value is not a number");
    }
  }
  return start;
}

// A window bound: a number in the x axis' SI unit or a quantity ("20 MPa", "30 %").
double window_bound(const std::string& text, Dimension dimension, std::string_view option) {
  return parse_quantity(text, dimension, option);
}

void report_evaluation(std::size_t index, const CalibrationEvaluation& e,
                       ProgressReporter& progress) {
  spdlog::info(
      "calibrate: evaluation {}: {} -> RMS {:.4f} ({})", index, fmt::join(e.values, ", "),
      e.rms_relative,
      e.reused ? std::string("reused, not run again") : fmt::format("{:.2f} s", e.wall_seconds));
  progress.update(static_cast<double>(index));
}

// Each fitted parameter's value beside its start, on the console.
void print_fitted_values(const std::vector<std::string>& names, const std::vector<double>& start,
                         const std::vector<double>& fitted) {
  for (std::size_t k = 0; k < names.size(); ++k)
    fmt::print("  {} = {:.6g} (start {:.6g})\n", names[k], fitted[k], start[k]);
}

// run.json's "fitted" and "start": each parameter's value, by name.
RunMetadata& add_fitted_values(RunMetadata& meta, const std::vector<std::string>& names,
                               const std::vector<double>& start,
                               const std::vector<double>& fitted) {
  nlohmann::json fitted_json = nlohmann::json::object(), start_json = nlohmann::json::object();
  for (std::size_t k = 0; k < names.size(); ++k) {
    fitted_json[names[k]] = fitted[k];
    start_json[names[k]] = start[k];
  }
  return meta.fact("fitted", fitted_json).fact("start", start_json);
}

// The x axis of a measured curve: strain (dimensionless) or solid fraction against stress (Pa).
Dimension x_dimension_of(const analysis::MeasuredCurve& reference) {
  return reference.axes == analysis::MeasuredAxes::stress_strain ? dim::dimensionless
                                                                 : dim::pressure;
}

// The search's options from the command line: reference, parameters and their start values,
// the objective window, the method and its first step, the evaluations' mass scaling. The
// reference and the bed go into run.json's inputs as they are named.
CompactionCalibrationOptions compaction_calibration_options(const CalibrateCli& cli,
                                                            RunMetadata& meta) {
  CompactionCalibrationOptions options;
  options.reference = analysis::read_measured_curve(cli.reference, cli.x_column, cli.y_column);
  meta.input("reference", cli.reference);
  if (!cli.packing.empty()) meta.input("packing", cli.packing);
  options.parameters = split_names(cli.fit.empty() ? "loading_stiffness" : cli.fit);
  options.start = start_values(cli.start);
  const Dimension x_dimension = x_dimension_of(options.reference);
  options.from = cli.from.empty() ? -HUGE_VAL : window_bound(cli.from, x_dimension, "--from");
  options.to = cli.to.empty() ? HUGE_VAL : window_bound(cli.to, x_dimension, "--to");
  options.max_evaluations = cli.max_evaluations;
  options.method = analysis::search_method_named(cli.method);
  options.initial_factor = cli.initial_factor > 0.0 ? cli.initial_factor : 2.0;
  if (cli.density_scale > 0.0) options.density_scale = cli.density_scale;
  if (cli.target_recovery > 0.0) options.target_recovery = cli.target_recovery / 100.0;
  return options;
}

// The units the report prints beside x and y: stress in Pa, strain and solid fraction none.
struct CurveUnits {
  std::string x, y;
};

CurveUnits curve_units(const analysis::MeasuredCurve& reference) {
  return {x_dimension_of(reference) == dim::pressure ? " Pa" : "",
          reference.axes == analysis::MeasuredAxes::stress_strain ? " Pa" : ""};
}

// evaluations.csv's comment: what each row's RMS compares.
std::string evaluation_log_comment(const CalibrateCli& cli,
                                   const CompactionCalibrationOptions& options) {
  return fmt::format(
      "shapepress calibrate: RMS relative {} error against {} ({}, {}) "
      "over x in [{:g}, {:g}]{}{}{}",
      analysis::axes_name(options.reference.axes), cli.reference, options.reference.x_column,
      options.reference.y_column, options.from, options.to, curve_units(options.reference).x,
      options.density_scale
          ? fmt::format("; evaluations with density_scale {}", *options.density_scale)
          : std::string(),
      options.target_recovery
          ? fmt::format("; with the elastic recovery against {:g} %: sqrt((e_curve^2 + "
                        "e_recovery^2)/2)",
                        100.0 * *options.target_recovery)
          : std::string());
}

// calibrated.toml's header: the command, the fitted values and the best run's mismatch.
std::string calibrated_toml_header(const CalibrateCli& cli,
                                   const CompactionCalibrationOptions& options,
                                   const CompactionCalibrationResult& result) {
  const analysis::MeasuredMismatch& error = result.error;
  const CurveUnits units = curve_units(options.reference);
  std::vector<std::string> fitted;
  for (std::size_t k = 0; k < options.parameters.size(); ++k)
    fitted.push_back(fmt::format("{} = {:.6g}", options.parameters[k], result.values[k]));
  return fmt::format(
      "# shapepress calibrate --config {} --reference {} --fit {}{}\n"
      "# fitted: {}\n"
      "# {} against the reference at {} points, x in [{:g}, {:g}]{}: RMS {:.6g}{} ({:.4g} %), "
      "largest {:.6g}{} at x = {:g}\n{}",
      cli.config, cli.reference, fmt::join(options.parameters, ","),
      cli.density_scale > 0.0 ? fmt::format(" --density-scale {}", cli.density_scale) : "",
      fmt::format("{}", fmt::join(fitted, ", ")), analysis::axes_name(options.reference.axes),
      error.points, error.from, error.to, units.x, error.rms, units.y, 100.0 * error.rms_relative,
      error.max, units.y, error.at_max,
      options.target_recovery
          ? fmt::format("# elastic recovery {:.4g} % against the target {:g} %\n",
                        100.0 * result.recovery, 100.0 * *options.target_recovery)
          : std::string());
}

// punch.csv of the run with the fitted values, on the evaluations' scene.
void write_best_punch(const std::filesystem::path& out, const CompactionCalibrationOptions& options,
                      const CompactionCalibrationResult& result) {
  CsvWriter punch(out / "punch.csv", punch_csv_columns());
  const PreparedCompaction& best = result.best.prepared;
  punch.comment(fmt::format(
      "shapepress calibrate: the run with the fitted values; strain from H0 = {:.10g} m; die "
      "area {:.10g} m^2",
      best.punch.reference_gap, best.setup.die_area));
  if (options.density_scale)
    punch.comment(fmt::format("mass scaling: particle density x {} (calibrate --density-scale)",
                              *options.density_scale));
  punch.comment("phase: 0 load, 1 hold, 2 unload, 4 release, 3 done");
  for (const PunchRecord& r : result.best.records)
    punch.row(punch_csv_row(r));
  punch.commit();
}

// A fitted k1 is a statement about the material at the bed's size: the loading modulus it
// implies carries it to another size of contact (sub-spheres, walls), and the other way round.
struct ImpliedLoading {
  double diameter = 0.0;  // the bed's mean particle diameter (m)
  double poisson_ratio = 0.0;
  nlohmann::json fitted = nlohmann::json::object();  // by name, at the fitted value
  std::vector<std::vector<std::string>> rows;        // name, at the start, fitted
};

ImpliedLoading implied_loading(const CompactionCalibrationOptions& options,
                               const CompactionCalibrationResult& result) {
  ImpliedLoading implied;
  implied.diameter = result.best.prepared.setup.inertial.diameter;
  const Material* particle = result.config.materials.find(result.config.particle_material);
  implied.poisson_ratio = particle ? particle->poisson_ratio : 0.0;
  for (std::size_t k = 0; k < options.parameters.size() && implied.diameter > 0.0; ++k) {
    const std::string& name = options.parameters[k];
    if (name != "loading_stiffness" && name != "loading_modulus") continue;
    const bool stiffness = name == "loading_stiffness";
    const auto carry = [&](double v) {
      return stiffness ? implied_loading_modulus(v, implied.diameter, implied.poisson_ratio)
                       : implied_loading_stiffness(v, implied.diameter, implied.poisson_ratio);
    };
    const std::string other = stiffness ? "implied_loading_modulus" : "implied_loading_stiffness";
    implied.rows.push_back({other, fmt::format("{:.10g}", carry(result.start[k])),
                            fmt::format("{:.10g}", carry(result.values[k]))});
    implied.fitted[other] = carry(result.values[k]);
  }
  return implied;
}

// calibration.csv: each parameter at the start and fitted, then the loading constants they imply.
void write_calibration_summary(const std::filesystem::path& out, const CalibrateCli& cli,
                               const CompactionCalibrationOptions& options,
                               const CompactionCalibrationResult& result,
                               const ImpliedLoading& implied) {
  const analysis::MeasuredMismatch& error = result.error;
  const CurveUnits units = curve_units(options.reference);
  CsvWriter summary(out / "calibration.csv", {"parameter", "start", "fitted"});
  summary.comment(fmt::format(
      "{} points of {} in [{:g}, {:g}]{}; rms = {:.6g}{}, rms_relative = {:.6g}, max = {:.6g}"
      "{}, max_relative = {:.6g}; converged = {}; evaluations = {}",
      error.points, cli.reference, error.from, error.to, units.x, error.rms, units.y,
      error.rms_relative, error.max, units.y, error.max_relative, result.converged ? 1 : 0,
      result.evaluations.size()));
  if (!implied.fitted.empty())
    summary.comment(fmt::format(
        "implied_*: k1 = 4/3 E*_L sqrt(R*) between two particles of the bed's mean diameter "
        "{:.6g} m (R* = d/4, E*_L = E_L / (2 (1 - nu^2)), nu = {})",
        implied.diameter, implied.poisson_ratio));
  for (std::size_t k = 0; k < options.parameters.size(); ++k)
    summary.row_text({options.parameters[k], fmt::format("{:.10g}", result.start[k]),
                      fmt::format("{:.10g}", result.values[k])});
  for (const std::vector<std::string>& row : implied.rows)
    summary.row_text(row);
  summary.commit();
}

// run.json's facts: the folder is also a compaction run (punch.csv of the best fit), so
// `report` reads it, and the fit's values and mismatch.
void add_calibration_facts(RunMetadata& meta, const CompactionCalibrationOptions& options,
                           const CompactionCalibrationResult& result,
                           const ImpliedLoading& implied) {
  const PreparedCompaction& best = result.best.prepared;
  const analysis::MeasuredMismatch& error = result.error;
  CompactConfig scene = result.config;
  if (options.density_scale) scene.density_scale = *options.density_scale;
  add_compaction_facts(meta, scene, best.setup, best.punch.reference_gap, *best.engine,
                       result.best.summary);
  add_fitted_values(meta, options.parameters, result.start, result.values)
      .fact("reference_axes", analysis::axes_name(options.reference.axes))
      .fact("points_compared", error.points)
      .fact("rms", error.rms)
      .fact("max", error.max)
      .fact("rms_relative", error.rms_relative)
      .fact("max_relative", error.max_relative)
      .fact("window", nlohmann::json::array({error.from, error.to}))
      .fact("converged", result.converged)
      .fact("evaluations", result.evaluations.size())
      .fact("objective", result.objective);
  if (std::isfinite(result.recovery)) meta.fact("elastic_recovery", result.recovery);
  if (options.target_recovery) meta.fact("target_recovery", *options.target_recovery);
  if (!implied.fitted.empty())
    meta.fact("implied", implied.fitted).fact("implied_at_diameter_m", implied.diameter);
}

void print_compaction_calibration(const CalibrateCli& cli,
                                  const CompactionCalibrationOptions& options,
                                  const CompactionCalibrationResult& result) {
  const analysis::MeasuredMismatch& error = result.error;
  const std::string& y_unit = curve_units(options.reference).y;
  fmt::print(
      "calibrated on {} points of {}: RMS {:.6g}{} ({:.3g} %), largest {:.6g}{} after {} runs\n",
      error.points, cli.reference, error.rms, y_unit, 100.0 * error.rms_relative, error.max, y_unit,
      result.evaluations.size());
  if (options.target_recovery)
    fmt::print("elastic recovery {:.4g} % against {:g} % (objective {:.3g})\n",
               100.0 * result.recovery, 100.0 * *options.target_recovery, result.objective);
  print_fitted_values(options.parameters, result.start, result.values);
}

int run_compaction_calibration(const CalibrateCli& cli, const ConfigTable& root,
                               const Invocation& invocation) {
  RunMetadata meta("calibrate", invocation.command_line);
  meta.options(options_json(cli));
  meta.input("config", cli.config);
  CompactConfig config = read_compact_config(root);
  root.check_unknown_keys();
  if (cli.count > 0 || cli.fills > 0)
    throw InputError("calibrate: --count and --fills are for a plate config's [bms] particle");
  CompactionCalibrationOptions options = compaction_calibration_options(cli, meta);
  const std::filesystem::path out(cli.out);
  ensure_output_folder(out);
  if (invocation.resumed) options.known = known_evaluations(out, options.parameters);
  EvaluationLog log(out / "evaluations.csv", options.parameters,
                    evaluation_log_comment(cli, options));
  write_invocation(out, cli, invocation);
  ProgressReporter progress("calibrate", options.max_evaluations,
                            {.quiet = invocation.quiet, .unit = "runs"});
  const int threads = omp_get_max_threads();
  const CompactionCalibrationResult result = calibrate_compaction(
      config, cli.packing, options, threads, [&](const CalibrationEvaluation& e) {
        log.add(e);
        report_evaluation(log.size(), e, progress);
      });
  progress.finish();
  write_file_atomically(out / "calibrated.toml", calibrated_toml_header(cli, options, result) +
                                                     compact_config_toml(result.config));
  write_best_punch(out, options, result);
  const ImpliedLoading implied = implied_loading(options, result);
  write_calibration_summary(out, cli, options, result, implied);
  add_calibration_facts(meta, options, result, implied);
  for (const char* name :
       {"evaluations.csv", "calibrated.toml", "punch.csv", "calibration.csv", invocation_name})
    meta.output(name);
  meta.write(out / run_metadata_name);
  print_compaction_calibration(cli, options, result);
  return 0;
}

// The plate reference curve: a CSV with the named columns, or the folder of a finished fem-plate
// run, whose force.csv (deformation, top_force_N) is the particle's own FEM curve (issue 26). The
// FEM run must have reached its last increment and pressed a sphere of the config's radius: a BMS
// template is only calibrated against the particle it fills. A 3D run's curve is the mean of its
// two plates' forces: its anchors hold a particle that is not symmetric about its centre plane at
// its centroid and take the difference (models.md), which the free BMS body, balanced between
// its plates, does not have.
struct ReferenceCurve {
  std::filesystem::path csv;
  std::vector<double> deformation, force;
  std::string force_column;
  // A reference with a `step` column (fem-plate's [plate] unload): its step-2 rows, the
  // unloading from the largest deformation down (the loading above is step 1's).
  std::vector<double> unloading_deformation, unloading_force;
};

// Moves the step-2 rows of `curve` into its unloading branch. The unloading turns at the
// reference's largest deformation, which the config's plates must reach too: the two unloadings
// start from the same state.
void split_unloading(ReferenceCurve& curve, const std::vector<double>& step,
                     const PlateConfig& config) {
  ReferenceCurve loading = curve;
  loading.deformation.clear();
  loading.force.clear();
  for (std::size_t k = 0; k < step.size(); ++k) {
    const bool unloading = step[k] == 2.0;
    (unloading ? loading.unloading_deformation : loading.deformation)
        .push_back(curve.deformation[k]);
    (unloading ? loading.unloading_force : loading.force).push_back(curve.force[k]);
  }
  curve = std::move(loading);
  if (curve.unloading_deformation.empty() || curve.deformation.empty()) return;
  const double turn = curve.deformation.back();
  if (std::fabs(turn - config.setup.max_deformation) > 1e-6 * turn)
    throw InputError(fmt::format(
        "--reference {}: it unloads from deformation {:.6g}; set the config's "
        "plate.max_deformation to it (now {:.6g}) so that both unload from the same state",
        curve.csv.string(), turn, config.setup.max_deformation));
}

ReferenceCurve read_plate_reference(const CalibrateCli& cli, PlateConfig& config) {
  const double radius = config.setup.radius;
  ReferenceCurve curve;
  curve.csv = reference_file(cli.reference);
  curve.force_column = cli.y_column.empty() ? std::string("F_tatara_N") : cli.y_column;
  std::string x_column = cli.x_column.empty() ? std::string("deformation") : cli.x_column;
  bool mean_of_plates = false;
  if (std::filesystem::is_directory(cli.reference)) {
    const RunRecord record =
        RunRecord::read(std::filesystem::path(cli.reference) / run_metadata_name);
    if (record.stage() != "fem-plate")
      throw InputError(
          fmt::format("--reference {}: a folder must hold a fem-plate run, its "
                      "run.json says stage \"{}\"",
                      cli.reference, record.stage()));
    const nlohmann::json& completed = record.json()["facts"]["completed"];
    if (!completed.is_boolean() || !completed.get<bool>())
      throw InputError(
          fmt::format("--reference {}: the FEM run did not reach its last "
                      "increment (run.json: completed = false)",
                      cli.reference));
    if (record.has("model") && record.json()["facts"]["model"] == "solid") {
      // A 3D FEM run of a mesh: the BMS template of that mesh is pressed along the FEM's axis,
      // given in the mesh's frame (the template's file turns it into the template's body frame).
      if (!config.bms || config.bms->templates.empty())
        throw InputError(fmt::format(
            "--reference {}: a 3D FEM run of the mesh {}: the config's [bms] must name the "
            "templates (bms.templates) filled from that mesh",
            cli.reference, record.json()["facts"]["mesh"].get<std::string>()));
      const nlohmann::json& axis = record.json()["facts"]["axis_direction"];
      config.bms->axis = geometry::PressAxis::direction;
      config.bms->direction = {axis.at(0).get<double>(), axis.at(1).get<double>(),
                               axis.at(2).get<double>()};
      config.setup.radius = bms_template_half_height(*config.bms);
      spdlog::info(
          "calibrate: the template pressed along the FEM run's {} axis ({:.4f}, {:.4f}, {:.4f} "
          "in the mesh's frame): its height {:.6g} m, the mesh's {:.6g} m",
          record.json()["facts"]["axis"].get<std::string>(), config.bms->direction[0],
          config.bms->direction[1], config.bms->direction[2], 2.0 * config.setup.radius,
          record.number("height_m"));
      mean_of_plates = true;
    } else {
      const double fem_radius = record.number("radius_m");
      // A spheroid's FEM run (polar_radius_m ≠ radius_m) is not the sphere calibrate fills.
      const double fem_polar =
          record.has("polar_radius_m") ? record.number("polar_radius_m") : fem_radius;
      if (std::fabs(fem_radius - radius) > 1e-9 * radius ||
          std::fabs(fem_polar - radius) > 1e-9 * radius)
        throw InputError(
            fmt::format("--reference {}: the FEM particle's radius {} m and polar radius {} m are "
                        "not the config's sphere radius {} m",
                        cli.reference, fem_radius, fem_polar, radius));
    }
    x_column = "deformation";
    curve.force_column = "top_force_N";
  }
  const CsvTable table = read_csv(curve.csv);
  curve.deformation = table.finite_column(x_column);
  curve.force = table.finite_column(curve.force_column);
  if (mean_of_plates) {
    const std::vector<double> bottom = table.finite_column("bottom_force_N");
    for (std::size_t k = 0; k < curve.force.size(); ++k)
      curve.force[k] = 0.5 * (curve.force[k] + bottom.at(k));
    curve.force_column = "mean of top_force_N and bottom_force_N";
  }
  if (std::find(table.columns.begin(), table.columns.end(), "step") != table.columns.end())
    split_unloading(curve, table.finite_column("step"), config);
  return curve;
}

// The plate search's options: the parameters (modulus and shear_ratio unless --fit), the
// reference curve, the deformation window (0.05 to 0.40 unless given), the method and its first
// step (each parameter times 4 unless given).
CalibrationOptions plate_calibration_options(const CalibrateCli& cli,
                                             const ReferenceCurve& reference) {
  CalibrationOptions options;
  options.parameters = split_names(cli.fit.empty() ? "modulus,shear_ratio" : cli.fit);
  options.reference_deformation = reference.deformation;
  options.reference_force = reference.force;
  options.reference_unloading_deformation = reference.unloading_deformation;
  options.reference_unloading_force = reference.unloading_force;
  options.start = start_values(cli.start);
  options.from = cli.from.empty() ? 0.05 : window_bound(cli.from, dim::dimensionless, "--from");
  options.to = cli.to.empty() ? 0.40 : window_bound(cli.to, dim::dimensionless, "--to");
  options.max_evaluations = cli.max_evaluations;
  options.method = analysis::search_method_named(cli.method);
  options.initial_factor = cli.initial_factor > 0.0 ? cli.initial_factor : 4.0;
  return options;
}

// The fitted bonds' stiffnesses per unit area at the best fill's sub-sphere size (Eq. 10: a
// modulus over the bond length 2r), to set beside the paper's k̄n and k̄s.
struct BondStiffness {
  double normal = 0.0, shear = 0.0;  // N/m^3
};

BondStiffness fitted_bond_stiffness(const CalibrationResult& result) {
  const BondParameters& b = result.config.bms->bond;
  const double two_r = 2.0 * result.best.sub_sphere_radius;
  const double kn = b.modulus > 0.0 ? b.modulus / two_r : b.normal_stiffness;
  const double ks = b.modulus > 0.0 ? kn * b.shear_ratio : b.shear_stiffness;
  return {kn, ks};
}

// calibration.csv: the fitted values beside the start and the paper's (per unit area k̄n, k̄s at
// this fill).
void write_plate_calibration_summary(const std::filesystem::path& out,
                                     const CalibrationOptions& options,
                                     const CalibrationResult& result,
                                     const BondStiffness& stiffness) {
  CsvWriter summary(out / "calibration.csv", {"parameter", "start", "fitted", "paper"});
  summary.comment(fmt::format(
      "N = {}, fills = {}, sub-sphere radius {:.6g} m; rms_relative = {:.6g}, max_relative = "
      "{:.6g} over [{}, {}]; converged = {}; evaluations = {}",
      result.best.spheres, result.best.fills(), result.best.sub_sphere_radius, result.rms_relative,
      result.max_relative, options.from, options.to, result.converged ? 1 : 0,
      result.evaluations.size()));
  for (std::size_t k = 0; k < options.parameters.size(); ++k)
    summary.row_text({options.parameters[k], format_number(result.start[k]),
                      format_number(result.values[k]), ""});
  summary.row_text({"bond_normal_stiffness_N_per_m3", "", format_number(stiffness.normal),
                    format_number(paper_normal_stiffness)});
  summary.row_text({"bond_shear_stiffness_N_per_m3", "", format_number(stiffness.shear),
                    format_number(paper_shear_stiffness)});
  summary.commit();
}

int run_plate(const CalibrateCli& cli, const ConfigTable& root, const Invocation& invocation) {
  RunMetadata meta("calibrate", invocation.command_line);
  meta.options(options_json(cli));
  meta.input("config", cli.config);
  PlateConfig config = read_plate_config(root);
  root.check_unknown_keys();
  if (!config.bms) throw InputError(cli.config + ": calibrate needs a [bms] particle and [bond]");
  if (cli.count > 0) config.bms->count = cli.count;
  if (cli.fills > 0) config.bms->fills = cli.fills;
  const ReferenceCurve reference = read_plate_reference(cli, config);
  meta.input("reference", reference.csv);
  CalibrationOptions options = plate_calibration_options(cli, reference);
  const double from = options.from, to = options.to;
  const std::filesystem::path out(cli.out);
  ensure_output_folder(out);
  if (invocation.resumed) options.known = known_evaluations(out, options.parameters);
  EvaluationLog log(
      out / "evaluations.csv", options.parameters,
      fmt::format("shapepress calibrate: {} sub-spheres, {} (seed {}), RMS relative force "
                  "error over deformation [{}, {}] against {}:{}",
                  config.bms->count,
                  config.bms->fills > 1 ? fmt::format("mean of {} fills", config.bms->fills)
                                        : std::string("one fill"),
                  config.bms->seed, from, to, reference.csv.string(), reference.force_column) +
          (reference.unloading_deformation.empty()
               ? std::string()
               : "; with its unloading (step 2): rms_relative = sqrt((loading^2 + "
                 "unloading^2) / 2), the unloading's RMS force error over the peak force"));
  write_invocation(out, cli, invocation);
  ProgressReporter progress("calibrate", options.max_evaluations,
                            {.quiet = invocation.quiet, .unit = "runs"});
  const CalibrationResult result =
      calibrate_plate(config, options, [&](const CalibrationEvaluation& e) {
        log.add(e);
        report_evaluation(log.size(), e, progress);
      });
  progress.finish();
  write_file_atomically(
      out / "calibrated.toml",
      fmt::format("# shapepress calibrate --config {} --reference {} --fit {} (N = {}):\n"
                  "# RMS relative error {:.5f} over deformation [{}, {}]\n",
                  cli.config, cli.reference, fmt::join(options.parameters, ","),
                  result.best.spheres, result.rms_relative, from, to) +
          plate_config_toml(result.config));
  write_force_csv(out / "force.csv", result.best, result.config, true);
  const BondStiffness stiffness = fitted_bond_stiffness(result);
  write_plate_calibration_summary(out, options, result, stiffness);
  // The folder is also a plate run (force.csv of the best fit): the plate facts, then the fit's.
  add_plate_facts(meta, result.config, PlateParticleKind::bms, result.best);
  add_fitted_values(meta, options.parameters, result.start, result.values)
      .fact("rms_relative", result.rms_relative)
      .fact("max_relative", result.max_relative)
      .fact("window_deformation", nlohmann::json::array({from, to}))
      .fact("converged", result.converged)
      .fact("evaluations", result.evaluations.size())
      .fact("bond_normal_stiffness_N_per_m3", stiffness.normal)
      .fact("bond_shear_stiffness_N_per_m3", stiffness.shear);
  if (!options.reference_unloading_deformation.empty())
    meta.fact("loading_rms_relative", result.loading_rms_relative)
        .fact("unloading_rms_of_peak", result.unloading_rms);
  for (const char* name :
       {"evaluations.csv", "calibrated.toml", "force.csv", "calibration.csv", invocation_name})
    meta.output(name);
  meta.write(out / run_metadata_name);
  fmt::print("calibrated N = {}: RMS {:.4f}, max {:.4f} over [{}, {}] after {} runs\n",
             result.best.spheres, result.rms_relative, result.max_relative, from, to,
             result.evaluations.size());
  print_fitted_values(options.parameters, result.start, result.values);
  if (!options.reference_unloading_deformation.empty()) {
    const PlateUnloading unloaded = plate_unloading(result.best.rows, result.config.setup.records);
    fmt::print(
        "  loading RMS {:.4f}, unloading RMS {:.4f} of the peak force; the fitted run keeps "
        "deformation {:.4g} unloaded\n",
        result.loading_rms_relative, result.unloading_rms, unloaded.residual_deformation);
  }
  fmt::print(
      "  k̄n = {:.4g} N/m^3, k̄s = {:.4g} N/m^3 (paper: Table 1, rubber {:.3g}, {:.3g}; Table 4, "
      "Avicel {:.3g}, {:.3g})\n",
      stiffness.normal, stiffness.shear, paper_normal_stiffness, paper_shear_stiffness,
      paper_avicel_normal_stiffness, paper_avicel_shear_stiffness);
  return 0;
}

int run(const CalibrateCli& given, const RunContext& context) {
  Invocation invocation{context.command_line, !given.resume.empty(), context.quiet};
  CalibrateCli cli = given;
  if (!given.resume.empty())
    invocation.command_line = calibrate_command(cli).resume(
        std::filesystem::absolute(given.resume) / invocation_name, given.resume);
  if (cli.config.empty() || cli.reference.empty() || cli.out.empty())
    throw InputError("calibrate: give --config, --reference and --out (or --resume OUT)");
  const ConfigTable root = ConfigTable::load_file(cli.config);
  // A compaction config has a punch program; a plate config has none.
  if (root.has("punch")) return run_compaction_calibration(cli, root, invocation);
  if (!cli.packing.empty() || cli.density_scale > 0.0 || cli.target_recovery > 0.0)
    throw InputError(
        "calibrate: --packing, --density-scale and --target-recovery are for a compaction config "
        "(one with [punch]); a plate config weighs its unloading by the reference's");
  return run_plate(cli, root, invocation);
}

}  // namespace

StageOptions calibrate_options() {
  StageOptions options = plate_config_options("calibrate");
  options.help =
      "A plate config (these keys), or a compact config: a config with [punch] is calibrated on "
      "a compaction and takes compact's keys.";
  return options;
}

CommandOptions calibrate_command_options() {
  static CalibrateCli defaults;
  return calibrate_command(defaults);
}

StageRunner setup_calibrate_cli(CLI::App& app) {
  auto cli = std::make_shared<CalibrateCli>();
  calibrate_command(*cli).add_to(app, &cli->resume,
                                 "continue the interrupted calibration in this output folder, "
                                 "with the arguments it was started with: evaluations in its "
                                 "evaluations.csv are not run again");
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::scenarios
