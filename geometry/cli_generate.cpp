#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <memory>

#include "common/atomic_file.hpp"
#include "common/csv.hpp"
#include "common/progress.hpp"
#include "common/run_metadata.hpp"
#include "geometry/cli.hpp"
#include "geometry/descriptors.hpp"
#include "geometry/generate.hpp"

namespace shapepress::geometry {
namespace {

struct GenerateCli {
  std::string targets;
  GenerateOptions options;
  std::string format = "stl";
  int directions = 64;
  double ks_tolerance = 0.1;
  std::string out;
};

// Quantile of a sorted sample at cumulative level p (the Hazen plotting position, as shape-stats).
double sample_quantile(const std::vector<double>& sorted, double p) {
  const double x = std::clamp(p * static_cast<double>(sorted.size()) - 0.5, 0.0,
                              static_cast<double>(sorted.size() - 1));
  const auto i = static_cast<std::size_t>(x);
  const std::size_t j = std::min(i + 1, sorted.size() - 1);
  return sorted[i] + (x - static_cast<double>(i)) * (sorted[j] - sorted[i]);
}

int run(const GenerateCli& cli, const RunContext& context) {
  const ShapeTargets targets = read_shape_targets(cli.targets);
  ProgressReporter progress("generate", cli.options.count,
                            {.quiet = context.quiet, .unit = "particles"});
  const std::vector<GeneratedParticle> particles = generate_population(
      targets, cli.options, [&](int done) { progress.update(static_cast<double>(done)); });
  progress.finish();
  const std::filesystem::path out(cli.out);
  ensure_output_folder(out);
  // The targets the run used, as TOML (`generate --targets effective.toml` reads them back).
  write_file_atomically(
      out / "effective.toml",
      fmt::format("# {}\n# the targets of this generate run\n", context.command_line) +
          shape_targets_toml(targets));
  CsvWriter csv(
      out / "shapes.csv",
      {"file", "seed", "redraws", "size_target_m", "elongation_target", "flatness_target",
       "volume_m3", "L_m", "I_m", "S_m", "asr", "elongation", "flatness", "sphericity", "convexity",
       "projected_equivalent_diameter_m", "projected_asr_mean", "roughness"});
  csv.comment(fmt::format("shapepress generate from '{}' ({} particles, seed {})", cli.targets,
                          particles.size(), cli.options.seed));
  std::vector<ShapeDescriptors> measured;
  std::vector<double> projected;
  double asr = 0.0, elongation = 0.0, flatness = 0.0, roughness = 0.0;
  const double n = static_cast<double>(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    measured.push_back(describe(particles[i].mesh, {cli.directions, cli.options.seed + 1000 + i}));
    const ShapeDescriptors& d = measured.back();
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
  RunMetadata meta("generate", context.command_line);
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
  app.add_option("--targets", cli->targets,
                 "shape statistics: shape-stats summary.json or a TOML with the same keys")
      ->required();
  app.add_option("--count", cli->options.count, "particles")->capture_default_str();
  app.add_option("--seed", cli->options.seed, "seed (same seed, same particles)")
      ->capture_default_str();
  app.add_option("--subdivisions", cli->options.subdivisions, "icosphere level (4: 2562 vertices)")
      ->capture_default_str();
  app.add_option("--max-degree", cli->options.max_degree, "highest spherical-harmonic degree")
      ->capture_default_str();
  app.add_option("--format", cli->format, "mesh format")
      ->check(CLI::IsMember({"stl", "off", "ply"}))
      ->capture_default_str();
  app.add_option("--directions", cli->directions, "views per particle for shapes.csv")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  app.add_option("--ks-tolerance", cli->ks_tolerance,
                 "KS distance of the projected ASR to the image distribution above which "
                 "generate warns (output and run.json)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--out", cli->out, "output folder (meshes, shapes.csv, effective.toml)")
      ->required();
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::geometry
