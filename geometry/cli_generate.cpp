#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "common/resume.hpp"
#include "common/run_metadata.hpp"
#include "common/sha256.hpp"
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

// What --resume needs to run the same generate again: every option, as text (doubles exact).
RunInvocation invocation_of(const GenerateCli& cli, const std::string& command_line) {
  RunInvocation invocation{
      command_line, std::filesystem::current_path(), cli.targets, sha256_file(cli.targets), {}};
  const GenerateOptions& o = cli.options;
  for (const auto& [name, value] :
       {std::pair<const char*, std::string>{"count", std::to_string(o.count)},
        {"seed", std::to_string(o.seed)},
        {"subdivisions", std::to_string(o.subdivisions)},
        {"max-degree", std::to_string(o.max_degree)},
        {"format", cli.format},
        {"directions", std::to_string(cli.directions)},
        {"ks-tolerance", exact_text(cli.ks_tolerance)},
        {"checkpoint-every", std::to_string(cli.checkpoints.every_steps)},
        {"checkpoint-minutes", exact_text(cli.checkpoints.minutes)}})
    invocation.arguments[name] = {value};
  return invocation;
}

// --resume OUT: the arguments the run was started with, from the working directory it was
// started in (a relative --targets means what it meant then).
GenerateCli resumed_arguments(const std::string& given, std::string& command_line) {
  const std::filesystem::path out = std::filesystem::absolute(given);
  const std::filesystem::path record = checkpoint_folder(out) / "resume.json";
  const RunInvocation invocation = resume_invocation(record, given);
  command_line = invocation.command_line;
  const auto argument = [&](const char* name) {
    const auto it = invocation.arguments.find(name);
    if (it == invocation.arguments.end() || it->second.size() != 1)
      throw InputError(
          fmt::format("{}: no argument '{}' (a damaged resume record)", record.string(), name));
    return it->second.front();
  };
  const auto number = [&](const char* name) { return parse_exact(argument(name), record); };
  const auto refuse = [&](const char* name, const std::string& text) {
    return InputError(fmt::format("{}: argument '{}' is '{}' (a damaged resume record)",
                                  record.string(), name, text));
  };
  const auto whole = [&](const char* name, std::uint64_t most) {
    const std::string text = argument(name);
    if (text.empty() || text.size() > 20 || text.find_first_not_of("0123456789") != text.npos)
      throw refuse(name, text);
    try {
      if (const std::uint64_t value = std::stoull(text); value <= most) return value;
    } catch (const std::out_of_range&) {
    }
    throw refuse(name, text);
  };
  constexpr std::uint64_t int_most = std::numeric_limits<int>::max();
  GenerateCli cli;
  cli.targets = invocation.config;
  cli.out = out.string();
  cli.options.count = static_cast<int>(whole("count", int_most));
  cli.options.seed = whole("seed", std::numeric_limits<std::uint64_t>::max());
  cli.options.subdivisions = static_cast<int>(whole("subdivisions", int_most));
  cli.options.max_degree = static_cast<int>(whole("max-degree", int_most));
  cli.format = argument("format");
  cli.directions = static_cast<int>(whole("directions", int_most));
  cli.ks_tolerance = number("ks-tolerance");
  cli.checkpoints.every_steps = static_cast<std::int64_t>(whole("checkpoint-every", 1ULL << 40));
  cli.checkpoints.minutes = number("checkpoint-minutes");
  if (cli.format != "stl" && cli.format != "off" && cli.format != "ply")
    throw refuse("format", cli.format);
  if (!(cli.ks_tolerance >= 0.0 && cli.ks_tolerance <= 1.0))
    throw refuse("ks-tolerance", argument("ks-tolerance"));
  if (!(cli.checkpoints.minutes >= 0.0))
    throw refuse("checkpoint-minutes", argument("checkpoint-minutes"));
  return cli;
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
                                            bool resumed, const std::string& command_line,
                                            bool quiet) {
  const std::filesystem::path out(cli.out), checkpoints = checkpoint_folder(out);
  const auto count = static_cast<std::size_t>(cli.options.count);
  GenerateWork work;
  std::int64_t step = 0;
  if (resumed) {
    remove_stale_temporaries(out);
    remove_stale_temporaries(checkpoints);
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
  if (step == 0) {
    // A fresh start must not be resumed from another run's checkpoints.
    std::filesystem::remove_all(checkpoints);
    ensure_output_folder(checkpoints);
    write_invocation(checkpoints / "resume.json", invocation_of(cli, command_line));
  }
  const CheckpointFolderGuard checkpoints_guard(checkpoints);
  // A step is one particle through one phase: drawn, shaped (a pass of the projected-ASR fit or
  // a box stretch), described; a second pass of the fit runs past the total shown.
  const double steps = 3.0 * static_cast<double>(count);
  ProgressReporter progress("generate", steps, {.quiet = quiet, .unit = "particle steps"});
  GenerateCheckpoints writer(checkpoints, work);
  CheckpointClock clock(cli.checkpoints);
  GenerateHooks hooks;
  hooks.block_steps = cli.checkpoints.every_steps;
  hooks.after_block = [&](const GenerateWork& w) {
    progress.update(std::min(steps, static_cast<double>(w.steps())));
    if (clock.due(w.steps())) {
      writer.write(w);
      clock.taken();
    }
    return SignalCheckpoints::received() == 0;
  };
  const SignalCheckpoints signals;
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

int run(const GenerateCli& given, const RunContext& context) {
  std::string command_line = context.command_line;
  const std::filesystem::path resumed(given.resume);
  if (finished_before_resume("generate", given.resume, checkpoint_folder(resumed) / "resume.json",
                             resumed / std::string(run_metadata_name))) {
    // What a kill during the final removal left (resume.json went first or in between).
    std::error_code ignored;
    std::filesystem::remove_all(checkpoint_folder(resumed), ignored);
    return 0;
  }
  const GenerateCli cli =
      given.resume.empty() ? given : resumed_arguments(given.resume, command_line);
  if (cli.targets.empty()) throw InputError("generate: give --targets FILE (or --resume OUT)");
  if (cli.out.empty()) throw InputError("generate: give --out FOLDER (or --resume OUT)");
  const ShapeTargets targets = read_shape_targets(cli.targets);
  // Before any folder is made: bad input leaves no file.
  targets.check();
  cli.options.check();
  const std::optional<Generated> generated =
      generate_resumably(cli, targets, !given.resume.empty(), command_line, context.quiet);
  const std::filesystem::path out(cli.out);
  if (!generated) {
    spdlog::warn(
        "generate: stopped by signal {}; checkpoint written: continue with `shapepress generate "
        "--resume {}`",
        SignalCheckpoints::received(), out.string());
    return 128 + SignalCheckpoints::received();
  }
  const std::vector<GeneratedParticle>& particles = generated->particles;
  const std::vector<ShapeDescriptors>& measured = generated->measured;
  // The targets the run used, as TOML (`generate --targets effective.toml` reads them back).
  write_file_atomically(out / "effective.toml",
                        fmt::format("# {}\n# the targets of this generate run\n", command_line) +
                            shape_targets_toml(targets));
  CsvWriter csv(
      out / "shapes.csv",
      {"file", "seed", "redraws", "size_target_m", "elongation_target", "flatness_target",
       "volume_m3", "L_m", "I_m", "S_m", "asr", "elongation", "flatness", "sphericity", "convexity",
       "projected_equivalent_diameter_m", "projected_asr_mean", "roughness"});
  csv.comment(fmt::format("shapepress generate from '{}' ({} particles, seed {})", cli.targets,
                          particles.size(), cli.options.seed));
  std::vector<double> projected;
  double asr = 0.0, elongation = 0.0, flatness = 0.0, roughness = 0.0;
  const double n = static_cast<double>(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const ShapeDescriptors& d = measured[i];
    projected.insert(projected.end(), d.projected_asr.begin(), d.projected_asr.end());
    asr += d.asr / n;
    elongation += d.elongation / n;
    flatness += d.flatness / n;
    roughness += particles[i].roughness / n;
  }
  std::string summary = fmt::format("means: ASR {:.4f}, elongation {:.4f}, flatness {:.4f}", asr,
                                    elongation, flatness);
  std::vector<std::string> warnings;
  double ks = 0.0;
  if (targets.projected_distribution()) {
    ks = ks_distance(projected, targets);
    summary += fmt::format("; KS distance of projected ASR to the image distribution {:.4f}", ks);
    if (ks > cli.ks_tolerance)
      warnings.push_back(fmt::format(
          "the projected ASR misses the image distribution: KS distance {:.4f} > {:.4f} "
          "(--ks-tolerance); compare projected_asr_quantiles with the targets in run.json",
          ks, cli.ks_tolerance));
  } else {
    summary += fmt::format(" (targets {:.4f}, {:.4f}, {:.4f})",
                           targets.target_elongation() * targets.target_flatness(),
                           targets.target_elongation(), targets.target_flatness());
  }
  csv.comment(summary);
  for (const std::string& warning : warnings)
    csv.comment("warning: " + warning);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const GeneratedParticle& p = particles[i];
    const ShapeDescriptors& d = measured[i];
    const std::string file = fmt::format("particle_{:04d}.{}", i, cli.format);
    write_mesh(p.mesh, out / file);
    std::vector<std::string> cells = {file, std::to_string(p.seed), std::to_string(p.redraws)};
    for (double v : {p.size_m, p.elongation_target, p.flatness_target, d.volume_m3, d.L_m, d.I_m,
                     d.S_m, d.asr, d.elongation, d.flatness, d.sphericity, d.convexity,
                     d.projected_equivalent_diameter_m, d.projected_asr_mean, p.roughness})
      cells.push_back(format_number(v));
    csv.row_text(cells);
  }
  csv.commit();
  RunMetadata meta("generate", command_line);
  meta.input("targets", cli.targets).output("shapes.csv");
  for (std::size_t i = 0; i < particles.size(); ++i)
    meta.output(fmt::format("particle_{:04d}.{}", i, cli.format));
  meta.fact("particles", particles.size())
      .fact("seed", cli.options.seed)
      .fact("subdivisions", cli.options.subdivisions)
      .fact("max_degree", cli.options.max_degree)
      .fact("format", cli.format)
      .fact("directions", cli.directions)
      .fact("mean_asr", asr)
      .fact("mean_elongation", elongation)
      .fact("mean_flatness", flatness)
      .fact("mean_roughness", roughness);
  if (targets.projected_distribution()) {
    std::sort(projected.begin(), projected.end());
    std::vector<double> quantiles;
    for (double level : targets.asr_levels)
      quantiles.push_back(sample_quantile(projected, level));
    meta.fact("projected_asr_ks", ks)
        .fact("projected_asr_ks_tolerance", cli.ks_tolerance)
        .fact("projected_asr_levels", targets.asr_levels)
        .fact("projected_asr_quantiles", quantiles)
        .fact("projected_asr_target_quantiles", targets.asr_quantiles);
  }
  meta.fact("warnings", warnings).write(out / run_metadata_name);
  // The run is whole: its checkpoints have done their work.
  std::error_code ignored;
  std::filesystem::remove_all(checkpoint_folder(out), ignored);
  spdlog::info("generate: {} particles in {}; {}", particles.size(), out.string(), summary);
  for (const std::string& warning : warnings)
    spdlog::warn("generate: {}", warning);
  return 0;
}

}  // namespace

StageOptions generate_options() {
  return shape_targets_options();
}

StageRunner setup_generate_cli(CLI::App& app) {
  auto cli = std::make_shared<GenerateCli>();
  std::vector<CLI::Option*> run_options = {
      app.add_option("--targets", cli->targets,
                     "shape statistics: shape-stats summary.json or a TOML with the same keys"),
      app.add_option("--count", cli->options.count, "particles")->capture_default_str(),
      app.add_option("--seed", cli->options.seed, "seed (same seed, same particles)")
          ->capture_default_str(),
      app.add_option("--subdivisions", cli->options.subdivisions,
                     "icosphere level (4: 2562 vertices)")
          ->capture_default_str(),
      app.add_option("--max-degree", cli->options.max_degree, "highest spherical-harmonic degree")
          ->capture_default_str(),
      app.add_option("--format", cli->format, "mesh format")
          ->check(CLI::IsMember({"stl", "off", "ply"}))
          ->capture_default_str(),
      app.add_option("--directions", cli->directions, "views per particle for shapes.csv")
          ->check(CLI::Range(1, 10000))
          ->capture_default_str(),
      app.add_option("--ks-tolerance", cli->ks_tolerance,
                     "KS distance of the projected ASR to the image distribution above which "
                     "generate warns (output and run.json)")
          ->check(CLI::Range(0.0, 1.0))
          ->capture_default_str(),
      app.add_option("--checkpoint-every", cli->checkpoints.every_steps,
                     "particle steps between checkpoints for --resume (a step: one particle "
                     "drawn, shaped or described; 0: by wall time only)")
          ->check(CLI::Range(std::int64_t{0}, std::int64_t{1} << 40))
          ->capture_default_str(),
      app.add_option("--checkpoint-minutes", cli->checkpoints.minutes,
                     "minutes of wall time between checkpoints for --resume (0: by steps only)")
          ->check(CLI::Range(0.0, 1e6))
          ->capture_default_str(),
      app.add_option("--out", cli->out, "output folder (meshes, shapes.csv, effective.toml)")};
  auto* resume = app.add_option(
      "--resume", cli->resume,
      "continue the killed run that writes this folder from its last checkpoint, with the "
      "arguments it was started with");
  for (CLI::Option* option : run_options)
    resume->excludes(option);
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::geometry
