#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "common/atomic_file.hpp"
#include "common/checkpoint.hpp"
#include "common/command_options.hpp"
#include "common/config.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "common/provenance.hpp"
#include "common/resume.hpp"
#include "common/run_metadata.hpp"
#include "packing/cli.hpp"
#include "packing/pack_config.hpp"
#include "simulate/checkpoint.hpp"

namespace shapepress::packing {
namespace {

struct PackCli {
  std::vector<std::string> templates;
  std::string config;
  std::string out;
  std::optional<std::uint64_t> seed;
  std::optional<std::int64_t> count;
  std::string summary;
  std::vector<std::string> template_names;
  std::string resume;
};

// The checkpoints of `pack --out packed.h5` go to packed.h5.checkpoints/ beside it (pack's output
// is a file, not a folder); removed when the run ends whole.
std::filesystem::path checkpoint_folder(const std::filesystem::path& out) {
  return out.string() + ".checkpoints";
}

constexpr std::string_view pack_stage = "pack";

CheckpointState phase_state(const PackPhaseState& s) {
  CheckpointState state;
  state.whole("phase", static_cast<std::int64_t>(s.phase))
      .number("phase_start", s.phase_start)
      .whole("phase_step", s.phase_step)
      .flag("settled", s.settled)
      .number("settled_solid_fraction", s.settled_solid_fraction)
      .number("precompression_solid_fraction", s.precompression_solid_fraction);
  return state;
}

PackPhaseState read_phase(const std::filesystem::path& path) {
  const CheckpointRecord record = read_checkpoint_record(path, pack_stage);
  const CheckpointFields state = record.state();
  PackPhaseState s;
  s.phase = static_cast<PackPhase>(state.whole("phase", 0, static_cast<int>(PackPhase::release)));
  s.phase_start = state.number("phase_start");
  s.phase_step = state.whole("phase_step", 0, std::numeric_limits<std::int64_t>::max());
  s.settled = state.flag("settled");
  s.settled_solid_fraction = state.number("settled_solid_fraction");
  s.precompression_solid_fraction = state.number("precompression_solid_fraction");
  return s;
}

// pack's options, bound once: parsed, recorded for --resume, written into run.json and
// documented (docs/stages.md).
CommandOptions pack_command(PackCli& cli) {
  CommandOptions options("pack");
  options
      .texts("templates", &cli.templates,
             "templates files of fill (their /bms and /cms groups); none for spheres only")
      .text("--config", &cli.config, "pack config TOML ([pack], [[template]], [sizes], ...)")
      .config()
      .text("--out", &cli.out, "packed.h5 (packed.xmf and packed.h5.run.json beside it)")
      .output()
      .whole("--seed", &cli.seed, "random seed (overrides pack.seed)")
      .text("--summary", &cli.summary,
            "sizes from this shape-stats summary.json (its Q3 x10/x50/x90) instead of the "
            "config's [sizes] summary or size_quantiles")
      .whole("--count", &cli.count, "number of bodies (overrides pack.count and target_mass)")
      .texts("--template", &cli.template_names,
             "a template to pack, \"bms/<name>\", \"cms/<name>\" or \"sphere\"; repeated: equal "
             "weights (replaces the config's [[template]] blocks)");
  return options;
}

// run.json names a length's fact with its unit, as the other stages do (bed_height_m).
void add_measures(RunMetadata& meta, const PackMeasures& m) {
  for_each_measure(m, [&](const char* name, std::string_view unit, double value) {
    meta.fact(unit == "m" ? std::string(name) + "_m" : std::string(name), value);
  });
}

// The command line's overrides of the config: seed, body count and templates. A study packs
// one config at several sizes and with several shapes without copying it.
void apply_overrides(const PackCli& cli, PackConfig& config) {
  if (cli.seed) config.request.seed = *cli.seed;
  if (cli.count) {
    if (*cli.count <= 0) throw InputError(fmt::format("pack: --count {} must be > 0", *cli.count));
    config.request.count = *cli.count;
    config.request.target_mass.reset();
  }
  if (!cli.template_names.empty()) {
    config.request.templates.clear();
    for (const std::string& name : cli.template_names)
      config.request.templates.push_back({name, 1.0});
  }
}

// Where a resumed run starts: its latest checkpoint's bed and phase, or none (the run starts
// again). Temporaries a killed write left beside `out` go first.
std::optional<PackResume> resume_point(const std::filesystem::path& out,
                                       const std::filesystem::path& checkpoints) {
  remove_stale_temporaries(out.has_parent_path() ? out.parent_path() : ".",
                           out.stem().string() + ".");
  if (const auto latest = latest_checkpoint(checkpoints)) {
    spdlog::info("pack: resuming {} from the checkpoint at step {}", out.string(), latest->step);
    return PackResume{read_snapshot(latest->snapshot), read_phase(latest->record)};
  }
  spdlog::info("pack: {} has no checkpoint yet: starting the run again", out.string());
  return std::nullopt;
}

// run.json's facts of the packed bed and the run that packed it.
void add_pack_facts(RunMetadata& meta, const PackRun& result, const PackConfig& config) {
  meta.fact("bodies", static_cast<std::int64_t>(result.packing.size()))
      .fact("sub_spheres", static_cast<std::int64_t>(result.packing.particles.size()))
      .fact("bonds", static_cast<std::int64_t>(result.packing.bonds.size()))
      .fact("box_x_m", result.packing.box.length_x)
      .fact("box_y_m", result.packing.box.length_y)
      .fact("floor_m", result.packing.floor)
      .fact("top_m", result.packing.top)
      .fact("seed", static_cast<std::int64_t>(config.request.seed))
      .fact("time_step_s", result.time_step)
      .fact("settle_density_scale", config.request.settle_density_scale)
      .fact("settle_time_step_s", result.settle_time_step)
      .fact("steps", result.steps)
      .fact("loop_s", result.loop_seconds)
      .fact("settled", result.settled)
      .fact("settled_solid_fraction", result.settled_solid_fraction)
      .fact("solid_fraction_volume", solid_volume_name(config.request.solid_fraction_volume));
  // Absent when there was no press, or the bed settled denser than its target.
  if (result.precompression_solid_fraction > 0.0)
    meta.fact("precompression_solid_fraction", result.precompression_solid_fraction);
}

void print_pack_summary(const PackRun& result, const PackConfig& config) {
  const PackMeasures& m = result.packing.measures;
  std::printf(
      "pack: %zu bodies, %zu sub-spheres, %zu bonds; bed height %.4g m\n"
      "  solid fraction %.4f by body volume, %.4f by shape volume, %.4f by sub-sphere volume\n"
      "  coordination %.3f; orientation order <P2> %.4f; largest overlap %.3g m (%.3g of a "
      "radius)\n"
      "  x10/x50/x90 %.4g/%.4g/%.4g m (target %.4g/%.4g/%.4g, %s-weighted)\n"
      "  %lld steps of %.3g s%s in %.1f s%s\n",
      result.packing.size(), result.packing.particles.size(), result.packing.bonds.size(),
      m.bed_height, m.solid_fraction, m.solid_fraction_shape, m.solid_fraction_spheres,
      m.coordination, m.orientation_order, m.largest_overlap, m.largest_overlap_relative, m.x10,
      m.x50, m.x90, m.target_x10, m.target_x50, m.target_x90,
      config.request.sizes.volume_weighted ? "volume" : "number",
      static_cast<long long>(result.steps), result.time_step,
      config.request.settle_density_scale == 1.0
          ? ""
          : fmt::format(" (the settle's of {:.3g} s at {:g} × density)", result.settle_time_step,
                        config.request.settle_density_scale)
                .c_str(),
      result.loop_seconds, result.settled ? "" : " (not at rest: see the warning)");
}

int run(const PackCli& given, const RunContext& context) {
  std::string command_line = context.command_line;
  if (finished_before_resume("pack", given.resume, checkpoint_folder(given.resume),
                             run_metadata_beside(given.resume)))
    return 0;
  PackCli cli = given;
  if (!given.resume.empty())
    command_line = pack_command(cli).resume(
        checkpoint_folder(std::filesystem::absolute(given.resume)) / "resume.json", given.resume);
  if (cli.config.empty()) throw InputError("pack: give --config FILE (or --resume OUT)");
  if (cli.out.empty()) throw InputError("pack: give --out FILE (or --resume OUT)");
  RunMetadata meta("pack", command_line);
  const ConfigTable root = ConfigTable::load_file(cli.config);
  meta.input("config", cli.config);
  PackConfig config = read_pack_config(root, cli.config, cli.summary);
  root.check_unknown_keys();
  apply_overrides(cli, config);
  std::vector<std::filesystem::path> files(cli.templates.begin(), cli.templates.end());
  const std::vector<BodyTemplate> templates = load_body_templates(files, config.request.templates);
  for (const std::filesystem::path& f : files)
    meta.input("templates", f);
  if (!cli.summary.empty())
    meta.input("summary", cli.summary);
  else if (!config.summary.empty())
    meta.input("summary", std::filesystem::path(cli.config).parent_path() / config.summary);

  const std::filesystem::path out(cli.out);
  if (out.has_parent_path()) ensure_output_folder(out.parent_path());
  const std::filesystem::path checkpoints = checkpoint_folder(out);
  std::optional<PackResume> resume;
  if (!given.resume.empty()) resume = resume_point(out, checkpoints);
  ResumableRun resumable("pack", out, checkpoints, config.checkpoints);
  resumable.start(!given.resume.empty(), pack_command(cli).invocation(command_line));
  const Provenance provenance{command_line, root.text(), config.request.seed};
  std::optional<ProgressReporter> progress;
  std::string phase;
  PackProgress hooks;
  hooks.update = [&](const std::string& name, double time, double max_time) {
    if (name != phase) {
      if (progress) progress->finish();
      phase = name;
      progress.emplace("pack " + name, max_time,
                       ProgressOptions{.quiet = context.quiet, .unit = "s simulated"});
    }
    progress->update(time);
  };
  hooks.after_step = [&](const Engine& engine, const PackPhaseState& state) {
    return resumable.after_step(engine.step_index(), [&] {
      write_checkpoint(checkpoints, engine, {}, provenance, pack_stage, phase_state(state));
    });
  };
  const PackRun result = pack(config.request, templates, hooks, std::move(resume));
  if (progress) progress->finish();
  if (result.interrupted) return resumable.stopped(result.steps);

  write_packing(out, result.packing, provenance);
  std::filesystem::path sidecar = out;
  sidecar.replace_extension(".xmf");
  meta.output(out.filename()).output(sidecar.filename());
  add_pack_facts(meta, result, config);
  meta.options(pack_command(cli).json());
  add_measures(meta, result.packing.measures);
  meta.fact("effective_config", pack_config_toml(config));
  meta.write(run_metadata_beside(out));
  resumable.finish();
  print_pack_summary(result, config);
  return 0;
}

}  // namespace

StageOptions pack_options() {
  return pack_config_options();
}

CommandOptions pack_command_options() {
  static PackCli defaults;
  return pack_command(defaults);
}

StageRunner setup_pack_cli(CLI::App& app) {
  auto cli = std::make_shared<PackCli>();
  pack_command(*cli).add_to(app, &cli->resume,
                            "continue the killed run that writes this packed.h5 from its last "
                            "checkpoint, with the arguments it was started with");
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::packing
