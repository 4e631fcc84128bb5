#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>
#include <string_view>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/command_options.hpp"
#include "common/config.hpp"
#include "common/error.hpp"
#include "common/provenance.hpp"
#include "common/resume.hpp"
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

// plate's options, bound once: parsed, recorded for --resume, written into run.json and
// documented (docs/stages.md).
CommandOptions plate_command(PlateCli& cli) {
  CommandOptions options("plate");
  options
      .text("--config", &cli.config,
            "plate config TOML (materials, sphere, plate, bms, bond); required unless --resume")
      .config()
      .text("--out", &cli.out,
            "output folder (force.csv, effective.toml); required unless --resume")
      .output()
      .text("--model", &cli.model,
            "normal law of every interaction, overriding the config's normal_law, with the "
            "interaction's parameters of that law (multicontact: paper Eq. 6)")
      .choices(normal_law_names())
      .text("--particle", &cli.particle,
            "sphere (one Hertz sphere), bms (bonded sub-spheres filling it, [bms] + [bond]) or "
            "cms (one rigid clump of overlapping sub-spheres filling it, [cms])")
      .choices({"sphere", "bms", "cms"})
      .show_default()
      .whole("--count", &cli.count, "bms: number of sub-spheres (overrides bms.count)")
      .range(Range::closed(1, 1000000))
      .whole("--fills", &cli.fills,
             "bms: mean curve of this many fills, seeds seed, seed + 1, … (overrides bms.fills; "
             "run side by side on the --threads)")
      .range(Range::closed(1, 1000))
      .whole("--seed", &cli.seed, "bms: seed of the (first) fill (overrides bms.seed)")
      .range(Range::non_negative())
      .whole("--spheres", &cli.spheres,
             "cms: number of overlapping sub-spheres asked of the filler (overrides cms.count)")
      .range(Range::closed(1, 1000000))
      .number("--time-step-fraction", &cli.time_step_fraction,
              "the step as this fraction of the critical one (overrides run.time_step_fraction; "
              "`advise` and its stability map vary it)")
      .range(Range::positive())
      .recorded_as("time_step_fraction")
      .flag("--snapshot", &cli.snapshot,
            "also write final.h5 + final.xdmf (ParaView: sub-spheres, bonds as lines, clump axes, "
            "plates)");
  return options;
}

int run(const PlateCli& given, const RunContext& context) {
  std::string command_line = context.command_line;
  const std::filesystem::path resumed(given.resume);
  if (finished_before_resume("plate", given.resume, resumed / std::string(checkpoint_folder),
                             resumed / std::string(run_metadata_name)))
    return 0;
  PlateCli cli = given;
  if (!given.resume.empty())
    command_line = plate_command(cli).resume(
        std::filesystem::absolute(given.resume) / std::string(checkpoint_folder) / "resume.json",
        given.resume);
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
  if (!given.resume.empty()) remove_stale_temporaries(out);
  ResumableRun resumable("plate", out, checkpoints,
                         {config.checkpoint_every, config.checkpoint_minutes});
  resumable.start(!given.resume.empty(), plate_command(cli).invocation(command_line));
  const PlateCheckpoints fills(
      checkpoints, resumable.policy(),
      Provenance{command_line, root.text(),
                 config.bms ? std::optional(config.bms->seed) : std::nullopt},
      cli.snapshot);
  const PlateRunOutcome outcome = run_plate_config(
      config, kind, [](const std::string& line) { spdlog::info("{}", line); }, nullptr, &fills);
  if (outcome.interrupted) return resumable.stopped();
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
  meta.options(plate_command(cli).json());
  add_plate_facts(meta, config, kind, outcome);
  meta.write(out / run_metadata_name);
  resumable.finish();
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

CommandOptions plate_command_options() {
  static PlateCli defaults;
  return plate_command(defaults);
}

StageRunner setup_plate_cli(CLI::App& app) {
  auto cli = std::make_shared<PlateCli>();
  plate_command(*cli).add_to(app, &cli->resume,
                             "continue the killed run in this folder from its checkpoints "
                             "(finished fills reused), with the arguments it was started with");
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::scenarios
