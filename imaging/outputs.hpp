#pragma once
// Files written by the imaging stages: the particle table, overlays and histogram plots for a
// person to check the segmentation by eye, and the ground truth of synthetic images.
#include <filesystem>
#include <vector>

#include "imaging/shape_stats.hpp"
#include "imaging/statistics.hpp"
#include "imaging/synth.hpp"

namespace shapepress::imaging {

// particles.csv: one row per particle of every image; lengths in metres and pixels.
void write_particles_csv(const std::filesystem::path& path, const std::vector<ImageResult>& images);

// The image in grey with each particle's outline (colour) and id; PNG.
void write_overlay_png(const std::filesystem::path& path, const ImageResult& image);

// size_distribution.png (Q0, Q3), asr_histogram.png, fourier_spectrum.png in `folder`.
void write_plots(const std::filesystem::path& folder, const ShapeSummary& summary);

// Any GrayImage as an 8-bit PNG (or other format OpenCV picks by extension), atomically.
void write_gray_image(const std::filesystem::path& path, const GrayImage& image);

// truth.csv of a synthetic scene, lengths in pixels and metres.
void write_truth_csv(const std::filesystem::path& path, const SynthScene& scene,
                     double pixel_size_m);

}  // namespace shapepress::imaging
