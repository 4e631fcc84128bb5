#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/run_metadata.hpp"
#include "common/units.hpp"
#include "imaging/cli.hpp"
#include "imaging/outputs.hpp"
#include "imaging/sem_tiff.hpp"
#include "imaging/synth.hpp"

namespace shapepress::imaging {
namespace {

struct SynthCli {
  std::string out;
  int images = 1;
  std::string shape = "mixed";
  std::string pixel_size = "0.5um";
  std::string format = "tif";
  SynthOptions options;
};

// The INI block an FEI instrument writes into TIFF tag 34682.
std::string fei_metadata(const SynthOptions& o, double pixel_size_m, std::uint64_t seed) {
  return fmt::format(
      "[User]\r\nUser=shapepress synth-images seed {}\r\n[Scan]\r\nPixelWidth={:.6e}\r\n"
      "PixelHeight={:.6e}\r\n[Image]\r\nResolutionX={}\r\nResolutionY={}\r\n",
      seed, pixel_size_m, pixel_size_m, o.width, o.height - o.info_bar_rows);
}

int run(const SynthCli& cli, const RunContext& context) {
  RunMetadata meta("synth-images", context.command_line);
  const double pixel_size_m = parse_quantity(cli.pixel_size, dim::length, "--pixel-size");
  if (!(pixel_size_m > 0)) throw InputError("--pixel-size: must be positive");
  if (cli.images < 1) throw InputError(fmt::format("--images: {} must be >= 1", cli.images));
  SynthOptions options = cli.options;
  options.shape = parse_synth_shape(cli.shape);
  options.check();
  const std::filesystem::path out(cli.out);
  ensure_output_folder(out);
  int total = 0;
  for (int i = 0; i < cli.images; ++i) {
    SynthOptions o = options;
    o.seed = options.seed + static_cast<std::uint64_t>(i);
    SynthScene scene = render_synthetic_scene(o);
    std::string stem = fmt::format("synth_{:03d}", i);
    if (cli.format == "tif")
      write_sem_tiff(out / (stem + ".tif"), scene.image, fei_metadata(o, pixel_size_m, o.seed));
    else
      write_gray_image(out / (stem + "." + cli.format), scene.image);
    write_truth_csv(out / (stem + "_truth.csv"), scene, pixel_size_m);
    meta.output(stem + "." + cli.format).output(stem + "_truth.csv");
    total += static_cast<int>(scene.particles.size());
  }
  // No input files: the settings are the inputs, so they are the facts.
  meta.fact("images", cli.images)
      .fact("particles", total)
      .fact("particles_per_image", options.particles)
      .fact("shape", cli.shape)
      .fact("pixel_size_m", pixel_size_m)
      .fact("width_px", options.width)
      .fact("height_px", options.height)
      .fact("info_bar_rows", options.info_bar_rows)
      .fact("median_diameter_px", options.median_diameter_px)
      .fact("noise", options.noise)
      .fact("blur_px", options.blur_px)
      .fact("dark_particles", options.dark_particles)
      .fact("seed", options.seed)
      .fact("format", cli.format)
      .write(out / run_metadata_name);
  spdlog::info("{} images with {} particles in {}", cli.images, total, out.string());
  return 0;
}

}  // namespace

StageRunner setup_synth_images_cli(CLI::App& app) {
  auto cli = std::make_shared<SynthCli>();
  SynthOptions& o = cli->options;
  o.info_bar_rows = 40;
  app.add_option("--out", cli->out, "output folder")->required();
  app.add_option("--images", cli->images, "number of images (seeds seed, seed+1, ...)")
      ->capture_default_str();
  app.add_option("--format", cli->format,
                 "tif (8-bit, FEI metadata with the pixel size), png or pgm (no metadata)")
      ->check(CLI::IsMember({"tif", "png", "pgm"}))
      ->capture_default_str();
  app.add_option("--pixel-size", cli->pixel_size, "written into the TIFF metadata and truth CSV")
      ->capture_default_str();
  app.add_option("--width", o.width, "px")->capture_default_str();
  app.add_option("--height", o.height, "px")->capture_default_str();
  app.add_option("--particles", o.particles, "particles per image")->capture_default_str();
  app.add_option("--shape", cli->shape, "disc, ellipse, fourier or mixed")->capture_default_str();
  app.add_option("--median-diameter", o.median_diameter_px, "px, equivalent circle diameter")
      ->capture_default_str();
  app.add_option("--diameter-spread", o.diameter_spread, "geometric standard deviation")
      ->capture_default_str();
  app.add_option("--min-diameter", o.min_diameter_px, "px")->capture_default_str();
  app.add_option("--max-diameter", o.max_diameter_px, "px")->capture_default_str();
  app.add_option("--min-aspect-ratio", o.min_aspect_ratio, "ellipses")->capture_default_str();
  app.add_option("--max-aspect-ratio", o.max_aspect_ratio, "ellipses")->capture_default_str();
  app.add_option("--D2", o.D2, "Fourier outlines: elongation")->capture_default_str();
  app.add_option("--D3", o.D3, "Fourier outlines: irregularity")->capture_default_str();
  app.add_option("--D8", o.D8, "Fourier outlines: roughness")->capture_default_str();
  app.add_option("--decay", o.decay_exponent, "Fourier outlines: D_n ~ n^-decay beyond 8")
      ->capture_default_str();
  app.add_option("--touching-fraction", o.touching_fraction, "share of particles in touching pairs")
      ->capture_default_str();
  app.add_option("--noise", o.noise, "Gaussian noise sigma, intensity units")
      ->capture_default_str();
  app.add_option("--blur", o.blur_px, "Gaussian blur sigma, px")->capture_default_str();
  app.add_option("--gradient", o.gradient, "background ramp across the image")
      ->capture_default_str();
  app.add_option("--info-bar", o.info_bar_rows, "rows of information bar (0: none)")
      ->capture_default_str();
  app.add_flag("--dark-particles", o.dark_particles, "dark particles on a bright background");
  app.add_option("--seed", o.seed, "random seed")->capture_default_str();
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::imaging
