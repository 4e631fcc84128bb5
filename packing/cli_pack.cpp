#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "common/atomic_file.hpp"
#include "common/config.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "common/provenance.hpp"
#include "common/run_metadata.hpp"
#include "packing/cli.hpp"
#include "packing/pack_config.hpp"

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
};

// run.json names a length's fact with its unit, as the other stages do (bed_height_m).
void add_measures(RunMetadata& meta, const PackMeasures& m) {
  for_each_measure(m, [&](const char* name, std::string_view unit, double value) {
    meta.fact(unit == "m" ? std::string(name) + "_m" : std::string(name), value);
  });
}

int run(const PackCli& cli, const RunContext& context) {
  RunMetadata meta("pack", context.command_line);
  const ConfigTable root = ConfigTable::load_file(cli.config);
  meta.input("config", cli.config);
  PackConfig config = read_pack_config(root, cli.config, cli.summary);
  root.check_unknown_keys();
  if (cli.seed) config.request.seed = *cli.seed;
  // A study packs one config at several sizes and with several shapes without copying it.
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
  const PackRun result = pack(config.request, templates, hooks);
  if (progress) progress->finish();

  const Provenance provenance{context.command_line, root.text(), config.request.seed};
  write_packing(out, result.packing, provenance);
  std::filesystem::path sidecar = out;
  sidecar.replace_extension(".xmf");
  const PackMeasures& m = result.packing.measures;
  meta.output(out.filename()).output(sidecar.filename());
  meta.fact("bodies", static_cast<std::int64_t>(result.packing.size()))
      .fact("sub_spheres", static_cast<std::int64_t>(result.packing.particles.size()))
      .fact("bonds", static_cast<std::int64_t>(result.packing.bonds.size()))
      .fact("box_x_m", result.packing.box.length_x)
      .fact("box_y_m", result.packing.box.length_y)
      .fact("floor_m", result.packing.floor)
      .fact("top_m", result.packing.top)
      .fact("seed", static_cast<std::int64_t>(config.request.seed))
      .fact("time_step_s", result.time_step)
      .fact("steps", result.steps)
      .fact("loop_s", result.loop_seconds)
      .fact("settled", result.settled)
      .fact("settled_solid_fraction", result.settled_solid_fraction)
      .fact("precompression_solid_fraction", result.precompression_solid_fraction);
  add_measures(meta, m);
  meta.fact("effective_config", pack_config_toml(config));
  meta.write(run_metadata_beside(out));
  std::printf(
      "pack: %zu bodies, %zu sub-spheres, %zu bonds; bed height %.4g m\n"
      "  solid fraction %.4f by shape volume, %.4f by sub-sphere volume\n"
      "  coordination %.3f; orientation order <P2> %.4f; largest overlap %.3g m (%.3g of a "
      "radius)\n"
      "  x10/x50/x90 %.4g/%.4g/%.4g m (target %.4g/%.4g/%.4g, %s-weighted)\n"
      "  %lld steps of %.3g s in %.1f s%s\n",
      result.packing.size(), result.packing.particles.size(), result.packing.bonds.size(),
      m.bed_height, m.solid_fraction_shape, m.solid_fraction_spheres, m.coordination,
      m.orientation_order, m.largest_overlap, m.largest_overlap_relative, m.x10, m.x50, m.x90,
      m.target_x10, m.target_x50, m.target_x90,
      config.request.sizes.volume_weighted ? "volume" : "number",
      static_cast<long long>(result.steps), result.time_step, result.loop_seconds,
      result.settled ? "" : " (not at rest: see the warning)");
  return 0;
}

}  // namespace

StageOptions pack_options() {
  return pack_config_options();
}

StageRunner setup_pack_cli(CLI::App& app) {
  auto cli = std::make_shared<PackCli>();
  app.add_option("templates", cli->templates,
                 "templates files of fill (their /bms and /cms groups); none for spheres only");
  app.add_option("--config", cli->config, "pack config TOML ([pack], [[template]], [sizes], ...)")
      ->required();
  app.add_option("--out", cli->out, "packed.h5 (packed.xmf and packed.h5.run.json beside it)")
      ->required();
  app.add_option("--seed", cli->seed, "random seed (overrides pack.seed)");
  app.add_option("--summary", cli->summary,
                 "sizes from this shape-stats summary.json (its Q3 x10/x50/x90) instead of the "
                 "config's [sizes] summary or size_quantiles");
  app.add_option("--count", cli->count, "number of bodies (overrides pack.count and target_mass)");
  app.add_option("--template", cli->template_names,
                 "a template to pack, \"bms/<name>\", \"cms/<name>\" or \"sphere\"; repeated: "
                 "equal weights (replaces the config's [[template]] blocks)");
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::packing
