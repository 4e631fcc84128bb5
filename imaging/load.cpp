#include "imaging/load.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <unordered_map>

#include "common/error.hpp"
#include "imaging/sem_tiff.hpp"

namespace shapepress::imaging {

LoadedImage load_image(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw InputError(fmt::format("{}: no such image file", path.string()));
  if (std::filesystem::is_directory(path, ec))
    throw InputError(fmt::format("{}: is a directory, expected an image file", path.string()));
  if (std::filesystem::file_size(path, ec) == 0)
    throw InputError(fmt::format("{}: empty file (0 bytes)", path.string()));

  cv::Mat raw = cv::imread(path.string(), cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  if (raw.empty())
    throw InputError(fmt::format(
        "{}: cannot be read as an image (expected TIFF, PNG, JPEG, BMP or PGM)", path.string()));
  LoadedImage loaded;
  loaded.channels = raw.channels();
  loaded.bit_depth = raw.depth() == CV_8U ? 8 : raw.depth() == CV_16U ? 16 : 32;
  cv::Mat gray;
  if (raw.channels() == 3)
    cv::cvtColor(raw, gray, cv::COLOR_BGR2GRAY);
  else if (raw.channels() == 4)
    cv::cvtColor(raw, gray, cv::COLOR_BGRA2GRAY);
  else
    gray = raw;
  double lo = 0.0, hi = 0.0;
  cv::minMaxLoc(gray, &lo, &hi);
  if (!(hi > lo))
    throw InputError(
        fmt::format("{}: the image is uniform (every pixel is {}): nothing to "
                    "segment",
                    path.string(), lo));
  cv::Mat scaled;
  gray.convertTo(scaled, CV_32F, 1.0 / (hi - lo), -lo / (hi - lo));
  cv::min(cv::max(scaled, 0.0), 1.0, scaled);  // rounding of the scaling must not leave [0, 1]
  loaded.image = GrayImage(scaled.cols, scaled.rows);
  for (int y = 0; y < scaled.rows; ++y)
    std::copy_n(scaled.ptr<float>(y), scaled.cols, &loaded.image.at(0, y));

  SemMetadata metadata = read_sem_metadata(path);
  loaded.pixel_size_m = metadata.pixel_width_m;
  if (metadata.data_rows && *metadata.data_rows < loaded.image.height)
    loaded.data_rows = metadata.data_rows;
  return loaded;
}

namespace {

// Fraction of a row taken by its most common value.
double mode_fraction(const GrayImage& image, int y, float* mode) {
  std::unordered_map<float, int> counts;
  int best = 0;
  for (int x = 0; x < image.width; ++x) {
    int c = ++counts[image.at(x, y)];
    if (c > best) {
      best = c;
      *mode = image.at(x, y);
    }
  }
  return static_cast<double>(best) / image.width;
}

}  // namespace

int detect_info_bar_rows(const GrayImage& image) {
  // The bottom row must be mostly the bar's background; rows above belong to the bar while
  // their most common value is that same background and covers at least 30 % of the row
  // (rows through text). Scan rows with noise have no value covering even 10 %.
  constexpr double min_share = 0.03, max_share = 0.30, bottom_fraction = 0.6,
                   text_row_fraction = 0.3;
  const int max_rows = static_cast<int>(image.height * max_share);
  int rows = 0;
  float bar_value = 0.0f;
  for (int y = image.height - 1; y >= image.height - max_rows && y >= 0; --y) {
    float mode = 0.0f;
    double fraction = mode_fraction(image, y, &mode);
    if (rows == 0 ? fraction < bottom_fraction
                  : (fraction < text_row_fraction || mode != bar_value))
      break;
    bar_value = mode;
    ++rows;
  }
  if (rows < image.height * min_share || rows >= max_rows) return 0;
  // The scan above a bar is noisy. A clean (synthetic or binary) image whose bottom rows are
  // plain background has no bar: cropping would cut into its particles.
  float above = 0.0f;
  return mode_fraction(image, image.height - rows - 1, &above) < text_row_fraction ? rows : 0;
}

GrayImage crop_rows(const GrayImage& image, int rows) {
  rows = std::clamp(rows, 0, image.height);
  GrayImage out(image.width, rows);
  std::copy_n(image.pixels.begin(), static_cast<std::size_t>(rows) * image.width,
              out.pixels.begin());
  return out;
}

}  // namespace shapepress::imaging
