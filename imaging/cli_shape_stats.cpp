#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <map>
#include <memory>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "common/run_metadata.hpp"
#include "common/units.hpp"
#include "imaging/cli.hpp"
#include "imaging/outputs.hpp"
#include "imaging/shape_stats.hpp"

namespace shapepress::imaging {
namespace {

struct ShapeStatsCli {
  std::vector<std::string> images;
  std::string out;
  std::string pixel_size;
  int crop_bottom = -1;
  std::string denoise = "gaussian";
  std::string background = "quadratic";
  std::string threshold = "otsu";
  std::string polarity = "auto";
  bool keep_edges = false;
  bool no_split = false;
  std::string split;  // empty: the default (or the preset's)
  std::string split_gaps = "unsmoothed";
  bool imagej = false;
  bool keep_holes = false;
  bool no_overlays = false;
  SegmentOptions segment;
  double min_fourier_diameter_px = 20.0;
};

template <typename Enum>
void bind_choice(CLI::App& app, const std::string& name, std::string& target,
                 const std::map<std::string, Enum>& choices, const std::string& help) {
  std::vector<std::string> names;
  for (const auto& [key, value] : choices)
    names.push_back(key);
  app.add_option(name, target, help)->check(CLI::IsMember(names))->capture_default_str();
}

const std::map<std::string, Denoise> denoise_choices = {
    {"none", Denoise::none}, {"gaussian", Denoise::gaussian}, {"median", Denoise::median}};
const std::map<std::string, Background> background_choices = {{"none", Background::none},
                                                              {"quadratic", Background::quadratic},
                                                              {"rolling", Background::rolling}};
const std::map<std::string, ThresholdMethod> threshold_choices = {
    {"otsu", ThresholdMethod::otsu},
    {"triangle", ThresholdMethod::triangle},
    {"fixed", ThresholdMethod::fixed},
    {"adaptive", ThresholdMethod::adaptive},
    {"isodata", ThresholdMethod::isodata}};
const std::map<std::string, Polarity> polarity_choices = {
    {"auto", Polarity::automatic}, {"bright", Polarity::bright}, {"dark", Polarity::dark}};

// --imagej: ImageJ's Analyze Particles as a user runs it (Default threshold, no smoothing or
// background, 8-connected, include holes, exclude on edges, no watershed unless --split imagej);
// options given explicitly still win over the preset.
void apply_imagej_preset(ShapeStatsCli& cli, const CLI::App& app) {
  auto given = [&](const char* name) { return app.count(name) > 0; };
  if (!given("--denoise")) cli.denoise = "none";
  if (!given("--background")) cli.background = "none";
  if (!given("--threshold")) cli.threshold = "isodata";
  if (!given("--split") && !given("--no-split")) cli.split = "none";
  if (!given("--split-fragment")) cli.segment.split_fragment_fraction = 0.0;
}

const std::map<std::string, std::string> split_choices = {
    {"none", "keep touching particles together"},
    {"neck", "split at narrow necks (distance map, neck width against the smaller radius)"},
    {"prominence", "distance-map maxima standing out by --split-prominence, 1 px lines"},
    {"imagej", "ImageJ's Watershed itself, on the mask before its holes are filled"}};

int run(const ShapeStatsCli& cli, const RunContext& context) {
  ShapeStatsOptions options;
  options.segment = cli.segment;
  options.segment.denoise = denoise_choices.at(cli.denoise);
  options.segment.background = background_choices.at(cli.background);
  options.segment.threshold = threshold_choices.at(cli.threshold);
  options.segment.polarity = polarity_choices.at(cli.polarity);
  options.segment.exclude_edges = !cli.keep_edges;
  const std::string split = cli.no_split ? "none" : cli.split.empty() ? "prominence" : cli.split;
  options.segment.split_touching = split != "none";
  options.segment.split_rule = split == "neck" ? SplitRule::neck : SplitRule::prominence;
  options.segment.split_lines = split != "neck";
  options.segment.fill_holes_after_split = split == "imagej";
  options.segment.split_gaps_unsmoothed = cli.split_gaps == "unsmoothed";
  options.segment.fill_holes = !cli.keep_holes;
  options.segment.check();
  if (!cli.pixel_size.empty())
    options.pixel_size_m = parse_quantity(cli.pixel_size, dim::length, "--pixel-size");
  if (options.pixel_size_m && !(*options.pixel_size_m > 0))
    throw InputError(fmt::format("--pixel-size: '{}' must be positive", cli.pixel_size));
  if (cli.crop_bottom >= 0) options.crop_bottom = cli.crop_bottom;
  options.min_fourier_diameter_px = cli.min_fourier_diameter_px;

  std::vector<std::filesystem::path> paths(cli.images.begin(), cli.images.end());
  ProgressReporter progress("shape-stats", static_cast<double>(paths.size()),
                            {.quiet = context.quiet, .unit = "images"});
  BatchResult batch =
      process_batch(paths, options, context.threads, [&](int done) { progress.update(done); });
  progress.finish();
  for (const SkippedImage& s : batch.skipped)
    spdlog::error("skipped {}", s.reason);
  if (batch.images.empty())
    throw InputError(fmt::format("no image could be processed ({} skipped: {})",
                                 batch.skipped.size(), batch.skipped.front().reason));

  const std::filesystem::path out(cli.out);
  ensure_output_folder(out);
  ShapeSummary summary = summarize(particle_samples(batch.images), options.min_fourier_diameter_px);
  std::vector<ImageReport> reports;
  for (const ImageResult& image : batch.images)
    reports.push_back(image.report);
  std::vector<std::string> skipped;
  for (const SkippedImage& s : batch.skipped)
    skipped.push_back(s.reason);
  write_particles_csv(out / "particles.csv", batch.images);
  write_file_atomically(out / "summary.json",
                        summary_to_json(summary, reports, skipped, context.command_line));
  if (!cli.no_overlays) {
    ensure_output_folder(out / "overlays");
    for (const ImageResult& image : batch.images)
      write_overlay_png(
          out / "overlays" /
              (std::filesystem::path(image.report.file).stem().string() + "_overlay.png"),
          image);
    ensure_output_folder(out / "plots");
    write_plots(out / "plots", summary);
  }
  RunMetadata meta("shape-stats", context.command_line);
  for (const ImageResult& image : batch.images)
    meta.input("image", image.report.file);
  meta.output("particles.csv").output("summary.json");
  meta.fact("images", batch.images.size())
      .fact("skipped_images", batch.skipped.size())
      .fact("particles", summary.particle_count)
      .fact("x50_volume_m", summary.size.volume.x50)
      .fact("asr_s50", summary.asr.s50)
      .fact("fourier_D2", summary.fourier.D2)
      .fact("denoise", cli.denoise)
      .fact("background", cli.background)
      .fact("threshold", cli.threshold)
      .fact("polarity", cli.polarity)
      .fact("split_touching", !cli.no_split)
      .fact("exclude_edges", !cli.keep_edges)
      .fact("min_fourier_diameter_px", cli.min_fourier_diameter_px);
  if (options.pixel_size_m) meta.fact("pixel_size_m", *options.pixel_size_m);
  meta.write(out / run_metadata_name);
  spdlog::info("{} particles in {} images: x50 (Q3) {:.4g} um, ASR S50 {:.3f}, D2 {:.3f}",
               summary.particle_count, batch.images.size(), summary.size.volume.x50 * 1e6,
               summary.asr.s50, summary.fourier.D2);
  if (!batch.skipped.empty()) {
    spdlog::error("{} of {} images skipped (see above); results cover the others",
                  batch.skipped.size(), paths.size());
    return static_cast<int>(ExitCode::bad_input);
  }
  return 0;
}

}  // namespace

StageRunner setup_shape_stats_cli(CLI::App& app) {
  auto cli = std::make_shared<ShapeStatsCli>();
  app.add_option("images", cli->images, "image files (TIFF, PNG, JPEG, BMP, PGM, GIF)")->required();
  app.add_option("--out", cli->out, "output folder")->required();
  app.add_option("--pixel-size", cli->pixel_size,
                 "pixel size when the file has no SEM metadata, e.g. 0.8um");
  app.add_option("--crop-bottom", cli->crop_bottom,
                 "rows of information bar to remove (default: from SEM metadata or detected)");
  bind_choice(app, "--denoise", cli->denoise, denoise_choices, "none, gaussian or median");
  app.add_option("--denoise-radius", cli->segment.denoise_radius_px, "px")->capture_default_str();
  bind_choice(app, "--background", cli->background, background_choices,
              "background flattening: none, quadratic (fitted surface) or rolling");
  app.add_option("--background-radius", cli->segment.rolling_radius_px,
                 "px, radius of the rolling background")
      ->capture_default_str();
  app.add_option("--background-min-fraction", cli->segment.background_min_fraction,
                 "the quadratic background is fitted only when the background pixels cover at "
                 "least this fraction of the image (a dense field has no background to model)")
      ->capture_default_str();
  bind_choice(app, "--threshold", cli->threshold, threshold_choices,
              "otsu, triangle, fixed, adaptive or isodata (ImageJ's Default)");
  app.add_option("--threshold-level", cli->segment.fixed_level,
                 "fixed threshold as a fraction of the intensity range")
      ->capture_default_str();
  app.add_option("--adaptive-block", cli->segment.adaptive_block_px, "odd window, px")
      ->capture_default_str();
  app.add_option("--adaptive-offset", cli->segment.adaptive_offset, "fraction above the local mean")
      ->capture_default_str();
  bind_choice(app, "--polarity", cli->polarity, polarity_choices,
              "bright (particles on dark), dark, or auto");
  app.add_flag("--keep-holes", cli->keep_holes, "do not fill holes in particles");
  app.add_flag("--no-split", cli->no_split, "do not split touching particles (= --split none)");
  std::vector<std::string> split_names;
  for (const auto& [key, help] : split_choices)
    split_names.push_back(key);
  app.add_option("--split", cli->split,
                 "none, neck, prominence (default; ImageJ-like watershed) or imagej (ImageJ's "
                 "Watershed, in ImageJ's order: before holes are filled)")
      ->check(CLI::IsMember(split_names));
  app.add_option("--split-gaps", cli->split_gaps,
                 "unsmoothed: split along the gaps of the image before --denoise, measure the "
                 "smoothed outlines; smoothed: split the smoothed mask")
      ->check(CLI::IsMember({"unsmoothed", "smoothed"}))
      ->capture_default_str();
  app.add_flag("--imagej", cli->imagej,
               "ImageJ's Analyze Particles as a user runs it: Default (IsoData) threshold, no "
               "smoothing or background, fill holes, exclude on edges, 8-connected; watershed "
               "with --split imagej; explicit options override");
  app.add_option("--split-neck", cli->segment.split_neck,
                 "split where the neck half-width < this x the smaller particle's inscribed radius")
      ->capture_default_str();
  app.add_option("--split-prominence", cli->segment.split_prominence_px,
                 "px; --split prominence|imagej keep distance-map maxima standing out by more")
      ->capture_default_str();
  app.add_option("--split-fragment", cli->segment.split_fragment_fraction,
                 "a piece the split cuts off below this fraction of the median area is joined "
                 "back to its neighbour (0: never)")
      ->capture_default_str();
  app.add_option("--cluster-split-neck", cli->segment.cluster_split_neck,
                 "a convex blob with holes is split as a cluster of touching particles around "
                 "pores when maxima behind necks narrower than this x the smaller inscribed "
                 "radius give 3 pieces or more")
      ->capture_default_str();
  app.add_option("--relief-solidity", cli->segment.relief_solidity,
                 "holes are filled before the split in blobs at least this convex (area / hull "
                 "area), else split along (0: always filled first)")
      ->capture_default_str();
  app.add_flag("--keep-edge-particles", cli->keep_edges, "keep particles touching the image edge");
  app.add_option("--min-area", cli->segment.min_area_px, "px")->capture_default_str();
  app.add_option("--max-area", cli->segment.max_area_px, "px (0: no limit)")->capture_default_str();
  app.add_option("--min-fourier-diameter", cli->min_fourier_diameter_px,
                 "px; smaller particles are left out of the mean Fourier spectrum")
      ->capture_default_str();
  app.add_flag("--no-overlays", cli->no_overlays, "skip overlay and plot PNGs");
  return [cli, &app](const RunContext& context) {
    if (cli->imagej) apply_imagej_preset(*cli, app);
    // ImageJ's Watershed keeps maxima standing out by more than 0.5 px (EDM.java's tolerance);
    // 0.6 is the default of the prominence flood only.
    if (cli->split == "imagej" && app.count("--split-prominence") == 0)
      cli->segment.split_prominence_px = 0.5;
    return run(*cli, context);
  };
}

}  // namespace shapepress::imaging
