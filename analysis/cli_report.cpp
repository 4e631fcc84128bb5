#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <memory>
#include <optional>

#include <fmt/format.h>

#include "analysis/cli.hpp"
#include "analysis/report.hpp"
#include "common/error.hpp"
#include "common/run_metadata.hpp"

namespace shapepress::analysis {
namespace {

struct ReportCli {
  std::vector<std::string> runs;
  std::string out;
  std::optional<double> poisson_ratio;
  std::optional<double> compare_from;
  std::vector<std::string> plate_curves;  // LABEL=FILE.csv
  std::vector<std::string> spread_from;   // METHOD=N
  std::vector<std::string> experiments;
  std::vector<std::string> advice;
  std::vector<double> heckel_window{0.3, 1.0};
  std::vector<double> kawakita_window{0.05, 1.0};
};

int run(const ReportCli& cli, const RunContext& context) {
  ReportOptions options;
  for (const std::string& r : cli.runs)
    options.runs.emplace_back(r);
  options.out = cli.out;
  options.windows = {cli.heckel_window[0], cli.heckel_window[1], cli.kawakita_window[0],
                     cli.kawakita_window[1]};
  if (cli.poisson_ratio && !(*cli.poisson_ratio >= 0.0 && *cli.poisson_ratio < 0.5))
    throw InputError(fmt::format("--poisson-ratio {}: expected 0 <= nu < 0.5", *cli.poisson_ratio));
  options.poisson_ratio = cli.poisson_ratio;
  if (cli.compare_from && !(*cli.compare_from > 0.0 && *cli.compare_from < 1.0))
    throw InputError(
        fmt::format("--compare-from {}: expected 0 < deformation < 1", *cli.compare_from));
  options.plate_compare_from = cli.compare_from;
  for (const std::string& curve : cli.plate_curves) {
    const std::size_t equals = curve.find('=');
    if (equals == std::string::npos || equals == 0 || equals + 1 == curve.size())
      throw InputError(fmt::format("--plate-curve '{}': expected LABEL=FILE.csv", curve));
    options.plate_curves.emplace_back(curve.substr(0, equals), curve.substr(equals + 1));
  }
  for (const std::string& item : cli.spread_from) {
    const std::size_t equals = item.find('=');
    int n = 0;
    try {
      std::size_t used = 0;
      if (equals != std::string::npos) n = std::stoi(item.substr(equals + 1), &used);
      if (equals == std::string::npos || equals == 0 || equals + 1 + used != item.size()) n = 0;
    } catch (const std::exception&) {
      n = 0;
    }
    if (n < 2)
      throw InputError(fmt::format(
          "--spread-from '{}': expected METHOD=N with N >= 2 (e.g. cms=150, bms=819)", item));
    options.spread_from[item.substr(0, equals)] = n;
  }
  for (const std::string& file : cli.experiments)
    options.experiments.emplace_back(file);
  for (const std::string& folder : cli.advice)
    options.advice.emplace_back(folder);
  if (options.runs.empty() && options.advice.empty())
    throw InputError("report: give run folders, --advice folders, or both");
  options.command_line = context.command_line;
  const ReportResult result = write_report(options);
  // The report's own record: which runs (their CSV and run.json, hashed) it was drawn from.
  RunMetadata meta("report", context.command_line);
  for (const std::filesystem::path& folder : options.runs)
    for (const char* name : {"punch.csv", "force.csv", "run.json"})
      if (std::filesystem::exists(folder / name)) meta.input("run", folder / name);
  for (const auto& curve : options.plate_curves)
    meta.input("plate_curve", curve.second);
  for (const auto& file : options.experiments)
    meta.input("experiment", file);
  for (const auto& folder : options.advice)
    meta.input("advice", folder / "advice.csv");
  meta.output(result.html.filename())
      .output(result.metrics.filename())
      .fact("compaction_runs", result.compaction_runs)
      .fact("plate_runs", result.plate_runs)
      .fact("charts", result.charts.size());
  if (options.poisson_ratio) meta.fact("poisson_ratio", *options.poisson_ratio);
  meta.write(std::filesystem::path(options.out) / run_metadata_name);
  if (result.plate_runs > 0 && !options.poisson_ratio)
    spdlog::info(
        "report: no --poisson-ratio, plate runs are compared with Hertz only (Tatara "
        "needs the sphere's Poisson ratio, which force.csv does not carry)");
  spdlog::info("report: {} compaction and {} plate run(s), {} charts, {}", result.compaction_runs,
               result.plate_runs, result.charts.size(), result.html.string());
  return 0;
}

}  // namespace

StageRunner setup_report_cli(CLI::App& app) {
  auto cli = std::make_shared<ReportCli>();
  app.add_option("runs", cli->runs,
                 "run folders: compaction (punch.csv) or plate (force.csv); several are overlaid");
  app.add_option("--out", cli->out, "report folder (report.html, metrics.json, *.svg/png/csv)")
      ->required();
  app.add_option("--poisson-ratio", cli->poisson_ratio,
                 "plate runs: the sphere's Poisson ratio, to draw and compare Tatara's curve");
  app.add_option("--compare-from", cli->compare_from,
                 "plate runs: the deformation Delta/(2R) the RMS against Hertz and Tatara starts "
                 "at, e.g. 0.05 for the paper's 5-40 % (default: 5 % of the deepest)");
  app.add_option("--plate-curve", cli->plate_curves,
                 "LABEL=FILE.csv: one more curve on the plate chart (columns deformation and "
                 "force_N or top_force_N), e.g. a BMS plate run; repeatable");
  app.add_option("--experiment", cli->experiments,
                 "FILE.csv: a measured compaction curve drawn over the runs and compared with "
                 "each (stress-strain: columns strain and stress_<unit>; solid fraction-stress: "
                 "stress_<unit> and solid_fraction; strain_% and solid_fraction_% in percent); "
                 "repeatable")
      ->check(CLI::ExistingFile);
  app.add_option("--advice", cli->advice,
                 "an advise folder (advice.csv, run.json): its speed-accuracy chart "
                 "(bed_speed_accuracy.svg for a bed), stability map and table; repeatable")
      ->check(CLI::ExistingDirectory);
  app.add_option("--spread-from", cli->spread_from,
                 "METHOD=N: the convergence spread of the plate runs with particle METHOD (cms, "
                 "bms) is taken over N and up (default: the method's two finest runs); repeatable");
  app.add_option("--heckel-window", cli->heckel_window,
                 "Heckel fit on loading points with stress in [LO, HI] x peak stress")
      ->expected(2)
      ->capture_default_str();
  app.add_option("--kawakita-window", cli->kawakita_window,
                 "Kawakita fit on loading points with stress in [LO, HI] x peak stress")
      ->expected(2)
      ->capture_default_str();
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::analysis
