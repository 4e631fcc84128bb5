#pragma once
// The shape-stats pipeline for a batch of images: load, crop the information bar, segment,
// measure; images are processed in parallel and a bad image is skipped with its reason.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "imaging/load.hpp"
#include "imaging/measure.hpp"
#include "imaging/segment.hpp"
#include "imaging/statistics.hpp"

namespace shapepress::imaging {

struct ShapeStatsOptions {
  SegmentOptions segment;
  std::optional<double> pixel_size_m;  // used when the file has no SEM metadata
  std::optional<int> crop_bottom;      // rows of information bar; unset: detect
  double min_fourier_diameter_px = 20.0;
};

struct ImageResult {
  ImageReport report;
  GrayImage image;  // cropped, as segmented (for the overlay)
  std::vector<ParticleMeasurement> particles;
};

// Throws InputError naming the file and the cause (unreadable, uniform, no pixel size, no
// particle found).
ImageResult process_image(const std::filesystem::path& path, const ShapeStatsOptions& options);

struct SkippedImage {
  std::string file;
  std::string reason;
};

struct BatchResult {
  std::vector<ImageResult> images;  // in the order given
  std::vector<SkippedImage> skipped;
};

// `threads` 0: OpenMP's default. `on_done` is called (serialised) after each image.
BatchResult process_batch(const std::vector<std::filesystem::path>& paths,
                          const ShapeStatsOptions& options, int threads,
                          const std::function<void(int done)>& on_done = {});

// The samples the statistics need, in SI units.
std::vector<ParticleSample> particle_samples(const std::vector<ImageResult>& images);

}  // namespace shapepress::imaging
