// ImageJ's watershed (imaging/imagej_watershed.hpp) on drawn masks: its distance map, where it
// cuts and how wide the cut is. That it is ImageJ's, pixel for pixel, is checked on real images
// against ImageJ's own results (tests/validation/imaging/imagej_real_images_test.cpp).
#include "imaging/imagej_watershed.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace shapepress::imaging {
namespace {

constexpr int width = 48, height = 32;

struct Disc {
  double x, y, r;
};

std::vector<std::uint8_t> discs(const std::vector<Disc>& list) {
  std::vector<std::uint8_t> mask(width * height, 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (const Disc& d : list)
        if (std::hypot(x + 0.5 - d.x, y + 0.5 - d.y) < d.r) mask[y * width + x] = 255;
  return mask;
}

// 8-connected pieces of a mask, labelled from 1.
std::vector<int> pieces(const std::vector<std::uint8_t>& mask, int& count) {
  std::vector<int> label(mask.size(), 0);
  count = 0;
  for (int start = 0; start < width * height; ++start) {
    if (!mask[start] || label[start]) continue;
    label[start] = ++count;
    std::vector<int> stack{start};
    while (!stack.empty()) {
      const int p = stack.back();
      stack.pop_back();
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = p % width + dx, y = p / width + dy;
          if (x < 0 || y < 0 || x >= width || y >= height) continue;
          const int q = y * width + x;
          if (mask[q] && !label[q]) {
            label[q] = count;
            stack.push_back(q);
          }
        }
      }
    }
  }
  return label;
}

TEST(ImageJWatershed, DistanceMapIsEuclidean) {
  const auto mask = discs({{14, 16, 10}, {30, 16, 9}});
  const std::vector<float> edm = imagej_distance_map(mask, width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double nearest = 1e9;
      for (int v = 0; v < height; ++v)
        for (int u = 0; u < width; ++u)
          if (!mask[v * width + u]) nearest = std::min(nearest, std::hypot(u - x, v - y));
      EXPECT_NEAR(edm[y * width + x], mask[y * width + x] ? nearest : 0.0, 1e-5)
          << "at " << x << ", " << y;
    }
  }
}

// Two discs that overlap by a neck: two particles, parted by a line one pixel wide that runs
// only where they meet: every cleared pixel touches both, and there are no more of them than
// the neck is high, plus one for a diagonal step.
TEST(ImageJWatershed, TouchingDiscsArePartedByAOnePixelLine) {
  const auto mask = discs({{14, 16, 10}, {30, 16, 9}});
  const auto kept = imagej_watershed(mask, width, height);
  int count = 0;
  const std::vector<int> label = pieces(kept, count);
  ASSERT_EQ(count, 2);
  int cleared = 0, neck = 0;
  for (int y = 0; y < height; ++y) {
    neck += mask[y * width + 23] != 0 || mask[y * width + 24] != 0;
    for (int x = 0; x < width; ++x) {
      const int p = y * width + x;
      if (!mask[p] || kept[p]) continue;
      ++cleared;
      bool touches[3] = {false, false, false};
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          touches[label[(y + dy) * width + x + dx]] = true;
      EXPECT_TRUE(touches[1] && touches[2]) << "cleared pixel " << x << ", " << y;
    }
  }
  EXPECT_LE(cleared, neck + 1);
}

// Maxima that stand no more than the tolerance above the saddle seed no particle: two discs
// whose centres are 4 px apart make one blob whose distance map dips 0.2 px between them.
TEST(ImageJWatershed, AShallowSaddleIsNoCut) {
  const auto mask = discs({{20, 16, 10}, {24, 16, 10}});
  EXPECT_EQ(imagej_watershed(mask, width, height), mask);
  const auto single = discs({{24, 16, 12}});
  EXPECT_EQ(imagej_watershed(single, width, height), single);
}

}  // namespace
}  // namespace shapepress::imaging
