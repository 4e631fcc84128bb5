// shapepress advise: the cheapest resolution and time step that still hold a plate config's
// answer (issue 21, points 2 and 3). Each rung of the ladder (sub-sphere count × time-step
// fraction) is one `shapepress plate` process in its own folder under --out, run side by side
// on the --threads (one thread each), so that a rung that diverges ends with its own exit code
// and named cause, and a killed advise leaves every finished rung reusable: a rung's folder
// counts as done when its rung.json (written last, atomically) names the same config, particle,
// count, fraction and fills. The judgement on the finished ladder is analysis/advise.hpp.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <thread>

#include <omp.h>

#include "analysis/advise.hpp"
#include "analysis/runs.hpp"
#include "common/atomic_file.hpp"
#include "common/config.hpp"
#include "common/error.hpp"
#include "common/run_metadata.hpp"
#include "common/sha256.hpp"
#include "scenarios/cli.hpp"
#include "scenarios/config_io.hpp"

extern char** environ;

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
};

struct RungJob {
  std::string label;
  int count = 0;
  double fraction = 0.0;
  fs::path folder;
  nlohmann::json key;  // what makes a finished folder this rung
};

// The named cause of a run's divergence message (simulate/diagnostics.cpp words them).
std::string divergence_cause(const std::string& message) {
  if (message.find("non-finite") != std::string::npos) return "non-finite";
  if (message.find("bonded spheres") != std::string::npos) return "bond overlap";
  if (message.find("energy") != std::string::npos) return "energy";
  if (message.find("overlap") != std::string::npos) return "overlap";
  return "failed";
}

// The run's message: the last "shapepress plate: error: …" (exit 2) or "…: failed: …" (exit 1)
// line main() prints.
std::string error_line(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line))
    for (const char* mark : {"plate: error: ", "plate: failed: "})
      if (const auto at = line.find(mark); at != std::string::npos)
        last = line.substr(at + std::char_traits<char>::length(mark));
  return last;
}

// Runs `args` (argv[0] the binary) with stdout and stderr into `log`; returns its exit code.
int run_process(const std::vector<std::string>& args, const fs::path& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> argv;
  for (const std::string& a : args)
    argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0)
    throw ComputationError(fmt::format("advise: cannot start {}: {}", args[0], spawned));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw ComputationError("advise: lost the run of " + log.string());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string fraction_text(double f) {
  return fmt::format("{:.4g}", f);
}

// The finished rung of `job` from its folder (the run's curve and CPU seconds, or its end).
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

std::vector<RungJob> ladder(const AdviseCli& cli, const std::string& particle,
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

// rung.json of a finished rung whose key is `job`'s; nothing when the folder holds no finished
// rung. InputError when it holds another rung (another config or fills) or when it is finished
// and --resume was not given.
std::optional<nlohmann::json> finished(const RungJob& job, bool resume) {
  const fs::path path = job.folder / "rung.json";
  if (!fs::exists(path)) return std::nullopt;
  std::ifstream in(path);
  nlohmann::json record = nlohmann::json::parse(in, nullptr, false);
  if (record.is_discarded() || !record.contains("key") || !record.contains("exit_code"))
    throw InputError(fmt::format("{}: not a rung record; remove the folder", path.string()));
  if (record["key"] != job.key)
    throw InputError(
        fmt::format("{} holds a rung of another advise ({} against {}): use another --out",
                    path.string(), record["key"].dump(), job.key.dump()));
  if (!resume)
    throw InputError(fmt::format(
        "{} holds finished rungs of an earlier advise: --resume reuses them", job.folder.string()));
  return record;
}

int run(const AdviseCli& cli, const RunContext& context) {
  RunMetadata meta("advise", context.command_line);
  const ConfigTable root = ConfigTable::load_file(cli.config);
  meta.input("config", cli.config);
  const PlateConfig config = read_plate_config(root, std::nullopt);
  root.check_unknown_keys();
  const std::string particle = !cli.particle.empty() ? cli.particle : config.bms ? "bms" : "cms";
  if (particle == "bms" && !config.bms)
    throw InputError(cli.config + ": advise --particle bms needs a [bms] table (and [bond])");
  if (particle != "bms" && cli.fills > 0)
    throw InputError("--fills is the random fills of --particle bms");
  if (config.run.time_step)
    throw InputError(cli.config +
                     ": advise varies run.time_step_fraction, but the config fixes "
                     "run.time_step");
  const int config_fills = config.bms ? config.bms->fills : 1;
  const int fills = particle == "bms" ? (cli.fills > 0 ? cli.fills : config_fills) : 1;
  AdviseCli effective = cli;
  if (effective.fractions.empty()) effective.fractions = {config.run.time_step_fraction};
  const fs::path out(cli.out);
  ensure_output_folder(out);
  const std::vector<RungJob> jobs = ladder(effective, particle, sha256_file(cli.config), fills);

  std::vector<std::optional<nlohmann::json>> records(jobs.size());
  std::vector<std::size_t> pending;
  for (std::size_t k = 0; k < jobs.size(); ++k) {
    records[k] = finished(jobs[k], cli.resume);
    if (!records[k]) pending.push_back(k);
  }
  spdlog::info("advise: {} rungs, {} already run, {} to run", jobs.size(),
               jobs.size() - pending.size(), pending.size());
  const std::string binary = fs::read_symlink("/proc/self/exe").string();
  const fs::path config_path = fs::absolute(cli.config);
  std::atomic<std::size_t> next{0};
  std::mutex lock;
  std::exception_ptr failure;
  const auto worker = [&] {
    for (std::size_t i = next++; i < pending.size(); i = next++) {
      const RungJob& job = jobs[pending[i]];
      try {
        ensure_output_folder(job.folder);
        std::vector<std::string> args = {binary,
                                         "--quiet",
                                         "--threads",
                                         "1",
                                         "plate",
                                         "--config",
                                         config_path,
                                         "--particle",
                                         particle,
                                         particle == "bms" ? "--count" : "--spheres",
                                         std::to_string(job.count),
                                         "--time-step-fraction",
                                         fmt::format("{:.17g}", job.fraction),
                                         "--out",
                                         job.folder.string()};
        if (particle == "bms") args.insert(args.end(), {"--fills", std::to_string(fills)});
        const int code = run_process(args, job.folder / "log.txt");
        nlohmann::json record = {{"key", job.key}, {"exit_code", code}};
        if (code != 0) record["message"] = error_line(job.folder / "log.txt");
        if (code != 0 && code != 1 && code != 2)
          throw ComputationError(fmt::format("advise: rung {} ended with exit {} (log: {})",
                                             job.label, code, (job.folder / "log.txt").string()));
        write_file_atomically(job.folder / "rung.json", record.dump(1) + "\n");
        const std::lock_guard guard(lock);
        records[pending[i]] = record;
        spdlog::info("advise: {} {}", job.label,
                     code == 0   ? "done"
                     : code == 1 ? "diverged: " + record["message"].get<std::string>()
                                 : "refused: " + record["message"].get<std::string>());
      } catch (...) {
        const std::lock_guard guard(lock);
        if (!failure) failure = std::current_exception();
        next = pending.size();
      }
    }
  };
  const int threads = context.threads > 0 ? context.threads : omp_get_max_threads();
  std::vector<std::thread> team;
  for (int t = 0; t < std::min<int>(threads, static_cast<int>(pending.size())); ++t)
    team.emplace_back(worker);
  for (std::thread& t : team)
    t.join();
  if (failure) std::rethrow_exception(failure);

  std::vector<analysis::Rung> rungs;
  for (std::size_t k = 0; k < jobs.size(); ++k)
    rungs.push_back(load_rung(jobs[k], *records[k]));
  const analysis::Advice advice = analysis::advise(rungs, cli.tolerance);
  analysis::write_advice_csv(out / "advice.csv", advice);
  meta.output("advice.csv");
  if (!analysis::find_gnuplot().empty()) {
    analysis::plot_chart(analysis::speed_accuracy_chart(advice), out / "speed_accuracy");
    analysis::plot_chart(analysis::stability_map_chart(advice), out / "stability_map");
    meta.output("speed_accuracy.svg").output("stability_map.svg");
  } else {
    spdlog::warn("advise: gnuplot not on PATH: no charts (advice.csv has the numbers)");
  }
  meta.fact("particle_kind", particle)
      .fact("tolerance", cli.tolerance)
      .fact("rungs", static_cast<int>(jobs.size()))
      .fact("rungs_run", static_cast<int>(pending.size()))
      .fact("rungs_reused", static_cast<int>(jobs.size() - pending.size()))
      .fact("fills", fills);
  if (!advice.pick) {
    meta.write(out / run_metadata_name);
    throw ComputationError("advise: no rung finished, so none can be recommended (advice.csv)");
  }
  const analysis::Rung& pick = rungs[*advice.pick];
  const analysis::Rung& reference = rungs[*advice.reference];
  // The full run is the config's own: the pick's CPU seconds scaled to the config's fills.
  const double predicted = pick.cpu_seconds * static_cast<double>(config_fills) / fills;
  meta.fact("reference", reference.label)
      .fact("reference_cpu_s", reference.cpu_seconds)
      .fact("pick", pick.label)
      .fact("pick_sub_spheres", pick.sub_spheres)
      .fact("pick_time_step_fraction", pick.time_step_fraction)
      .fact("pick_rms_vs_reference", advice.rows[*advice.pick].versus_reference.rms_relative)
      .fact("pick_cpu_s", pick.cpu_seconds)
      .fact("predicted_full_run_cpu_s", predicted)
      .fact("cost_saved_factor", reference.cpu_seconds / pick.cpu_seconds);
  meta.write(out / run_metadata_name);
  spdlog::info(
      "advise: pick {} ({} sub-spheres, step {} of critical): {:.2g} % RMS from {}, {:.3g} s "
      "CPU against {:.3g} s ({:.3g}x less); the config's run ({} fills) predicted {:.3g} s CPU",
      pick.label, pick.sub_spheres, fraction_text(pick.time_step_fraction),
      100.0 * advice.rows[*advice.pick].versus_reference.rms_relative, reference.label,
      pick.cpu_seconds, reference.cpu_seconds, reference.cpu_seconds / pick.cpu_seconds,
      config_fills, predicted);
  return 0;
}

}  // namespace

StageRunner setup_advise_cli(CLI::App& app) {
  auto cli = std::make_shared<AdviseCli>();
  app.add_option("--config", cli->config, "plate config TOML (as for `plate`)")->required();
  app.add_option("--out", cli->out,
                 "folder of the rungs (one plate run each), advice.csv, speed_accuracy.svg, "
                 "stability_map.svg, run.json")
      ->required();
  app.add_option("--particle", cli->particle,
                 "bms (bonded sub-spheres, --count) or cms (a rigid clump, --spheres); default "
                 "bms when the config has [bms]")
      ->check(CLI::IsMember({"bms", "cms"}));
  app.add_option("--counts", cli->counts, "the sub-sphere counts of the ladder")
      ->required()
      ->delimiter(',')
      ->check(CLI::Range(1, 1000000));
  app.add_option("--fractions", cli->fractions,
                 "the time-step fractions of the critical step (default: the config's "
                 "run.time_step_fraction)")
      ->delimiter(',')
      ->check(CLI::Range(1e-6, 1.0));
  app.add_option("--tolerance", cli->tolerance,
                 "largest RMS relative difference from the finest rung a pick may have")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--fills", cli->fills, "bms: fills per rung (default: the config's bms.fills)")
      ->check(CLI::Range(1, 1000));
  app.add_flag("--resume", cli->resume,
               "reuse the rungs already finished in --out (a killed or extended advise)");
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::scenarios
