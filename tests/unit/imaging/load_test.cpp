// Loading: every failure names the file and the cause; depths and colour are accepted; the
// information bar is found.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "common/error.hpp"
#include "imaging/load.hpp"
#include "tests/support/files.hpp"

namespace shapepress::imaging {
namespace {

namespace fs = std::filesystem;

// Netpbm files written by hand (OpenCV reads them): P5 grey (8 or 16 bit, big-endian), P6 RGB.
void write_netpbm(const fs::path& path, int w, int h, int channels, int maxval,
                  const std::function<int(int, int)>& value) {
  std::ofstream out(path, std::ios::binary);
  out << (channels == 3 ? "P6" : "P5") << "\n" << w << " " << h << "\n" << maxval << "\n";
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c) {
        int v = value(x, y);
        if (maxval > 255) out.put(static_cast<char>(v >> 8));
        out.put(static_cast<char>(v & 0xff));
      }
}

fs::path temp_path(const std::string& name) {
  static const fs::path dir = testing::fresh_directory("imaging_load");
  return dir / name;
}

void expect_input_error(const fs::path& path, const std::string& cause) {
  try {
    load_image(path);
    FAIL() << "expected InputError for " << path;
  } catch (const InputError& e) {
    std::string message = e.what();
    EXPECT_NE(message.find(path.filename().string()), std::string::npos) << message;
    EXPECT_NE(message.find(cause), std::string::npos) << message;
  }
}

TEST(Load, BadFilesAreNamedWithTheirCause) {
  expect_input_error(temp_path("does_not_exist.png"), "no such image file");
  fs::path empty = temp_path("empty.png");
  std::ofstream(empty).close();
  expect_input_error(empty, "empty file");
  fs::path text = temp_path("notes.tif");
  std::ofstream(text) << "these are not pixels\n";
  expect_input_error(text, "cannot be read as an image");
  fs::path black = temp_path("black.pgm");
  write_netpbm(black, 32, 32, 1, 255, [](int, int) { return 0; });
  expect_input_error(black, "uniform");
  fs::path white = temp_path("white.pgm");
  write_netpbm(white, 32, 32, 1, 255, [](int, int) { return 255; });
  expect_input_error(white, "uniform");
}

TEST(Load, SixteenBitAndColourImages) {
  auto square = [](int x, int y) { return x >= 5 && x < 15 && y >= 5 && y < 15; };
  fs::path deep_path = temp_path("deep.pgm");
  write_netpbm(deep_path, 30, 20, 1, 65535,
               [&](int x, int y) { return square(x, y) ? 41000 : 1000; });
  LoadedImage d = load_image(deep_path);
  EXPECT_EQ(d.bit_depth, 16);
  EXPECT_FLOAT_EQ(d.image.at(0, 0), 0.0f);
  EXPECT_FLOAT_EQ(d.image.at(7, 7), 1.0f);
  EXPECT_FALSE(d.pixel_size_m);  // a PGM carries no SEM metadata

  fs::path colour_path = temp_path("colour.ppm");
  write_netpbm(colour_path, 30, 20, 3, 255, [&](int x, int y) { return square(x, y) ? 200 : 10; });
  LoadedImage c = load_image(colour_path);
  EXPECT_EQ(c.channels, 3);
  EXPECT_FLOAT_EQ(c.image.at(7, 7), 1.0f);
}

TEST(Load, InformationBarIsDetectedAndNoisyScansAreNot) {
  GrayImage image(200, 150);
  unsigned state = 12345;
  for (float& v : image.pixels) {  // scan noise: no row has one dominant value
    state = state * 1103515245u + 12345u;
    v = 0.3f + 0.2f * static_cast<float>((state >> 16) % 1000) / 1000.0f;
  }
  EXPECT_EQ(detect_info_bar_rows(image), 0);
  for (int y = 130; y < 150; ++y)
    for (int x = 0; x < 200; ++x)
      image.at(x, y) = (y > 135 && y < 140 && x % 9 < 2) ? 1.0f : 0.0f;
  EXPECT_EQ(detect_info_bar_rows(image), 20);
  EXPECT_EQ(crop_rows(image, 130).height, 130);

  // A clean binary image: plain background rows at the bottom are not a bar.
  GrayImage clean(200, 150, 0.0f);
  for (int y = 20; y < 140; ++y)
    for (int x = 50; x < 150; ++x)
      clean.at(x, y) = 1.0f;
  EXPECT_EQ(detect_info_bar_rows(clean), 0);
}

// ImageJ's sample blobs.gif (8-bit, inverting lookup table) and an ImageJ-written 16-bit TIFF
// of it (raw values × 257) against blobs_raw.pgm, the same raw values as a plain file.
const std::string data = std::string(SHAPEPRESS_TEST_DATA) + "/imaging/";

TEST(Load, GifAppliesItsPaletteAndSixteenBitTiffKeepsItsValues) {
  LoadedImage raw = load_image(data + "blobs_raw.pgm");
  LoadedImage gif = load_image(data + "blobs.gif");
  ASSERT_EQ(gif.image.width, 256);
  ASSERT_EQ(gif.image.height, 254);
  EXPECT_EQ(gif.bit_depth, 8);
  EXPECT_EQ(gif.channels, 1);  // a gray palette gives a gray image
  // The inverting palette shows value v as 255 - v: the blobs look dark, as in ImageJ.
  EXPECT_DOUBLE_EQ(gif.raw_min, 255 - raw.raw_max);
  EXPECT_DOUBLE_EQ(gif.raw_max, 255 - raw.raw_min);
  for (std::size_t i = 0; i < raw.image.pixels.size(); ++i)
    ASSERT_NEAR(gif.image.pixels[i], 1.0f - raw.image.pixels[i], 1e-6f) << "pixel " << i;
  // imagej_8bit_levels gives the file's values back exactly.
  GrayImage levels = imagej_8bit_levels(gif.image, gif);
  GrayImage raw_levels = imagej_8bit_levels(raw.image, raw);
  for (std::size_t i = 0; i < raw.image.pixels.size(); ++i)
    ASSERT_FLOAT_EQ(levels.pixels[i] * 255.0f, 255.0f - std::round(raw_levels.pixels[i] * 255.0f));

  LoadedImage deep = load_image(data + "blobs16.tif");
  EXPECT_EQ(deep.bit_depth, 16);
  EXPECT_DOUBLE_EQ(deep.raw_min, raw.raw_min * 257);
  EXPECT_DOUBLE_EQ(deep.raw_max, raw.raw_max * 257);
  for (std::size_t i = 0; i < raw.image.pixels.size(); ++i)
    ASSERT_NEAR(deep.image.pixels[i], raw.image.pixels[i], 1e-6f) << "pixel " << i;
}

// scikit-image's chessboard in 16 bits, little- and big-endian, as written by another program
// than ImageJ (tifffile, values 0-255 in 16-bit words): both byte orders give the pixels of the
// same chessboard in 8 bits.
TEST(Load, SixteenBitTiffInBothByteOrders) {
  LoadedImage eight = load_image(data + "chessboard_GRAY.png");
  for (const char* name : {"chessboard_GRAY_U16.tif", "chessboard_GRAY_U16B.tif"}) {
    SCOPED_TRACE(name);
    LoadedImage deep = load_image(data + name);
    EXPECT_EQ(deep.bit_depth, 16);
    ASSERT_EQ(deep.image.width, eight.image.width);
    ASSERT_EQ(deep.image.height, eight.image.height);
    EXPECT_DOUBLE_EQ(deep.raw_max, eight.raw_max);  // scikit-image stores the 8-bit values
    for (std::size_t i = 0; i < eight.image.pixels.size(); ++i)
      ASSERT_NEAR(deep.image.pixels[i], eight.image.pixels[i], 1e-6f) << "pixel " << i;
  }
}

TEST(Load, TruncatedGifIsNamedAsUnreadable) {
  fs::path gif = temp_path("truncated.gif");
  std::ofstream(gif, std::ios::binary) << "GIF89a\x10\x00";
  expect_input_error(gif, "cannot be read as an image");
}

}  // namespace
}  // namespace shapepress::imaging
