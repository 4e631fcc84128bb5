#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>

#include "common/atomic_file.hpp"
#include "common/command_options.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "common/resume.hpp"
#include "common/run_metadata.hpp"
#include "geometry/cli.hpp"
#include "geometry/descriptors.hpp"
#include "geometry/generate.hpp"
#include "geometry/generate_checkpoint.hpp"

namespace shapepress::geometry {
namespace {

struct GenerateCli {
  std::string targets;
  GenerateOptions options;
  std::string format = "stl";
  int directions = 64;
  double ks_tolerance = 0.1;
  std::string out;
  CheckpointPolicy checkpoints;  // --checkpoint-every (particle steps), --checkpoint-minutes
  std::string resume;
};

// The checkpoints of `generate --out shapes` go to shapes/checkpoints/, removed when the run ends
// whole.
std::filesystem::path checkpoint_folder(const std::filesystem::path& out) {
  return out / "checkpoints";
}

// generate's options, bound once: parsed, recorded for --resume, written into run.json and
// documented (docs/stages.md).
CommandOptions generate_command(GenerateCli& cli) {
  CommandOptions options("generate");
  options
      .text("--targets", &cli.targets,
            "shape statistics: shape-stats summary.json or a TOML with the same keys")
      .config()
      .whole("--count", &cli.options.count, "particles")
      .range(Range::closed(1, 1000000))
      .show_default()
      .whole("--seed", &cli.options.seed, "seed (same seed, same particles)")
      .show_default()
      .whole("--subdivisions", &cli.options.subdivisions, "icosphere level (4: 2562 vertices)")
      .range(Range::closed(1, 7))
      .show_default()
      .whole("--max-degree", &cli.options.max_degree, "highest spherical-harmonic degree")
      .range(Range::closed(3, 40))
      .show_default()
      .text("--format", &cli.format, "mesh format")
      .choices({"stl", "off", "ply"})
      .show_default()
      .whole("--directions", &cli.directions, "views per particle for shapes.csv")
      .range(Range::closed(1, 10000))
      .show_default()
      .number("--ks-tolerance", &cli.ks_tolerance,
              "KS distance of the projected ASR to the image distribution above which generate "
              "warns (output and run.json)")
      .range(Range::closed(0.0, 1.0))
      .show_default()
      .whole("--checkpoint-every", &cli.checkpoints.every_steps,
             "particle steps between checkpoints for --resume (a step: one particle drawn, "
             "shaped or described; 0: by wall time only)")
      .range(Range::closed(0, static_cast<double>(std::int64_t{1} << 40)))
      .show_default()
      .number("--checkpoint-minutes", &cli.checkpoints.minutes,
              "minutes of wall time between checkpoints for --resume (0: by steps only)")
      .range(Range::closed(0.0, 1e6))
      .show_default()
      .text("--out", &cli.out, "output folder (meshes, shapes.csv, effective.toml)")
      .output();
  return options;
}

// Quantile of a sorted sample at cumulative level p (the Hazen plotting position, as shape-stats).
double sample_quantile(const std::vector<double>& sorted, double p) {
  const double x = std::clamp(p * static_cast<double>(sorted.size()) - 0.5, 0.0,
                              static_cast<double>(sorted.size() - 1));
  const auto i = static_cast<std::size_t>(x);
  const std::size_t j = std::min(i + 1, sorted.size() - 1);
  return sorted[i] + (x - static_cast<double>(i)) * (sorted[j] - sorted[i]);
}

// The particles and their descriptors, from the checkpoints of a resumed run on; nothing when a
// signal stopped the run (after its checkpoint).
struct Generated {
  std::vector<GeneratedParticle> particles;
  std::vector<ShapeDescriptors> measured;
};

std::optional<Generated> generate_resumably(const GenerateCli& cli, const ShapeTargets& targets,
                                            ResumableRun& resumable, bool resumed,
                                            const RunInvocation& start, bool quiet) {
  const std::filesystem::path out(cli.out), checkpoints = resumable.folder();
  const auto count = static_cast<std::size_t>(cli.options.count);
  GenerateWork work;
  std::int64_t step = 0;
  if (resumed) {
    remove_stale_temporaries(out);
    work = read_generate_checkpoints(checkpoints, count, step);
    if (step > 0)
      spdlog::info(
          "generate: resuming {} from the checkpoint at step {} ({} of {} particles drawn, {} "
          "described)",
          out.string(), step, work.draws.size(), count, work.descriptors.size());
    else
      spdlog::info("generate: {} has no checkpoint yet: starting the run again", out.string());
  }
  ensure_output_folder(out);
  resumable.start(resumed, start);
  // A step is one particle through one phase: drawn, shaped (a pass of the projected-ASR fit or
  // a box stretch), described; a second pass of the fit runs past the total shown.
  const double steps = 3.0 * static_cast<double>(count);
  ProgressReporter progress("generate", steps, {.quiet = quiet, .unit = "particle steps"});
  GenerateCheckpoints writer(checkpoints, work);
  GenerateHooks hooks;
  hooks.block_steps = cli.checkpoints.every_steps;
  hooks.after_block = [&](const GenerateWork& w) {
    progress.update(std::min(steps, static_cast<double>(w.steps())));
    return resumable.after_step(w.steps(), [&] { writer.write(w); });
  };
  std::optional<Generated> generated;
  try {
    auto particles = generate_population(targets, cli.options, work, hooks);
    if (!particles) return std::nullopt;
    auto measured = describe_population(*particles, cli.directions, cli.options.seed, work, hooks);
    if (!measured) return std::nullopt;
    generated = Generated{std::move(*particles), std::move(*measured)};
  } catch (const InputError& e) {
    if (!resumed) throw;
    throw InputError(fmt::format("{}: {}", checkpoints.string(), e.what()));
  }
  progress.finish();
  return generated;
}

// The population's means and every projected ASR (the views of all particles), for the summary
// and the KS distance to the image distribution.
struct PopulationMeans {
  std::vector<double> projected;
  double asr = 0.0, elongation = 0.0, flatness = 0.0, roughness = 0.0;
};

PopulationMeans population_means(const Generated& generated) {
  PopulationMeans m;
  const double n = static_cast<double>(generated.particles.size());
  for (std::size_t i = 0; i < generated.particles.size(); ++i) {
    const ShapeDescriptors& d = generated.measured[i];
    m.projected.insert(m.projected.end(), d.projected_asr.begin(), d.projected_asr.end());
    m.asr += d.asr / n;
    m.elongation += d.elongation / n;
    m.flatness += d.flatness / n;
    m.roughness += generated.particles[i].roughness / n;
  }
  return m;
}

// How the population meets its targets: a line of means, the KS distance of the projected ASR
// to the image distribution when the targets hold one, and a warning when it exceeds the
// tolerance.
struct TargetFit {
  std::string summary;
  std::vector<std::string> warnings;
  double ks = 0.0;
};

TargetFit target_fit(const PopulationMeans& means, const ShapeTargets& targets,
                     double ks_tolerance) {
  TargetFit fit;
  fit.summary = fmt::format("means: ASR {:.4f}, elongation {:.4f}, flatness {:.4f}", means.asr,
                            means.elongation, means.flatness);
  if (targets.projected_distribution()) {
    fit.ks = ks_distance(means.projected, targets);
    fit.summary +=
        fmt::format("; KS distance of projected ASR to the image distribution {:.4f}", fit.ks);
    if (fit.ks > ks_tolerance)
      fit.warnings.push_back(fmt::format(
          "the projected ASR misses the image distribution: KS distance {:.4f} > {:.4f} "
          "(--ks-tolerance); compare projected_asr_quantiles with the targets in run.json",
          fit.ks, ks_tolerance));
  } else {
    fit.summary += fmt::format(" (targets {:.4f}, {:.4f}, {:.4f})",
                               targets.target_elongation() * targets.target_flatness(),
                               targets.target_elongation(), targets.target_flatness());
  }
  return fit;
}

std::string mesh_file(std::size_t i, const std::string& format) {
  return fmt::format("particle_{:04d}.{}", i, format);
}

// Every particle's mesh, and shapes.csv: its targets and measured descriptors, one row each.
void write_shapes(const std::filesystem::path& out, const GenerateCli& cli,
                  const Generated& generated, const TargetFit& fit) {
  CsvWriter csv(
      out / "shapes.csv",
      {"file", "seed", "redraws", "size_target_m", "elongation_target", "flatness_target",
       "volume_m3", "L_m", "I_m", "S_m", "asr", "elongation", "flatness", "sphericity", "convexity",
       "projected_equivalent_diameter_m", "projected_asr_mean", "roughness"});
  csv.comment(fmt::format("shapepress generate from '{}' ({} particles, seed {})", cli.targets,
                          generated.particles.size(), cli.options.seed));
  csv.comment(fit.summary);
  for (const std::string& warning : fit.warnings)
    csv.comment("warning: " + warning);
  for (std::size_t i = 0; i < generated.particles.size(); ++i) {
    const GeneratedParticle& p = generated.particles[i];
    const ShapeDescriptors& d = generated.measured[i];
    const std::string file = mesh_file(i, cli.format);
    write_mesh(p.mesh, out / file);
    std::vector<std::string> cells = {file, std::to_string(p.seed), std::to_string(p.redraws)};
    for (double v : {p.size_m, p.elongation_target, p.flatness_target, d.volume_m3, d.L_m, d.I_m,
                     d.S_m, d.asr, d.elongation, d.flatness, d.sphericity, d.convexity,
                     d.projected_equivalent_diameter_m, d.projected_asr_mean, p.roughness})
      cells.push_back(format_number(v));
    csv.row_text(cells);
  }
  csv.commit();
}

// run.json's facts: the run's settings, the means, and the projected ASR's quantiles beside the
// targets' when they hold a distribution.
void add_generate_facts(RunMetadata& meta, const GenerateCli& cli, const ShapeTargets& targets,
                        std::size_t particles, PopulationMeans means, const TargetFit& fit) {
  meta.fact("particles", particles)
      .fact("seed", cli.options.seed)
      .fact("subdivisions", cli.options.subdivisions)
      .fact("max_degree", cli.options.max_degree)
      .fact("format", cli.format)
      .fact("directions", cli.directions)
      .fact("mean_asr", means.asr)
      .fact("mean_elongation", means.elongation)
      .fact("mean_flatness", means.flatness)
      .fact("mean_roughness", means.roughness);
  if (targets.projected_distribution()) {
    std::sort(means.projected.begin(), means.projected.end());
    std::vector<double> quantiles;
    for (double level : targets.asr_levels)
      quantiles.push_back(sample_quantile(means.projected, level));
    meta.fact("projected_asr_ks", fit.ks)
        .fact("projected_asr_ks_tolerance", cli.ks_tolerance)
        .fact("projected_asr_levels", targets.asr_levels)
        .fact("projected_asr_quantiles", quantiles)
        .fact("projected_asr_target_quantiles", targets.asr_quantiles);
  }
  meta.fact("warnings", fit.warnings);
}

int run(const GenerateCli& given, const RunContext& context) {
  std::string command_line = context.command_line;
  const std::filesystem::path resumed(given.resume);
  if (finished_before_resume("generate", given.resume, checkpoint_folder(resumed),
                             resumed / std::string(run_metadata_name)))
    return 0;
  GenerateCli cli = given;
  if (!given.resume.empty())
    command_line = generate_command(cli).resume(
        checkpoint_folder(std::filesystem::absolute(given.resume)) / "resume.json", given.resume);
  if (cli.targets.empty()) throw InputError("generate: give --targets FILE (or --resume OUT)");
  if (cli.out.empty()) throw InputError("generate: give --out FOLDER (or --resume OUT)");
  const ShapeTargets targets = read_shape_targets(cli.targets);
  // Before any folder is made: bad input leaves no file.
  targets.check();
  cli.options.check();
  const std::filesystem::path out(cli.out);
  ResumableRun resumable("generate", out, checkpoint_folder(out), cli.checkpoints);
  const std::optional<Generated> generated =
      generate_resumably(cli, targets, resumable, !given.resume.empty(),
                         generate_command(cli).invocation(command_line), context.quiet);
  if (!generated) return resumable.stopped();
  // The targets the run used, as TOML (`generate --targets effective.toml` reads them back).
  write_file_atomically(out / "effective.toml",
                        fmt::format("# {}\n# the targets of this generate run\n", command_line) +
                            shape_targets_toml(targets));
  PopulationMeans means = population_means(*generated);
  const TargetFit fit = target_fit(means, targets, cli.ks_tolerance);
  write_shapes(out, cli, *generated, fit);
  const std::size_t particles = generated->particles.size();
  RunMetadata meta("generate", command_line);
  meta.options(generate_command(cli).json());
  meta.input("targets", cli.targets).output("shapes.csv");
  for (std::size_t i = 0; i < particles; ++i)
    meta.output(mesh_file(i, cli.format));
  add_generate_facts(meta, cli, targets, particles, std::move(means), fit);
  meta.write(out / run_metadata_name);
  resumable.finish();
  spdlog::info("generate: {} particles in {}; {}", particles, out.string(), fit.summary);
  for (const std::string& warning : fit.warnings)
    spdlog::warn("generate: {}", warning);
  return 0;
}

}  // namespace

StageOptions generate_options() {
  return shape_targets_options();
}

CommandOptions generate_command_options() {
  static GenerateCli defaults;
  return generate_command(defaults);
}

StageRunner setup_generate_cli(CLI::App& app) {
  auto cli = std::make_shared<GenerateCli>();
  generate_command(*cli).add_to(app, &cli->resume,
                                "continue the killed run that writes this folder from its last "
                                "checkpoint, with the arguments it was started with");
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::geometry
