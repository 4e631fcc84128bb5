// Agreement with ImageJ's definitions: the same binary images measured by ImageJ 1.53t
// (Analyze Particles; references in tests/data/imaging/*_imagej.csv) and by shape-stats'
// segmentation and measurement, particle by particle.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "common/csv.hpp"
#include "imaging/measure.hpp"
#include "imaging/segment.hpp"

namespace shapepress::imaging {
namespace {

const std::string data = std::string(SHAPEPRESS_TEST_DATA) + "/imaging/";

// An 8-bit P5 file, thresholded at `level` (ImageJ: setThreshold(level, 255)), as a 0/1 image.
GrayImage read_binary_pgm(const std::string& path, int level) {
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  int w = 0, h = 0, maxval = 0;
  in >> magic >> w >> h >> maxval;
  in.get();
  GrayImage image(w, h);
  for (float& v : image.pixels)
    v = static_cast<unsigned char>(in.get()) >= level ? 1.0f : 0.0f;
  EXPECT_TRUE(in) << path;
  return image;
}

std::vector<ParticleMeasurement> measure_like_imagej(const GrayImage& binary) {
  SegmentOptions options;  // plain thresholding: nothing ImageJ's Analyze Particles lacks
  options.denoise = Denoise::none;
  options.background = Background::none;
  options.threshold = ThresholdMethod::fixed;
  options.polarity = Polarity::bright;
  options.fill_holes = false;  // ImageJ's area is the pixel count without "include holes"
  options.split_touching = false;
  options.min_area_px = 1;
  return measure_particles(segment_particles(binary, options).labels);
}

void compare_with_imagej(const std::string& image, const std::string& reference) {
  std::vector<ParticleMeasurement> ours = measure_like_imagej(read_binary_pgm(data + image, 128));
  CsvTable ij = read_csv(data + reference);
  ASSERT_EQ(ours.size(), ij.rows.size()) << "particle count differs from ImageJ";
  const auto area = ij.column("Area"), x = ij.column("X"), y = ij.column("Y");
  const auto perim = ij.column("Perim."), feret = ij.column("Feret"),
             min_feret = ij.column("MinFeret"), circ = ij.column("Circ."),
             solidity = ij.column("Solidity"), major = ij.column("Major"),
             minor = ij.column("Minor");
  for (std::size_t i = 0; i < ij.rows.size(); ++i) {
    // Match by centroid: the two programs number particles in the same raster order, but the
    // match must not depend on that.
    auto m = std::min_element(ours.begin(), ours.end(), [&](const auto& a, const auto& b) {
      return std::hypot(a.centroid.x - x[i], a.centroid.y - y[i]) <
             std::hypot(b.centroid.x - x[i], b.centroid.y - y[i]);
    });
    SCOPED_TRACE(image + " ImageJ particle " + std::to_string(i + 1));
    ASSERT_LT(std::hypot(m->centroid.x - x[i], m->centroid.y - y[i]), 1e-2);
    // ImageJ prints 3 decimals: tolerances of half a unit in the last place (5e-4), relative
    // where the value can exceed 100.
    EXPECT_DOUBLE_EQ(m->area, area[i]);  // pixel count, exact
    EXPECT_NEAR(m->perimeter, perim[i], 5e-4 + 1e-6 * perim[i]);
    EXPECT_NEAR(m->feret.max, feret[i], 5e-4);
    EXPECT_NEAR(m->feret.min, min_feret[i], 5e-4);
    EXPECT_NEAR(m->circularity, circ[i], 5e-4);
    EXPECT_NEAR(m->solidity, solidity[i], 5e-4);
    EXPECT_NEAR(m->ellipse_major, major[i], 5e-4);
    EXPECT_NEAR(m->ellipse_minor, minor[i], 5e-4);
  }
}

TEST(ImageJAgreement, KnownShapes) {
  compare_with_imagej("shapes.pgm", "shapes_imagej.csv");
}

TEST(ImageJAgreement, Blobs) {
  compare_with_imagej("blobs_raw.pgm", "blobs_raw_imagej.csv");
}

}  // namespace
}  // namespace shapepress::imaging
