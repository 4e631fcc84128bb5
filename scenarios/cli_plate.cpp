#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <string_view>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/config.hpp"
#include "common/error.hpp"
#include "common/provenance.hpp"
#include "common/resume.hpp"
#include "common/sha256.hpp"
#include "scenarios/cli.hpp"
#include "scenarios/config_io.hpp"
#include "scenarios/plate_checkpoint.hpp"
#include "scenarios/plate_run.hpp"
#include "scenarios/run_facts.hpp"
#include "simulate/contact_law_config.hpp"

namespace shapepress::scenarios {
namespace {

struct PlateCli {
  std::string config;
  std::string out;
  std::string model;  // empty: each interaction's normal_law
  std::string particle = "sphere";
  int count = 0;
  int spheres = 0;
  int fills = 0;
  std::int64_t seed = -1;
  double time_step_fraction = 0.0;  // 0: the config's run.time_step_fraction
  bool snapshot = false;
  std::string resume;
};

constexpr std::string_view checkpoint_folder = "checkpoints";

// The options resume.json keeps, by name (common/resume.hpp RunInvocation::arguments).
std::map<std::string, std::vector<std::string>> arguments_of(const PlateCli& cli) {
  std::map<std::string, std::vector<std::string>> a;
  a["particle"] = {cli.particle};
  if (!cli.model.empty()) a["model"] = {cli.model};
  a["count"] = {std::to_string(cli.count)};
  a["spheres"] = {std::to_string(cli.spheres)};
  a["fills"] = {std::to_string(cli.fills)};
  a["seed"] = {std::to_string(cli.seed)};
  a["time_step_fraction"] = {exact_text(cli.time_step_fraction)};
  a["snapshot"] = {cli.snapshot ? "1" : "0"};
  return a;
}

// --resume OUT: the arguments the run was started with, from the working folder it was started
// in (relative paths in them and in the config mean what they meant then).
PlateCli resumed_arguments(const std::string& folder, std::string& command_line) {
  const std::filesystem::path out = std::filesystem::absolute(folder);
  const std::filesystem::path record = out / std::string(checkpoint_folder) / "resume.json";
  const RunInvocation invocation = resume_invocation(record, folder);
  command_line = invocation.command_line;
  const auto argument = [&](const char* name) {
    const auto it = invocation.arguments.find(name);
    if (it == invocation.arguments.end() || it->second.empty())
      throw InputError(
          fmt::format("{}: no argument '{}' (a damaged resume record)", record.string(), name));
    return it->second.front();
  };
  const auto whole = [&](const char* name, std::int64_t least) {
    return parse_whole(argument(name), name, record, least, std::numeric_limits<int>::max());
  };
  PlateCli cli;
  cli.config = invocation.config;
  cli.out = out.string();
  cli.particle = argument("particle");
  if (cli.particle != "sphere" && cli.particle != "bms" && cli.particle != "cms")
    throw InputError(fmt::format("{}: argument 'particle' is '{}' (a damaged resume record)",
                                 record.string(), cli.particle));
  if (invocation.arguments.contains("model")) cli.model = argument("model");
  cli.count = static_cast<int>(whole("count", 0));
  cli.spheres = static_cast<int>(whole("spheres", 0));
  cli.fills = static_cast<int>(whole("fills", 0));
  cli.seed =
      parse_whole(argument("seed"), "seed", record, -1, std::numeric_limits<std::int64_t>::max());
  cli.time_step_fraction = parse_exact(argument("time_step_fraction"), record);
  cli.snapshot = argument("snapshot") == "1";
  return cli;
}

int run(const PlateCli& given, const RunContext& context) {
  std::string command_line = context.command_line;
  const std::filesystem::path resumed(given.resume);
  if (finished_before_resume("plate", given.resume,
                             resumed / std::string(checkpoint_folder) / "resume.json",
                             resumed / std::string(run_metadata_name)))
    return 0;
  const PlateCli cli = given.resume.empty() ? given : resumed_arguments(given.resume, command_line);
  if (cli.config.empty()) throw InputError("plate: give --config FILE (or --resume OUT)");
  if (cli.out.empty()) throw InputError("plate: give --out FOLDER (or --resume OUT)");
  RunMetadata meta("plate", command_line);
  const ConfigTable root = ConfigTable::load_file(cli.config);
  meta.input("config", cli.config);
  std::optional<std::string> model;  // --model overrides normal_law of every interaction
  if (!cli.model.empty()) model = cli.model;
  PlateConfig config = read_plate_config(root, model);
  root.check_unknown_keys();
  const PlateParticleKind kind = cli.particle == "bms"   ? PlateParticleKind::bms
                                 : cli.particle == "cms" ? PlateParticleKind::cms
                                                         : PlateParticleKind::sphere;
  const bool bonded = kind == PlateParticleKind::bms;
  if (bonded && !config.bms)
    throw InputError(cli.config + ": --particle bms needs a [bms] table (and [bond])");
  if (!bonded && config.bms)
    spdlog::info("plate: --particle {}: the [bms] and [bond] tables are not used", cli.particle);
  if (kind != PlateParticleKind::cms && config.cms)
    spdlog::info("plate: --particle {}: the [cms] table is not used", cli.particle);
  if (cli.count > 0) {
    if (!bonded) throw InputError("--count is the number of sub-spheres of --particle bms");
    config.bms->count = cli.count;
  }
  if (cli.fills > 0 || cli.seed >= 0) {
    if (!bonded) throw InputError("--fills and --seed are the random fills of --particle bms");
    if (cli.fills > 0) config.bms->fills = cli.fills;
    if (cli.seed >= 0) config.bms->seed = static_cast<std::uint64_t>(cli.seed);
  }
  if (kind == PlateParticleKind::cms && !config.cms) {  // [cms] is optional: its defaults
    config.cms = CmsConfig{};
    config.cms->material = config.sphere_material;
  }
  if (cli.spheres > 0) {
    if (kind != PlateParticleKind::cms)
      throw InputError("--spheres is the number of overlapping sub-spheres of --particle cms");
    config.cms->count = cli.spheres;
  }
  if (cli.time_step_fraction > 0.0) {
    if (config.run.time_step)
      throw InputError(cli.config +
                       ": --time-step-fraction scales the critical step, but the config fixes "
                       "run.time_step");
    config.run.time_step_fraction = cli.time_step_fraction;
  }
  const std::filesystem::path out(cli.out);
  ensure_output_folder(out);
  const std::filesystem::path checkpoints = out / std::string(checkpoint_folder);
  if (!given.resume.empty()) {
    for (const auto* sub : {"", "checkpoints"})
      remove_stale_temporaries(out / sub);
  } else {
    // A fresh start must not be resumed from another run's checkpoints.
    std::filesystem::remove_all(checkpoints);
  }
  ensure_output_folder(checkpoints);
  const CheckpointFolderGuard checkpoints_guard(checkpoints);
  if (given.resume.empty() || !std::filesystem::exists(checkpoints / "resume.json"))
    write_invocation(checkpoints / "resume.json",
                     {command_line, std::filesystem::current_path(), cli.config,
                      sha256_file(cli.config), arguments_of(cli)});
  const PlateCheckpoints resumable(
      checkpoints, {config.checkpoint_every, config.checkpoint_minutes},
      Provenance{command_line, root.text(),
                 config.bms ? std::optional(config.bms->seed) : std::nullopt},
      cli.snapshot);
  const SignalCheckpoints signals;
  const PlateRunOutcome outcome = run_plate_config(
      config, kind, [](const std::string& line) { spdlog::info("{}", line); }, nullptr, &resumable);
  if (outcome.interrupted) {
    spdlog::warn(
        "plate: stopped by signal {}; checkpoint written: continue with `shapepress plate "
        "--resume {}`",
        SignalCheckpoints::received(), out.string());
    return 128 + SignalCheckpoints::received();
  }
  // What the run used, every key with its value (defaults and command-line overrides included):
  // `plate --config effective.toml` with the same --particle runs it again. Written with the
  // results, so a run that fails leaves no file.
  write_file_atomically(out / "effective.toml",
                        fmt::format("# {}\n# the effective config of a plate --particle {} run\n",
                                    command_line, cli.particle) +
                            plate_config_toml(config));
  write_force_csv(out / "force.csv", outcome, config, kind);
  meta.output("force.csv");
  if (cli.snapshot) {  // the first fill's last state, kept when it finished (PlateCheckpoints)
    for (const auto* name : {"final.h5", "final.xdmf"})  // (moved already by a killed attempt)
      if (std::filesystem::exists(checkpoints / name))
        std::filesystem::rename(checkpoints / name, out / name);
    meta.output("final.h5").output("final.xdmf");
  }
  add_plate_facts(meta, config, kind, outcome);
  meta.write(out / run_metadata_name);
  // The run is whole: its checkpoints have done their work.
  std::error_code ignored;
  std::filesystem::remove_all(checkpoints, ignored);
  const PlateRow& last = outcome.rows.back();
  spdlog::info("plate: {} rows in {}; {} of {} bonds intact; {:.3g} s wall, {:.3g} s CPU",
               outcome.rows.size(), (out / "force.csv").string(), last.intact_bonds, outcome.bonds,
               last.wall_seconds, last.cpu_seconds);
  return 0;
}

}  // namespace

StageOptions plate_options() {
  return plate_config_options("plate");
}

StageRunner setup_plate_cli(CLI::App& app) {
  auto cli = std::make_shared<PlateCli>();
  app.add_option("--config", cli->config,
                 "plate config TOML (materials, sphere, plate, bms, bond); required unless "
                 "--resume");
  app.add_option("--out", cli->out,
                 "output folder (force.csv, effective.toml); required unless --resume");
  app.add_option("--model", cli->model,
                 "normal law of every interaction, overriding the config's normal_law, with "
                 "the interaction's parameters of that law (multicontact: paper Eq. 6)")
      ->check(CLI::IsMember(normal_law_names()));
  app.add_option("--particle", cli->particle,
                 "sphere (one Hertz sphere), bms (bonded sub-spheres filling it, [bms] + [bond]) "
                 "or cms (one rigid clump of overlapping sub-spheres filling it, [cms])")
      ->check(CLI::IsMember({"sphere", "bms", "cms"}))
      ->capture_default_str();
  app.add_option("--count", cli->count, "bms: number of sub-spheres (overrides bms.count)")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--fills", cli->fills,
                 "bms: mean curve of this many fills, seeds seed, seed + 1, … (overrides "
                 "bms.fills; run side by side on the --threads)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--seed", cli->seed, "bms: seed of the (first) fill (overrides bms.seed)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--spheres", cli->spheres,
                 "cms: number of overlapping sub-spheres asked of the filler (overrides "
                 "cms.count)")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--time-step-fraction", cli->time_step_fraction,
                 "the step as this fraction of the critical one (overrides "
                 "run.time_step_fraction; `advise` and its stability map vary it)")
      ->check(CLI::PositiveNumber);
  auto* snapshot = app.add_flag(
      "--snapshot", cli->snapshot,
      "also write final.h5 + final.xdmf (ParaView: sub-spheres, bonds as lines, clump axes, "
      "plates)");
  auto* resume = app.add_option(
      "--resume", cli->resume,
      "continue the killed run in this folder from its checkpoints (finished fills reused), with "
      "the arguments it was started with");
  for (const char* name : {"--config", "--out", "--model", "--particle", "--count", "--fills",
                           "--seed", "--spheres", "--time-step-fraction"})
    resume->excludes(app.get_option(name));
  resume->excludes(snapshot);
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::scenarios
