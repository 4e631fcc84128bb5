#pragma once
// Loading images of a powder: any grayscale or colour file OpenCV reads (8/16-bit TIFF, PNG,
// JPEG, BMP, PGM) or a GIF (first frame, through giflib), the SEM metadata, and the
// information bar at the bottom.
#include <filesystem>
#include <optional>
#include <string>

#include "imaging/image.hpp"

namespace shapepress::imaging {

struct LoadedImage {
  GrayImage image;  // intensities stretched to [0, 1] (min→0, max→1)
  int bit_depth = 8;
  int channels = 1;
  double raw_min = 0.0;  // gray values (after colour → gray) that were stretched to 0 and 1
  double raw_max = 1.0;
  std::optional<double> pixel_size_m;  // from the SEM metadata, if any
  std::optional<int> data_rows;        // from the SEM metadata: rows above the information bar
};

// Throws InputError naming the file: missing, unreadable, empty, or uniform (all one value).
LoadedImage load_image(const std::filesystem::path& path);

// Rows of a digitally drawn information bar at the bottom (0 if none): a block of rows, 3–30 %
// of the height, in which one exact value (the bar's background) covers most of the bottom row
// and at least 30 % of every row (text rows), as instruments draw it without noise. Detector
// noise makes such rows impossible in the scan, and the row above the bar must be noisy (a
// clean image with plain background rows has no bar); --crop-bottom overrides the detection.
int detect_info_bar_rows(const GrayImage& image);

// A stretched image (of `loaded`, possibly cropped) as the 8-bit gray levels ImageJ thresholds,
// divided by 255: the file's own values for 8-bit files; min..max in 256 bins otherwise.
GrayImage imagej_8bit_levels(const GrayImage& image, const LoadedImage& loaded);

// The top `rows` rows.
GrayImage crop_rows(const GrayImage& image, int rows);

}  // namespace shapepress::imaging
