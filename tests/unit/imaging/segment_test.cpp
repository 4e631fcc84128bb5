// Segmentation steps on small drawn scenes: the neck criterion of the split, polarity,
// hole filling, edge exclusion and the size filter.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "common/error.hpp"
#include "imaging/load.hpp"
#include "imaging/segment.hpp"

namespace shapepress::imaging {
namespace {

struct Disc {
  double x, y, r;
};

std::vector<std::uint8_t> disc_mask(int w, int h, const std::vector<Disc>& discs) {
  std::vector<std::uint8_t> mask(w * h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (const Disc& d : discs)
        if (std::hypot(x + 0.5 - d.x, y + 0.5 - d.y) < d.r) mask[y * w + x] = 1;
  return mask;
}

GrayImage render(int w, int h, const std::vector<Disc>& discs, float particle, float background) {
  auto mask = disc_mask(w, h, discs);
  GrayImage image(w, h);
  for (int i = 0; i < w * h; ++i)
    image.pixels[i] = mask[i] ? particle : background;
  return image;
}

TEST(Split, TouchingDiscsOfUnequalSizeAreTwo) {
  // R = 30 and R = 15 overlapping by 1.5 px: the neck is far narrower than the small disc.
  auto mask = disc_mask(160, 100, {{50, 50, 30}, {50 + 30 + 15 - 1.5, 50, 15}});
  EXPECT_EQ(split_touching_particles(mask, 160, 100, 0.75).count, 2);
}

TEST(Split, WideNeckStaysOne) {
  // Two discs of R = 20 whose centres are 16 px apart: the waist is 2·√(20² − 8²) = 36.7 px
  // wide, nearly the full diameter — one particle.
  auto mask = disc_mask(120, 100, {{50, 50, 20}, {66, 50, 20}});
  EXPECT_EQ(split_touching_particles(mask, 120, 100, 0.75).count, 1);
}

TEST(Split, NeckThresholdIsTheTunedRatio) {
  // Centres 32 px apart, R = 20: neck half-width √(20² − 16²) = 12 px = 0.6 R. A ratio of 0.5
  // keeps it whole, 0.75 splits it.
  auto mask = disc_mask(120, 100, {{44, 50, 20}, {76, 50, 20}});
  EXPECT_EQ(split_touching_particles(mask, 120, 100, 0.5).count, 1);
  EXPECT_EQ(split_touching_particles(mask, 120, 100, 0.75).count, 2);
}

TEST(Split, EllipseIsNotCutAlongItsRidge) {
  std::vector<std::uint8_t> mask(200 * 100, 0);
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 200; ++x)
      if (std::pow((x + 0.5 - 100) / 80, 2) + std::pow((y + 0.5 - 50) / 20, 2) < 1)
        mask[y * 200 + x] = 1;
  EXPECT_EQ(split_touching_particles(mask, 200, 100, 0.75).count, 1);
}

TEST(Segment, PolarityIsDetectedEitherWay) {
  std::vector<Disc> discs = {{40, 40, 15}, {100, 60, 20}};
  SegmentOptions options;
  Segmentation bright = segment_particles(render(160, 120, discs, 0.8f, 0.2f), options);
  EXPECT_TRUE(bright.bright_particles);
  EXPECT_EQ(bright.labels.count, 2);
  Segmentation dark = segment_particles(render(160, 120, discs, 0.2f, 0.8f), options);
  EXPECT_FALSE(dark.bright_particles);
  EXPECT_EQ(dark.labels.count, 2);
  options.polarity = Polarity::bright;  // forcing the wrong polarity finds the background
  EXPECT_NE(segment_particles(render(160, 120, discs, 0.2f, 0.8f), options).labels.count, 2);
}

TEST(Segment, HolesAreFilledAndEdgeParticlesExcluded) {
  GrayImage image = render(160, 120, {{60, 60, 25}, {158, 60, 15}}, 0.9f, 0.1f);
  for (int y = 55; y < 65; ++y)
    for (int x = 55; x < 65; ++x)
      image.at(x, y) = 0.1f;  // a hole in the first particle
  SegmentOptions options;
  Segmentation s = segment_particles(image, options);
  ASSERT_EQ(s.labels.count, 1);
  EXPECT_EQ(s.excluded_on_edge, 1);
  int area = 0;
  for (auto l : s.labels.labels)
    area += l == 1;
  EXPECT_NEAR(area, std::numbers::pi * 25 * 25, 0.02 * std::numbers::pi * 625);  // hole filled
  options.exclude_edges = false;
  EXPECT_EQ(segment_particles(image, options).labels.count, 2);
}

TEST(Segment, SizeFilterAndThresholdMethods) {
  GrayImage image = render(160, 120, {{40, 40, 3}, {100, 60, 20}}, 0.9f, 0.1f);
  for (ThresholdMethod method : {ThresholdMethod::otsu, ThresholdMethod::triangle,
                                 ThresholdMethod::fixed, ThresholdMethod::adaptive}) {
    SegmentOptions options;
    options.denoise = Denoise::none;  // a two-level image: every method finds the same edges
    options.threshold = method;
    options.min_area_px = 50;  // the r = 3 speck (28 px) is dropped
    Segmentation s = segment_particles(image, options);
    EXPECT_EQ(s.labels.count, 1) << to_string(method);
    EXPECT_EQ(s.excluded_by_size, 1) << to_string(method);
  }
}

TEST(Segment, UnevenIlluminationIsFlattened) {
  // A ramp from 0.0 to 0.6 across the image under particles of contrast 0.3: a global
  // threshold without flattening merges the bright side's background with the particles.
  std::vector<Disc> discs = {{30, 40, 12}, {90, 80, 14}, {150, 40, 12}, {210, 80, 14}};
  GrayImage image = render(240, 120, discs, 0.3f, 0.0f);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 240; ++x)
      image.at(x, y) += 0.6f * x / 240.0f;
  for (Background background : {Background::quadratic, Background::rolling}) {
    for (Denoise denoise : {Denoise::gaussian, Denoise::median}) {
      SegmentOptions options;
      options.background = background;
      options.rolling_radius_px = 40;  // larger than the particles (radius <= 14)
      options.denoise = denoise;
      options.polarity = Polarity::bright;
      EXPECT_EQ(segment_particles(image, options).labels.count, 4)
          << static_cast<int>(background) << " " << static_cast<int>(denoise);
    }
  }
  SegmentOptions flat_off;
  flat_off.background = Background::none;
  flat_off.polarity = Polarity::bright;
  EXPECT_NE(segment_particles(image, flat_off).labels.count, 4);  // the test can fail
}

TEST(Segment, BadOptionsNameTheField) {
  SegmentOptions options;
  options.split_neck = 1.5;
  try {
    options.check();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--split-neck"), std::string::npos);
  }
  options = SegmentOptions{};
  options.background_min_fraction = 1.5;
  EXPECT_THROW(options.check(), InputError);
}

// ImageJ 1.53t's "Default" levels on real images, as imagej_analyze.ijm printed them
// (tests/data/imaging): objects above 107 (coins.png) and 116 (gravel256.png), and raw blob
// values above 125 in blobs_raw.pgm.
int imagej_level_of(const std::string& file) {
  LoadedImage loaded = load_image(std::string(SHAPEPRESS_TEST_DATA) + "/imaging/" + file);
  GrayImage levels = imagej_8bit_levels(loaded.image, loaded);
  std::array<long, 256> histogram{};
  for (float v : levels.pixels)
    ++histogram[static_cast<std::size_t>(std::lround(v * 255.0f))];
  return imagej_default_threshold(histogram);
}

TEST(Segment, ImageJDefaultThresholdOnRealImages) {
  EXPECT_EQ(imagej_level_of("coins.png"), 107);
  EXPECT_EQ(imagej_level_of("gravel256.png"), 116);
  EXPECT_EQ(imagej_level_of("blobs_raw.pgm"), 125);
}

}  // namespace
}  // namespace shapepress::imaging
