// shapepress advise: the cheapest resolution and time step that still hold a plate config's
// answer (issue 21, points 2 and 3). Each rung of the ladder (sub-sphere count × time-step
// fraction) is one `shapepress plate` process in its own folder under --out, run side by side
// on the --threads (one thread each), so that a rung that diverges ends with its own exit code
// and named cause, and a killed advise leaves every finished rung reusable: a rung's folder
// counts as done when its rung.json (written last, atomically) names the same config, particle,
// count, fraction and fills. The judgement on the finished ladder is analysis/advise.hpp.
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>

#include <omp.h>

#include "analysis/advise.hpp"
#include "analysis/runs.hpp"
#include "common/atomic_file.hpp"
#include "common/config.hpp"
#include "common/error.hpp"
#include "common/job_pool.hpp"
#include "common/run_metadata.hpp"
#include "common/sha256.hpp"
#include "scenarios/advise_bed_size.hpp"
#include "scenarios/advise_compaction.hpp"
#include "scenarios/advise_runs.hpp"
#include "scenarios/cli.hpp"
#include "scenarios/config_io.hpp"

namespace shapepress::scenarios {
namespace {

namespace fs = std::filesystem;

struct AdviseCli {
  std::string config;
  std::string out;
  std::string particle;  // empty: bms when the config has [bms], else cms
  std::vector<int> counts;
  std::vector<double> fractions;
  double tolerance = 0.05;
  int fills = 0;  // bms: fills per rung; 0: the config's
  bool resume = false;
  CompactionAdviseRequest compaction;  // a compaction config's bed (--templates, --pack-config)
  std::vector<std::string> bed_runs;   // finished compactions of a bed-size ladder
};

struct RungJob {
  std::string label;
  int count = 0;
  double fraction = 0.0;
  fs::path folder;
  nlohmann::json key;  // what makes a finished folder this rung
};

std::string fraction_text(double f) {
  return fmt::format("{:.4g}", f);
}

// The finished rung of `job` from its folder (the run's curve, counted cost and CPU seconds, or
// its end).
analysis::Rung load_rung(const RungJob& job, const nlohmann::json& record) {
  analysis::Rung rung;
  rung.label = job.label;
  rung.sub_spheres = job.count;
  rung.time_step_fraction = job.fraction;
  const int code = record.at("exit_code").get<int>();
  if (code != 0) {
    rung.end = code == 1 ? analysis::RunEnd::diverged : analysis::RunEnd::refused;
    rung.message = record.value("message", "");
    rung.cause = code == 1 ? divergence_cause(rung.message) : "refused";
    return rung;
  }
  const analysis::PlateCurve c = analysis::read_plate_curve(job.folder / "force.csv");
  rung.curve = {{0.0}, {0.0}, job.label};  // both plates touch at zero force
  for (std::size_t i = 0; i < c.deformation.size(); ++i)
    if (c.deformation[i] > rung.curve.x.back()) {
      rung.curve.x.push_back(c.deformation[i]);
      rung.curve.y.push_back(c.top_force[i]);
    }
  rung.cpu_seconds = c.cpu_seconds;
  rung.counted_cost = counted_cost(job.folder, "plate");
  // plate checks divergence at every row; a curve with a non-finite force (a run from before
  // that check) is a diverged run all the same, never a curve to compare.
  if (!std::all_of(c.top_force.begin(), c.top_force.end(),
                   [](double f) { return std::isfinite(f); })) {
    rung.end = analysis::RunEnd::diverged;
    rung.cause = "non-finite";
    rung.message = (job.folder / "force.csv").string() + " holds a non-finite force";
    rung.curve = {};
  }
  return rung;
}

std::vector<RungJob> ladder_jobs(const AdviseCli& cli, const std::string& particle,
                                 const std::string& config_hash, int fills) {
  std::vector<RungJob> jobs;
  for (int count : cli.counts)
    for (double fraction : cli.fractions) {
      RungJob job;
      job.count = count;
      job.fraction = fraction;
      job.label = fmt::format("{}-{}-f{}", particle, count, fraction_text(fraction));
      job.folder = fs::path(cli.out) / job.label;
      job.key = {{"config_sha256", config_hash},
                 {"particle", particle},
                 {"count", count},
                 {"time_step_fraction", fraction},
                 {"fills", fills}};
      jobs.push_back(std::move(job));
    }
  return jobs;
}

// A compaction config's ladder: the bed re-filled and re-packed at each rung
// (advise_compaction.hpp).
int run_compaction_ladder(const AdviseCli& cli, const RunContext& context) {
  if (!cli.particle.empty() || cli.fills > 0)
    throw InputError(
        "advise: --particle and --fills are a plate config's; a compaction bed's "
        "kind is its templates'");
  CompactionAdviseRequest request = cli.compaction;
  request.config = cli.config;
  request.out = cli.out;
  request.counts = cli.counts;
  request.fractions = cli.fractions;
  request.tolerance = cli.tolerance;
  request.resume = cli.resume;
  return run_compaction_advise(request, context);
}

// What every rung of a plate ladder shares: the particle kind and the fills each rung runs
// (config_fills: the config's own, which the full run's predicted cost is scaled to).
struct PlateLadder {
  std::string particle;
  int fills = 1;
  int config_fills = 1;
};

PlateLadder plate_ladder(const AdviseCli& cli, const PlateConfig& config) {
  PlateLadder ladder;
  ladder.particle = !cli.particle.empty() ? cli.particle : config.bms ? "bms" : "cms";
  if (ladder.particle == "bms" && !config.bms)
    throw InputError(cli.config + ": advise --particle bms needs a [bms] table (and [bond])");
  if (ladder.particle != "bms" && cli.fills > 0)
    throw InputError("--fills is the random fills of --particle bms");
  if (config.run.time_step)
    throw InputError(cli.config +
                     ": advise varies run.time_step_fraction, but the config fixes "
                     "run.time_step");
  ladder.config_fills = config.bms ? config.bms->fills : 1;
  ladder.fills = ladder.particle == "bms" ? (cli.fills > 0 ? cli.fills : ladder.config_fills) : 1;
  return ladder;
}

// The `shapepress plate` command line of one rung, on one thread.
std::vector<std::string> plate_rung_arguments(const std::string& binary,
                                              const fs::path& config_path,
                                              const PlateLadder& ladder, const RungJob& job) {
  std::vector<std::string> args = {binary,
                                   "--quiet",
                                   "--threads",
                                   "1",
                                   "plate",
                                   "--config",
                                   config_path,
                                   "--particle",
                                   ladder.particle,
                                   ladder.particle == "bms" ? "--count" : "--spheres",
                                   std::to_string(job.count),
                                   "--time-step-fraction",
                                   fmt::format("{:.17g}", job.fraction),
                                   "--out",
                                   job.folder.string()};
  if (ladder.particle == "bms") args.insert(args.end(), {"--fills", std::to_string(ladder.fills)});
  return args;
}

// Runs one rung's plate process and writes its rung.json: exit 0 done, 1 diverged, 2 refused
// (each with plate's error line); any other end stops the ladder.
nlohmann::json run_plate_rung(const std::vector<std::string>& args, const RungJob& job) {
  ensure_output_folder(job.folder);
  const ChildEnd end = run_process(args, job.folder / "log.txt");
  const int code = end.exit_code;
  nlohmann::json record = {{"key", job.key}, {"exit_code", code}};
  if (code != 0) record["message"] = error_line(job.folder / "log.txt", "plate");
  if (code != 0 && code != 1 && code != 2)
    throw ComputationError(fmt::format("advise: rung {} ended with {} (log: {})", job.label,
                                       end.how(), (job.folder / "log.txt").string()));
  write_file_atomically(job.folder / "rung.json", record.dump(1) + "\n");
  return record;
}

// Every rung's record: a finished folder's (--resume), else its plate run's, the pending ones
// side by side on the threads. Returns how many were run.
std::size_t run_plate_ladder(const std::vector<RungJob>& jobs, const AdviseCli& cli,
                             const PlateLadder& ladder, const RunContext& context,
                             std::vector<std::optional<nlohmann::json>>& records) {
  records.assign(jobs.size(), std::nullopt);
  std::vector<std::size_t> pending;
  for (std::size_t k = 0; k < jobs.size(); ++k) {
    records[k] = finished_record(jobs[k].folder / "rung.json", jobs[k].key, cli.resume);
    if (!records[k]) pending.push_back(k);
  }
  spdlog::info("advise: {} rungs, {} already run, {} to run", jobs.size(),
               jobs.size() - pending.size(), pending.size());
  const std::string binary = this_binary();
  const fs::path config_path = fs::absolute(cli.config);
  std::mutex lock;
  const auto run_rung = [&](std::size_t i) {
    const RungJob& job = jobs[pending[i]];
    const nlohmann::json record =
        run_plate_rung(plate_rung_arguments(binary, config_path, ladder, job), job);
    const int code = record["exit_code"].get<int>();
    const std::lock_guard guard(lock);
    records[pending[i]] = record;
    spdlog::info("advise: {} {}", job.label,
                 code == 0   ? "done"
                 : code == 1 ? "diverged: " + record["message"].get<std::string>()
                             : "refused: " + record["message"].get<std::string>());
  };
  run_jobs(pending.size(), context.threads > 0 ? context.threads : omp_get_max_threads(), run_rung);
  return pending.size();
}

// run.json's facts on the pick against the reference, and the log line that says them. The
// full run is the config's own: the pick's counted cost (and CPU seconds, beside it) scaled to
// the config's fills.
void report_pick(const analysis::Advice& advice, const std::vector<analysis::Rung>& rungs,
                 const PlateLadder& ladder, RunMetadata& meta) {
  const analysis::Rung& pick = rungs[*advice.pick];
  const analysis::Rung& reference = rungs[*advice.reference];
  const double scale = static_cast<double>(ladder.config_fills) / ladder.fills;
  const auto ratio = [](double reference_cost, double pick_cost) {
    return reference_cost >= 0.0 && pick_cost > 0.0 ? reference_cost / pick_cost : NAN;
  };
  const double pick_cost = static_cast<double>(pick.counted_cost);
  const double reference_cost = static_cast<double>(reference.counted_cost);
  const double saved = ratio(reference_cost, pick_cost);
  const double cpu_saved = ratio(reference.cpu_seconds, pick.cpu_seconds);
  meta.fact("reference", reference.label)
      .fact("reference_cpu_s", reference.cpu_seconds)
      .fact("pick", pick.label)
      .fact("pick_sub_spheres", pick.sub_spheres)
      .fact("pick_time_step_fraction", pick.time_step_fraction)
      .fact("pick_rms_vs_reference", advice.rows[*advice.pick].versus_reference.rms_relative)
      // What the tolerance judged, under the name the report reads for every ladder.
      .fact("pick_error_vs_reference", advice.rows[*advice.pick].error)
      .fact("pick_cpu_s", pick.cpu_seconds)
      .fact("cost_scaling", "counted_cost (and cpu_s) x config fills / fills")
      .fact("predicted_full_run_cpu_s", pick.cpu_seconds * scale);
  // Rungs run before the count (advise --resume of an older folder) state none.
  if (reference.counted_cost >= 0) meta.fact("reference_counted_cost", reference.counted_cost);
  if (pick.counted_cost >= 0)
    meta.fact("pick_counted_cost", pick.counted_cost)
        .fact("predicted_full_run_counted_cost", pick_cost * scale);
  if (std::isfinite(saved)) meta.fact("cost_saved_factor", saved);
  if (std::isfinite(cpu_saved)) meta.fact("cpu_saved_factor", cpu_saved);
  spdlog::info(
      "advise: pick {} ({} sub-spheres, step {} of critical): {:.2g} % RMS from {}, counted cost "
      "{} ({:.3g} s CPU) against {} ({:.3g} s CPU), {:.3g}x less ({:.3g}x less CPU); the config's "
      "run ({} fills) predicted {:.3g} ({:.3g} s CPU)",
      pick.label, pick.sub_spheres, fraction_text(pick.time_step_fraction),
      100.0 * advice.rows[*advice.pick].versus_reference.rms_relative, reference.label,
      pick.counted_cost, pick.cpu_seconds, reference.counted_cost, reference.cpu_seconds, saved,
      cpu_saved, ladder.config_fills, pick_cost * scale, pick.cpu_seconds * scale);
}

int run(const AdviseCli& cli, const RunContext& context) {
  if (!cli.bed_runs.empty())
    return run_bed_size_advise({cli.bed_runs, cli.out, cli.tolerance}, context);
  if (cli.config.empty() || cli.counts.empty())
    throw InputError(
        "advise: give --config and --counts (a plate or compaction ladder to run), or --bed-runs "
        "(finished compactions of a bed-size ladder to judge)");
  if (!cli.compaction.templates.empty()) return run_compaction_ladder(cli, context);
  RunMetadata meta("advise", context.command_line);
  const ConfigTable root = ConfigTable::load_file(cli.config);
  meta.input("config", cli.config);
  if (root.has("punch"))
    throw InputError(cli.config +
                     ": a compaction config: advise re-fills and re-packs its bed, so give "
                     "--templates (fill's templates.h5) and --pack-config (pack's config)");
  const PlateConfig config = read_plate_config(root, std::nullopt);
  root.check_unknown_keys();
  const PlateLadder ladder = plate_ladder(cli, config);
  AdviseCli effective = cli;
  if (effective.fractions.empty()) effective.fractions = {config.run.time_step_fraction};
  const fs::path out(cli.out);
  ensure_output_folder(out);
  const std::vector<RungJob> jobs =
      ladder_jobs(effective, ladder.particle, sha256_file(cli.config), ladder.fills);
  std::vector<std::optional<nlohmann::json>> records;
  const std::size_t rungs_run = run_plate_ladder(jobs, cli, ladder, context, records);

  std::vector<analysis::Rung> rungs;
  for (std::size_t k = 0; k < jobs.size(); ++k)
    rungs.push_back(load_rung(jobs[k], *records[k]));
  const analysis::Advice advice = analysis::advise(rungs, cli.tolerance);
  write_advice(advice, out, meta);
  meta.fact("particle_kind", ladder.particle)
      .fact("tolerance", cli.tolerance)
      .fact("rungs", static_cast<int>(jobs.size()))
      .fact("rungs_run", static_cast<int>(rungs_run))
      .fact("rungs_reused", static_cast<int>(jobs.size() - rungs_run))
      .fact("fills", ladder.fills);
  if (!advice.pick) {
    meta.write(out / run_metadata_name);
    throw ComputationError("advise: no rung finished, so none can be recommended (advice.csv)");
  }
  report_pick(advice, rungs, ladder, meta);
  meta.write(out / run_metadata_name);
  return 0;
}

}  // namespace

StageRunner setup_advise_cli(CLI::App& app) {
  auto cli = std::make_shared<AdviseCli>();
  auto* config = app.add_option(
      "--config", cli->config,
      "plate config TOML (as for `plate`), or a compaction config (as for `compact`) with "
      "--templates and --pack-config");
  app.add_option("--out", cli->out,
                 "folder of the rungs (one plate run each), advice.csv, speed_accuracy.svg, "
                 "stability_map.svg, run.json")
      ->required();
  app.add_option("--particle", cli->particle,
                 "bms (bonded sub-spheres, --count) or cms (a rigid clump, --spheres); default "
                 "bms when the config has [bms]")
      ->check(CLI::IsMember({"bms", "cms"}));
  app.add_option("--counts", cli->counts, "the sub-sphere counts of the ladder")
      ->needs(config)
      ->delimiter(',')
      ->check(CLI::Range(1, 1000000));
  app.add_option("--fractions", cli->fractions,
                 "the time-step fractions of the critical step (default: the config's "
                 "run.time_step_fraction)")
      ->delimiter(',')
      ->check(CLI::Range(1e-6, 1.0));
  app.add_option("--tolerance", cli->tolerance,
                 "largest RMS relative difference from the finest rung a pick may have (with "
                 "--bed-runs: the largest relative difference of a mean figure from the reference)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--fills", cli->fills, "bms: fills per rung (default: the config's bms.fills)")
      ->check(CLI::Range(1, 1000));
  app.add_flag("--resume", cli->resume,
               "reuse the rungs already finished in --out (a killed or extended advise)");
  CompactionAdviseRequest& bed = cli->compaction;
  auto* templates = app.add_option(
      "--templates", bed.templates,
      "compaction: fill's templates.h5 of the bed (its run.json names the meshes and the fill's "
      "options; each rung re-fills them at its count)");
  app.add_option(
         "--pack-config", bed.pack_config,
         "compaction: pack's config of the bed (re-packed at each count with the same seed)")
      ->needs(templates);
  app.add_option("--bodies", bed.bodies,
                 "compaction: bodies of the reduced bed the rungs press (default: the pack "
                 "config's pack.count)")
      ->needs(templates)
      ->check(CLI::Range(1, 10000000));
  app.add_option("--full-bodies", bed.full_bodies,
                 "compaction: bodies of the full run whose cost is predicted (default: the pack "
                 "config's pack.count)")
      ->needs(templates)
      ->check(CLI::Range(1, 10000000));
  app.add_option("--seeds", bed.seeds,
                 "compaction: packing seeds, each a packing of the same bed (the ladder runs on "
                 "each; default: the pack config's seed)")
      ->needs(templates)
      ->delimiter(',');
  app.add_option("--curve-axis", bed.curve_axis,
                 "compaction: the stress curve's abscissa, strain (from the punch's start) or "
                 "solid_fraction (by shape volume: beds that settled apart compared where they "
                 "are equally dense)")
      ->needs(templates)
      ->check(CLI::IsMember({"strain", "solid_fraction"}))
      ->capture_default_str();
  app.add_option("--density-scales", bed.density_scales,
                 "compaction: the mass scalings of the ladder (run.density_scale; default: the "
                 "config's)")
      ->needs(templates)
      ->delimiter(',')
      ->check(CLI::Range(1e-6, 1e12));
  app.add_option("--reference-run", bed.reference_runs,
                 "compaction: a finished compact run's folder of the same bed at a setting the "
                 "ladder does not run (a full study's, at a count too dear to re-run), taken as a "
                 "rung of its seed; repeatable")
      ->needs(templates)
      ->check(CLI::ExistingDirectory);
  app.add_option("--bed-runs", cli->bed_runs,
                 "finished compact runs' folders of one powder at several bed sizes (bodies) and "
                 "sub-sphere counts, each packed with its own seed: the bodies, count and seeds "
                 "within --tolerance of the largest, finest bed, and their predicted cost "
                 "(bed_size.csv, bed_size_*.svg, bed_speed_accuracy.svg)")
      ->excludes(config)
      ->delimiter(',')
      ->check(CLI::ExistingDirectory);
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::scenarios
