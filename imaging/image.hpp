#pragma once
// Plain image types shared by the imaging stage. OpenCV stays inside the .cpp files: these are
// the values that cross the library's API.
#include <cstdint>
#include <vector>

namespace shapepress::imaging {

// A grayscale image with intensities scaled to [0, 1], row-major, y down (image convention).
struct GrayImage {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;

  GrayImage() = default;
  GrayImage(int w, int h, float value = 0.0f)
      : width(w), height(h), pixels(static_cast<std::size_t>(w) * h, value) {}
  float& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  float at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
  bool empty() const { return width <= 0 || height <= 0; }
};

// One label per pixel: 0 is background, 1..count are particles.
struct LabelImage {
  int width = 0;
  int height = 0;
  int count = 0;
  std::vector<std::int32_t> labels;

  std::int32_t at(int x, int y) const { return labels[static_cast<std::size_t>(y) * width + x]; }
};

struct Point2 {
  double x = 0.0;
  double y = 0.0;
};

}  // namespace shapepress::imaging
