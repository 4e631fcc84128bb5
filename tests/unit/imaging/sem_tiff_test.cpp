// The FEI/Thermo Fisher SEM metadata reader (libtiff) on TIFFs built byte by byte here (both
// byte orders, damaged ones), and the writer used by synth-images read back by OpenCV.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/error.hpp"
#include "imaging/load.hpp"
#include "imaging/sem_tiff.hpp"
#include "tests/support/files.hpp"

namespace shapepress::imaging {
namespace {

namespace fs = std::filesystem;

fs::path temp_path(const std::string& name) {
  static const fs::path dir = testing::fresh_directory("imaging_sem_tiff");
  return dir / name;
}

void put(std::string& out, std::uint32_t value, int size, bool big_endian) {
  for (int i = 0; i < size; ++i) {
    int shift = big_endian ? 8 * (size - 1 - i) : 8 * i;
    out.push_back(static_cast<char>((value >> shift) & 0xff));
  }
}

// A 4×2 8-bit TIFF with one strip and the FEI text in tag 34682, as the instrument writes it.
std::string handmade_tiff(const std::string& text, bool big_endian) {
  std::string t = big_endian ? "MM" : "II";
  put(t, 42, 2, big_endian);
  put(t, 8, 4, big_endian);
  const int entries = 7;
  const std::uint32_t text_at = 8 + 2 + 12 * entries + 4;
  const std::uint32_t pixels_at = text_at + static_cast<std::uint32_t>(text.size()) + 1;
  put(t, entries, 2, big_endian);
  auto entry = [&](int tag, int type, std::uint32_t count, std::uint32_t value) {
    put(t, tag, 2, big_endian);
    put(t, type, 2, big_endian);
    put(t, count, 4, big_endian);
    if (type == 3 && count == 1) {  // a SHORT sits in the first two bytes of the value field
      put(t, value, 2, big_endian);
      put(t, 0, 2, big_endian);
    } else {
      put(t, value, 4, big_endian);
    }
  };
  entry(256, 3, 1, 4);
  entry(257, 3, 1, 2);
  entry(258, 3, 1, 8);
  entry(262, 3, 1, 1);
  entry(273, 4, 1, pixels_at);
  entry(279, 4, 1, 8);
  entry(34682, 2, static_cast<std::uint32_t>(text.size()) + 1, text_at);
  put(t, 0, 4, big_endian);
  t += text;
  t.push_back('\0');
  t += std::string("\x10\x20\x30\x40\x50\x60\x70\x80", 8);
  return t;
}

const std::string fei_text =
    "[User]\r\nDate=01/02/2023\r\n[Beam]\r\nHV=5000\r\n[Scan]\r\nPixelWidth=2.5e-08\r\n"
    "PixelHeight=2.5e-08\r\n[Image]\r\nResolutionX=4\r\nResolutionY=2\r\n";

TEST(SemTiff, ParsesTheScanSection) {
  SemMetadata m = parse_fei_metadata(fei_text);
  ASSERT_TRUE(m.pixel_width_m);
  EXPECT_DOUBLE_EQ(*m.pixel_width_m, 2.5e-8);
  ASSERT_TRUE(m.data_rows);
  EXPECT_EQ(*m.data_rows, 2);
  // PixelWidth outside [Scan] (e.g. [EScan] of another detector) is not the scan's pixel.
  EXPECT_FALSE(parse_fei_metadata("[EScan]\nPixelWidth=1e-6\n").pixel_width_m);
}

TEST(SemTiff, ReadsTheTagInBothByteOrders) {
  for (bool big : {false, true}) {
    fs::path path = temp_path(big ? "fei_mm.tif" : "fei_ii.tif");
    std::ofstream(path, std::ios::binary) << handmade_tiff(fei_text, big);
    auto text = read_tiff_ascii_tag(path, fei_metadata_tag);
    ASSERT_TRUE(text) << path;
    EXPECT_EQ(*text, fei_text);
    EXPECT_DOUBLE_EQ(*read_sem_metadata(path).pixel_width_m, 2.5e-8);
  }
}

TEST(SemTiff, NonTiffAndTiffWithoutTagHaveNoMetadata) {
  fs::path pgm = temp_path("plain.pgm");
  std::ofstream(pgm, std::ios::binary) << "P5\n2 1\n255\n\x01\x02";
  EXPECT_FALSE(read_sem_metadata(pgm).pixel_width_m);
  fs::path tif = temp_path("notag.tif");
  std::string bytes = handmade_tiff("x", false);
  bytes[8 + 2 + 12 * 6] = 0x11;  // retag 34682 (0x877A) as 34577: no FEI tag any more
  std::ofstream(tif, std::ios::binary) << bytes;
  EXPECT_FALSE(read_sem_metadata(tif).pixel_width_m);
}

TEST(SemTiff, TruncatedIfdIsAnInputErrorNamingTheFile) {
  fs::path path = temp_path("truncated.tif");
  std::ofstream(path, std::ios::binary) << handmade_tiff(fei_text, false).substr(0, 30);
  try {
    read_sem_metadata(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("truncated.tif"), std::string::npos) << e.what();
  }
}

// The text's bytes cut off by the end of the file (libtiff only warns and drops the tag), and the
// tag stored as numbers: the file is damaged, not an image without metadata.
TEST(SemTiff, UnreadableOrNumericTagIsAnInputErrorNamingTheFile) {
  const std::string whole = handmade_tiff(fei_text, false);
  fs::path cut = temp_path("text_cut.tif");
  std::ofstream(cut, std::ios::binary) << whole.substr(0, 8 + 2 + 12 * 7 + 4 + 10);
  fs::path numeric = temp_path("numeric_tag.tif");
  std::string retyped = whole;
  retyped[8 + 2 + 12 * 6 + 2] = 4;  // tag 34682's type ASCII (2) -> LONG (4)
  std::ofstream(numeric, std::ios::binary) << retyped;
  for (const fs::path& path : {cut, numeric}) {
    try {
      read_sem_metadata(path);
      ADD_FAILURE() << "expected InputError for " << path;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path.filename().string()), std::string::npos)
          << e.what();
    }
  }
}

TEST(SemTiff, WrittenTiffLoadsWithItsPixelSizeAndBar) {
  GrayImage image(64, 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      image.at(x, y) = static_cast<float>((x + y) % 256) / 255.0f;
  fs::path path = temp_path("written.tif");
  write_sem_tiff(path, image, "[Scan]\nPixelWidth=8e-07\n[Image]\nResolutionY=40\n");
  LoadedImage loaded = load_image(path);  // OpenCV's TIFF reader must accept the file
  EXPECT_EQ(loaded.image.width, 64);
  EXPECT_EQ(loaded.image.height, 48);
  EXPECT_EQ(loaded.bit_depth, 8);
  ASSERT_TRUE(loaded.pixel_size_m);
  EXPECT_DOUBLE_EQ(*loaded.pixel_size_m, 8e-7);
  ASSERT_TRUE(loaded.data_rows);
  EXPECT_EQ(*loaded.data_rows, 40);
  // Pixel values survive (stretched to [0, 1] by the loader: min 0, max 110/255).
  EXPECT_NEAR(loaded.image.at(10, 20), 30.0 / 110.0, 1e-6);
}

}  // namespace
}  // namespace shapepress::imaging
