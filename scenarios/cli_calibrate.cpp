#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/config.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"
#include "scenarios/calibrate.hpp"
#include "scenarios/cli.hpp"
#include "scenarios/run_facts.hpp"

namespace shapepress::scenarios {
namespace {

struct CalibrateCli {
  std::string config;
  std::string reference;
  std::string x_column = "deformation";
  std::string y_column = "F_tatara_N";
  std::string fit = "modulus,shear_ratio";
  std::string start;  // "name=value,..."
  int count = 0;
  int fills = 0;
  double from = 0.05;
  double to = 0.40;
  int max_evaluations = 40;
  double initial_factor = 4.0;
  std::string out;
};

// Table 1 of Giannis et al. 2023, for the side-by-side report.
constexpr double paper_normal_stiffness = 1.15e6;  // N/m^3
constexpr double paper_shear_stiffness = 1.25e6;   // N/m^3

std::vector<std::string> split_names(const std::string& text) {
  std::vector<std::string> names;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) names.push_back(item);
  return names;
}

int run(const CalibrateCli& cli, const RunContext& context) {
  RunMetadata meta("calibrate", context.command_line);
  const ConfigTable root = ConfigTable::load_file(cli.config);
  meta.input("config", cli.config);
  PlateConfig config = read_plate_config(root);
  root.check_unknown_keys();
  if (!config.bms) throw InputError(cli.config + ": calibrate needs a [bms] particle and [bond]");
  if (cli.count > 0) config.bms->count = cli.count;
  if (cli.fills > 0) config.bms->fills = cli.fills;
  const CsvTable reference = read_csv(cli.reference);
  meta.input("reference", cli.reference);
  CalibrationOptions options;
  options.parameters = split_names(cli.fit);
  options.reference_deformation = reference.finite_column(cli.x_column);
  options.reference_force = reference.finite_column(cli.y_column);
  for (const std::string& item : split_names(cli.start)) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw InputError("--start '" + item + "': expected name=value (e.g. modulus=5e6)");
    try {
      options.start.emplace_back(item.substr(0, eq), std::stod(item.substr(eq + 1)));
    } catch (const std::exception&) {
      throw InputError("--start '" + item + "': the value is not a number");
    }
  }
  options.from = cli.from;
  options.to = cli.to;
  options.max_evaluations = cli.max_evaluations;
  options.initial_factor = cli.initial_factor;
  const std::filesystem::path out(cli.out);
  ensure_output_folder(out);
  std::vector<std::string> columns = {"evaluation"};
  for (const std::string& name : options.parameters)
    columns.push_back(name);
  columns.insert(columns.end(), {"rms_relative", "wall_s"});
  CsvWriter log(out / "evaluations.csv", columns);
  log.comment(
      fmt::format("shapepress calibrate: {} sub-spheres, {} (seed {}), RMS relative force "
                  "error over deformation [{}, {}] against {}:{}",
                  config.bms->count,
                  config.bms->fills > 1 ? fmt::format("mean of {} fills", config.bms->fills)
                                        : std::string("one fill"),
                  config.bms->seed, cli.from, cli.to, cli.reference, cli.y_column));
  int index = 0;
  const CalibrationResult result =
      calibrate_plate(config, options, [&](const CalibrationEvaluation& e) {
        std::vector<double> row = {static_cast<double>(++index)};
        row.insert(row.end(), e.values.begin(), e.values.end());
        row.insert(row.end(), {e.rms_relative, e.wall_seconds});
        log.row(row);
        spdlog::info("calibrate: evaluation {}: {} -> RMS {:.4f} ({:.2f} s)", index,
                     fmt::join(e.values, ", "), e.rms_relative, e.wall_seconds);
      });
  log.commit();
  write_file_atomically(
      out / "calibrated.toml",
      fmt::format("# shapepress calibrate --config {} --reference {} --fit {} (N = {}):\n"
                  "# RMS relative error {:.5f} over deformation [{}, {}]\n",
                  cli.config, cli.reference, cli.fit, config.bms->count, result.rms_relative,
                  cli.from, cli.to) +
          plate_config_toml(result.config));
  write_force_csv(out / "force.csv", result.best, result.config, true);
  // Fitted values beside the start and the paper's (per unit area k̄n, k̄s at this fill).
  CsvWriter summary(out / "calibration.csv", {"parameter", "start", "fitted", "paper"});
  summary.comment(fmt::format(
      "N = {}, fills = {}, sub-sphere radius {:.6g} m; rms_relative = {:.6g}, max_relative = "
      "{:.6g} over [{}, {}]; converged = {}; evaluations = {}",
      result.best.spheres, result.best.fills(), result.best.sub_sphere_radius, result.rms_relative,
      result.max_relative, cli.from, cli.to, result.converged ? 1 : 0, result.evaluations.size()));
  for (std::size_t k = 0; k < options.parameters.size(); ++k)
    summary.row_text({options.parameters[k], format_number(result.start[k]),
                      format_number(result.values[k]), ""});
  const BondParameters& b = result.config.bms->bond;
  const double two_r = 2.0 * result.best.sub_sphere_radius;
  const double kn = b.modulus > 0.0 ? b.modulus / two_r : b.normal_stiffness;
  const double ks = b.modulus > 0.0 ? kn * b.shear_ratio : b.shear_stiffness;
  summary.row_text({"bond_normal_stiffness_N_per_m3", "", format_number(kn),
                    format_number(paper_normal_stiffness)});
  summary.row_text({"bond_shear_stiffness_N_per_m3", "", format_number(ks),
                    format_number(paper_shear_stiffness)});
  summary.commit();
  // The folder is also a plate run (force.csv of the best fit): the plate facts, then the fit's.
  add_plate_facts(meta, result.config, PlateParticleKind::bms, result.best);
  nlohmann::json fitted = nlohmann::json::object(), start = nlohmann::json::object();
  for (std::size_t k = 0; k < options.parameters.size(); ++k) {
    fitted[options.parameters[k]] = result.values[k];
    start[options.parameters[k]] = result.start[k];
  }
  meta.fact("fitted", fitted)
      .fact("start", start)
      .fact("rms_relative", result.rms_relative)
      .fact("max_relative", result.max_relative)
      .fact("window_deformation", nlohmann::json::array({cli.from, cli.to}))
      .fact("converged", result.converged)
      .fact("evaluations", result.evaluations.size())
      .fact("bond_normal_stiffness_N_per_m3", kn)
      .fact("bond_shear_stiffness_N_per_m3", ks);
  for (const char* name : {"evaluations.csv", "calibrated.toml", "force.csv", "calibration.csv"})
    meta.output(name);
  meta.write(out / run_metadata_name);
  fmt::print("calibrated N = {}: RMS {:.4f}, max {:.4f} over [{}, {}] after {} runs\n",
             result.best.spheres, result.rms_relative, result.max_relative, cli.from, cli.to,
             result.evaluations.size());
  for (std::size_t k = 0; k < options.parameters.size(); ++k)
    fmt::print("  {} = {:.6g} (start {:.6g})\n", options.parameters[k], result.values[k],
               result.start[k]);
  fmt::print("  k̄n = {:.4g} N/m^3, k̄s = {:.4g} N/m^3 (paper: {:.3g}, {:.3g})\n", kn, ks,
             paper_normal_stiffness, paper_shear_stiffness);
  return 0;
}

}  // namespace

StageOptions calibrate_options() {
  return plate_config_options("calibrate");
}

StageRunner setup_calibrate_cli(CLI::App& app) {
  auto cli = std::make_shared<CalibrateCli>();
  app.add_option("--config", cli->config, "plate config with [bms] and [bond] (the start values)")
      ->required();
  app.add_option("--reference", cli->reference, "reference curve CSV (e.g. the Tatara curve)")
      ->required();
  app.add_option("--x-column", cli->x_column, "deformation column of the reference")
      ->capture_default_str();
  app.add_option("--y-column", cli->y_column, "force column of the reference [N]")
      ->capture_default_str();
  app.add_option("--fit", cli->fit,
                 "parameters, comma-separated: modulus, shear_ratio, normal_stiffness, "
                 "shear_stiffness, contact_modulus, radius_multiplier")
      ->capture_default_str();
  app.add_option("--start", cli->start,
                 "start values replacing the config's, in SI units: name=value,... "
                 "(e.g. modulus=3e6,contact_modulus=1.85e9)");
  app.add_option("--count", cli->count, "sub-spheres (overrides bms.count)")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--fills", cli->fills,
                 "fit the mean curve of this many fills (seeds seed, seed + 1, …; overrides "
                 "bms.fills)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--from", cli->from, "objective window: lowest deformation")
      ->capture_default_str();
  app.add_option("--to", cli->to, "objective window: highest deformation")->capture_default_str();
  app.add_option("--max-evaluations", cli->max_evaluations, "plate runs at most")
      ->capture_default_str();
  app.add_option("--initial-factor", cli->initial_factor,
                 "first simplex: each parameter times this factor (smaller when the start is "
                 "already close)")
      ->check(CLI::Range(1.01, 100.0))
      ->capture_default_str();
  app.add_option("--out", cli->out,
                 "output folder (calibrated.toml, calibration.csv, evaluations.csv, force.csv)")
      ->required();
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::scenarios
