#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>

#include "common/atomic_file.hpp"
#include "common/config.hpp"
#include "common/error.hpp"
#include "common/provenance.hpp"
#include "scenarios/cli.hpp"
#include "scenarios/config_io.hpp"
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
};

int run(const PlateCli& cli, const RunContext& context) {
  RunMetadata meta("plate", context.command_line);
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
  // What the run used, every key with its value (defaults and command-line overrides included):
  // `plate --config effective.toml` with the same --particle runs it again.
  write_file_atomically(out / "effective.toml",
                        fmt::format("# {}\n# the effective config of a plate --particle {} run\n",
                                    context.command_line, cli.particle) +
                            plate_config_toml(config));
  const PlateRunOutcome outcome =
      run_plate_config(config, kind, [](const std::string& line) { spdlog::info("{}", line); });
  write_force_csv(out / "force.csv", outcome, config, kind);
  meta.output("force.csv");
  if (cli.snapshot && outcome.final_snapshot) {
    write_plate_snapshot(out, outcome,
                         Provenance{context.command_line, root.text(),
                                    config.bms ? std::optional(config.bms->seed) : std::nullopt});
    meta.output("final.h5").output("final.xdmf");
  }
  add_plate_facts(meta, config, kind, outcome);
  meta.write(out / run_metadata_name);
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
  app.add_option("--config", cli->config, "plate config TOML (materials, sphere, plate, bms, bond)")
      ->required();
  app.add_option("--out", cli->out, "output folder (force.csv, effective.toml)")->required();
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
  app.add_flag(
      "--snapshot", cli->snapshot,
      "also write final.h5 + final.xdmf (ParaView: sub-spheres, bonds as lines, clump axes, "
      "plates)");
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::scenarios
