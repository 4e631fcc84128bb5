#include "imaging/load.hpp"

#include <fmt/format.h>

#include <gif_lib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <unordered_map>

#include "common/error.hpp"
#include "imaging/sem_tiff.hpp"

namespace shapepress::imaging {

namespace {

enum class ImageFormat { unknown, gif, decoded_by_opencv };

// The formats shapepress reads, by their signature. cv::imread alone would try every codec
// OpenCV was built with (DICOM through GDCM, JPEG 2000, OpenEXR, …): on damaged input GDCM aborts
// the process on an assertion instead of failing, so only files that announce one of the
// formats we support reach OpenCV.
ImageFormat sniff_format(const std::filesystem::path& path) {
  std::array<unsigned char, 8> head{};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(head.data()), head.size());
  const auto n = static_cast<std::size_t>(in.gcount());
  const auto starts = [&](std::initializer_list<unsigned char> magic) {
    return n >= magic.size() && std::equal(magic.begin(), magic.end(), head.begin());
  };
  if (starts({'G', 'I', 'F', '8'})) return ImageFormat::gif;
  const bool netpbm =
      n >= 3 && head[0] == 'P' && head[1] >= '1' && head[1] <= '6' && std::isspace(head[2]) != 0;
  if (starts({'I', 'I', 42, 0}) || starts({'M', 'M', 0, 42}) ||    // TIFF
      starts({0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}) ||     // PNG
      starts({0xff, 0xd8, 0xff}) || starts({'B', 'M'}) || netpbm)  // JPEG, BMP, PGM/PPM/PBM
    return ImageFormat::decoded_by_opencv;
  return ImageFormat::unknown;
}

// OpenCV 4.6 (Debian 12) reads no GIF, and ImageJ's own samples are GIFs: giflib decodes the
// first frame; the palette is applied (the image as it looks, as for any colour file), so a
// gray ramp gives one channel and any other palette three (BGR, like cv::imread).
cv::Mat read_gif(const std::filesystem::path& path) {
  int error = 0;
  GifFileType* gif = DGifOpenFileName(path.c_str(), &error);
  if (!gif) return {};
  struct Closer {
    GifFileType* gif;
    ~Closer() {
      int ignored = 0;
      DGifCloseFile(gif, &ignored);
    }
  } closer{gif};
  if (DGifSlurp(gif) != GIF_OK || gif->ImageCount < 1 || gif->SWidth <= 0 || gif->SHeight <= 0)
    return {};
  const SavedImage& frame = gif->SavedImages[0];
  const ColorMapObject* palette =
      frame.ImageDesc.ColorMap ? frame.ImageDesc.ColorMap : gif->SColorMap;
  if (!palette || !frame.RasterBits) return {};
  bool gray = true;
  for (int i = 0; i < palette->ColorCount; ++i) {
    const GifColorType& c = palette->Colors[i];
    gray = gray && c.Red == c.Green && c.Green == c.Blue;
  }
  auto color = [&](int index) -> const GifColorType& {
    return palette->Colors[std::clamp(index, 0, palette->ColorCount - 1)];
  };
  // Pixels outside the first frame's rectangle show the screen's background colour.
  const GifColorType& fill = color(gif->SBackGroundColor);
  cv::Mat out(gif->SHeight, gif->SWidth, gray ? CV_8UC1 : CV_8UC3,
              gray ? cv::Scalar(fill.Red) : cv::Scalar(fill.Blue, fill.Green, fill.Red));
  const GifImageDesc& d = frame.ImageDesc;
  for (int y = 0; y < d.Height; ++y) {
    for (int x = 0; x < d.Width; ++x) {
      const int ox = d.Left + x, oy = d.Top + y;
      if (ox < 0 || oy < 0 || ox >= out.cols || oy >= out.rows) continue;
      const GifColorType& c = color(frame.RasterBits[static_cast<std::size_t>(y) * d.Width + x]);
      if (gray)
        out.at<std::uint8_t>(oy, ox) = c.Red;
      else
        out.at<cv::Vec3b>(oy, ox) = cv::Vec3b(c.Blue, c.Green, c.Red);
    }
  }
  return out;
}

}  // namespace

LoadedImage load_image(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw InputError(fmt::format("{}: no such image file", path.string()));
  if (std::filesystem::is_directory(path, ec))
    throw InputError(fmt::format("{}: is a directory, expected an image file", path.string()));
  if (std::filesystem::file_size(path, ec) == 0)
    throw InputError(fmt::format("{}: empty file (0 bytes)", path.string()));

  const ImageFormat format = sniff_format(path);
  cv::Mat raw;
  try {
    raw = format == ImageFormat::gif ? read_gif(path)
          : format == ImageFormat::decoded_by_opencv
              ? cv::imread(path.string(), cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR)
              : cv::Mat();
  } catch (const cv::Exception& e) {  // e.g. a header declaring more pixels than OpenCV allows
    throw InputError(fmt::format("{}: cannot be read as an image: {}", path.string(), e.what()));
  }
  if (raw.empty())
    throw InputError(
        fmt::format("{}: cannot be read as an image (expected TIFF, PNG, JPEG, BMP, PGM or GIF)",
                    path.string()));
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
  loaded.raw_min = lo;
  loaded.raw_max = hi;
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

GrayImage imagej_8bit_levels(const GrayImage& image, const LoadedImage& loaded) {
  GrayImage out = image;
  const bool eight_bit = loaded.bit_depth == 8;
  const double range = loaded.raw_max - loaded.raw_min;
  for (float& v : out.pixels) {
    // 8-bit: the stored value back (exact); deeper: ImageJ's "8-bit" conversion, which maps
    // min..max onto 256 equal bins.
    const double level =
        eight_bit ? std::round(v * range + loaded.raw_min) : std::min(255.0, std::floor(v * 256.0));
    v = static_cast<float>(level / 255.0);
  }
  return out;
}

GrayImage crop_rows(const GrayImage& image, int rows) {
  rows = std::clamp(rows, 0, image.height);
  GrayImage out(image.width, rows);
  std::copy_n(image.pixels.begin(), static_cast<std::size_t>(rows) * image.width,
              out.pixels.begin());
  return out;
}

}  // namespace shapepress::imaging
