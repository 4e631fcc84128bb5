#include "imaging/fourier.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <numeric>

namespace shapepress::imaging {

std::vector<double> radius_function(const std::vector<Point2>& polygon, Point2 centre,
                                    int samples) {
  std::vector<double> radius(samples, 0.0);
  const std::size_t n = polygon.size();
  for (int k = 0; k < samples; ++k) {
    double theta = 2.0 * std::numbers::pi * k / samples;
    double ux = std::cos(theta), uy = std::sin(theta);
    double farthest = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      // Ray centre + t u against segment a + s (b - a): solve with 2D cross products.
      const Point2& a = polygon[i];
      const Point2& b = polygon[(i + 1) % n];
      double ex = b.x - a.x, ey = b.y - a.y;
      double denom = ux * ey - uy * ex;
      if (denom == 0.0) continue;
      double ax = a.x - centre.x, ay = a.y - centre.y;
      double t = (ax * ey - ay * ex) / denom;
      double s = (ax * uy - ay * ux) / denom;
      if (t > 0 && s >= 0 && s <= 1) farthest = std::max(farthest, t);
    }
    radius[k] = farthest;
  }
  return radius;
}

FourierSpectrum fourier_descriptors(const std::vector<double>& radius, double* mean_radius) {
  FourierSpectrum d{};
  const auto samples = static_cast<int>(radius.size());
  const double r0 = std::accumulate(radius.begin(), radius.end(), 0.0) / samples;
  if (mean_radius) *mean_radius = r0;
  if (r0 <= 0) return d;
  d[0] = 1.0;
  for (int order = 1; order <= fourier_max_order && order < samples / 2; ++order) {
    std::complex<double> c = 0.0;
    for (int k = 0; k < samples; ++k)
      c += radius[k] * std::polar(1.0, -2.0 * std::numbers::pi * order * k / samples);
    d[order] = 2.0 * std::abs(c) / samples / r0;
  }
  return d;
}

}  // namespace shapepress::imaging
