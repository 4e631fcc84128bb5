#include "imaging/shape_stats.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "common/error.hpp"

namespace shapepress::imaging {

ImageResult process_image(const std::filesystem::path& path, const ShapeStatsOptions& options) {
  LoadedImage loaded = load_image(path);
  ImageResult result;
  ImageReport& report = result.report;
  report.file = path.string();
  if (loaded.pixel_size_m) {
    report.pixel_size_m = *loaded.pixel_size_m;
    report.pixel_size_source = "sem-metadata";
    if (options.pixel_size_m && std::abs(*options.pixel_size_m / *loaded.pixel_size_m - 1) > 1e-6)
      spdlog::warn("{}: the SEM metadata's pixel size {:g} m is used, not --pixel-size {:g} m",
                   path.string(), *loaded.pixel_size_m, *options.pixel_size_m);
  } else if (options.pixel_size_m) {
    report.pixel_size_m = *options.pixel_size_m;
    report.pixel_size_source = "--pixel-size";
  } else {
    throw InputError(fmt::format(
        "{}: pixel size unknown: the file has no SEM metadata ([Scan] PixelWidth in TIFF tag "
        "34682); give it with --pixel-size, e.g. --pixel-size 0.8um",
        path.string()));
  }

  int bar_rows = options.crop_bottom ? *options.crop_bottom
                 : loaded.data_rows  ? loaded.image.height - *loaded.data_rows
                                     : detect_info_bar_rows(loaded.image);
  if (bar_rows < 0 || bar_rows >= loaded.image.height - 8)
    throw InputError(fmt::format("{}: --crop-bottom {} leaves no image ({} rows)", path.string(),
                                 bar_rows, loaded.image.height));
  result.image = bar_rows > 0 ? crop_rows(loaded.image, loaded.image.height - bar_rows)
                              : std::move(loaded.image);
  // ImageJ's "Default" threshold works on the file's 8-bit levels, not on the stretched ones.
  if (options.segment.threshold == ThresholdMethod::isodata)
    result.image = imagej_8bit_levels(result.image, loaded);
  report.width = result.image.width;
  report.height = result.image.height;
  report.info_bar_rows = bar_rows;

  Segmentation segmentation = segment_particles(result.image, options.segment);
  report.bright_particles = segmentation.bright_particles;
  report.threshold = segmentation.threshold;
  report.excluded_on_edge = segmentation.excluded_on_edge;
  report.excluded_by_size = segmentation.excluded_by_size;
  report.background = to_string(segmentation.background);
  report.background_fraction = segmentation.background_fraction;
  if (options.segment.background == Background::quadratic &&
      segmentation.background != Background::quadratic)
    spdlog::info(
        "{}: no background fitted: its pixels are {:.0f} % of the image, under "
        "--background-min-fraction {:g} (a dense field of touching particles)",
        path.string(), 100.0 * segmentation.background_fraction,
        options.segment.background_min_fraction);
  if (segmentation.labels.count == 0)
    throw InputError(fmt::format(
        "{}: no particle found ({} on the edge and {} outside the size range were excluded); "
        "check --polarity, --threshold and --min-area",
        path.string(), segmentation.excluded_on_edge, segmentation.excluded_by_size));
  result.particles =
      measure_particles(segmentation.labels, &segmentation.flattened, segmentation.threshold);
  report.particles = static_cast<int>(result.particles.size());
  return result;
}

BatchResult process_batch(const std::vector<std::filesystem::path>& paths,
                          const ShapeStatsOptions& options, int threads,
                          const std::function<void(int done)>& on_done) {
  const int n = static_cast<int>(paths.size());
  std::vector<std::optional<ImageResult>> results(n);
  std::vector<std::string> failures(n);
  int done = 0;
  // One image per thread; with fewer images than threads the outer team is smaller, and a
  // team of one leaves the particle loop inside free to use the threads.
  const int team = std::max(1, std::min(n, threads > 0 ? threads : omp_get_max_threads()));
#pragma omp parallel for schedule(dynamic, 1) num_threads(team)
  for (int i = 0; i < n; ++i) {
    try {
      results[i] = process_image(paths[i], options);
    } catch (const InputError& e) {
      failures[i] = e.what();
    } catch (const std::exception& e) {  // OpenCV or allocation failures: report, keep going
      failures[i] = fmt::format("{}: {}", paths[i].string(), e.what());
    }
#pragma omp critical(shape_stats_progress)
    {
      ++done;
      if (on_done) on_done(done);
    }
  }
  BatchResult batch;
  for (int i = 0; i < n; ++i) {
    if (results[i])
      batch.images.push_back(std::move(*results[i]));
    else
      batch.skipped.push_back({paths[i].string(), failures[i]});
  }
  return batch;
}

std::vector<ParticleSample> particle_samples(const std::vector<ImageResult>& images) {
  std::vector<ParticleSample> samples;
  for (const ImageResult& image : images) {
    const double px = image.report.pixel_size_m;
    for (const ParticleMeasurement& m : image.particles) {
      samples.push_back({m.equivalent_diameter * px, m.equivalent_diameter, m.aspect_ratio,
                         m.circularity, m.solidity, m.convexity, m.fourier_mean_radius, m.fourier});
    }
  }
  return samples;
}

}  // namespace shapepress::imaging
