#include "imaging/measure.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace shapepress::imaging {
namespace {

struct RegionSums {
  int first_x = -1, first_y = -1;  // first pixel in raster order: where tracing starts
  double n = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
};

// Moment ellipse with the region's second moments, scaled to the region's area (ImageJ's
// EllipseFitter). Pixel extent adds 1/12 px² to the axial variances.
void fit_ellipse(const RegionSums& s, ParticleMeasurement& m) {
  double mx = s.sx / s.n, my = s.sy / s.n;
  double xx = s.sxx / s.n - mx * mx + 1.0 / 12.0;
  double yy = s.syy / s.n - my * my + 1.0 / 12.0;
  double xy = s.sxy / s.n - mx * my;
  double half_sum = 0.5 * (xx + yy), root = std::hypot(0.5 * (xx - yy), xy);
  double major = 4.0 * std::sqrt(half_sum + root);
  double minor = 4.0 * std::sqrt(std::max(half_sum - root, 0.0));
  double scale =
      major * minor > 0 ? std::sqrt(m.area / (std::numbers::pi / 4 * major * minor)) : 1.0;
  m.ellipse_major = major * scale;
  m.ellipse_minor = minor * scale;
  double angle = -0.5 * std::atan2(2.0 * xy, xx - yy) * 180.0 / std::numbers::pi;  // y up
  m.ellipse_angle = angle < 0 ? angle + 180.0 : angle;
}

// Everything that depends only on the outline polygon and the area.
void measure_outline(ParticleMeasurement& m, double perimeter) {
  m.perimeter = perimeter;
  m.equivalent_diameter = std::sqrt(4.0 * m.area / std::numbers::pi);
  std::vector<Point2> hull = convex_hull(m.outline);
  m.feret = feret_diameters(hull);
  m.aspect_ratio = m.feret.max > 0 ? m.feret.min / m.feret.max : 0.0;
  m.circularity = perimeter > 0
                      ? std::min(1.0, 4.0 * std::numbers::pi * m.area / (perimeter * perimeter))
                      : 0.0;
  double hull_area = polygon_area(hull);
  m.solidity = hull_area > 0 ? std::min(1.0, m.area / hull_area) : 0.0;
  m.convexity = perimeter > 0 ? std::min(1.0, polygon_perimeter(hull) / perimeter) : 0.0;
  m.fourier = fourier_descriptors(radius_function(m.outline, m.centroid), &m.fourier_mean_radius);
}

}  // namespace

std::vector<ParticleMeasurement> measure_particles(const LabelImage& labels) {
  std::vector<RegionSums> sums(labels.count + 1);
  for (int y = 0; y < labels.height; ++y) {
    for (int x = 0; x < labels.width; ++x) {
      int l = labels.at(x, y);
      if (l == 0) continue;
      RegionSums& s = sums[l];
      if (s.first_x < 0) {
        s.first_x = x;
        s.first_y = y;
      }
      s.n += 1;
      s.sx += x;
      s.sy += y;
      s.sxx += static_cast<double>(x) * x;
      s.syy += static_cast<double>(y) * y;
      s.sxy += static_cast<double>(x) * y;
    }
  }
  std::vector<ParticleMeasurement> particles(labels.count);
#pragma omp parallel for schedule(dynamic, 4)
  for (int l = 1; l <= labels.count; ++l) {
    const RegionSums& s = sums[l];
    ParticleMeasurement& m = particles[l - 1];
    m.label = l;
    m.area = s.n;
    m.centroid = {s.sx / s.n + 0.5, s.sy / s.n + 0.5};
    auto inside = [&](int x, int y) {
      return x >= 0 && y >= 0 && x < labels.width && y < labels.height && labels.at(x, y) == l;
    };
    m.outline = trace_outline(inside, s.first_x, s.first_y);
    fit_ellipse(s, m);
    measure_outline(m, traced_perimeter(m.outline));
  }
  return particles;
}

ParticleMeasurement measure_polygon(const std::vector<Point2>& polygon) {
  ParticleMeasurement m;
  m.outline = polygon;
  m.area = polygon_area(polygon);
  // Centroid of the polygon's area.
  double cx = 0, cy = 0, twice = 0;
  for (std::size_t i = 0, n = polygon.size(); i < n; ++i) {
    const Point2& a = polygon[i];
    const Point2& b = polygon[(i + 1) % n];
    double c = a.x * b.y - b.x * a.y;
    twice += c;
    cx += (a.x + b.x) * c;
    cy += (a.y + b.y) * c;
  }
  m.centroid = {cx / (3 * twice), cy / (3 * twice)};
  measure_outline(m, polygon_perimeter(polygon));
  return m;
}

}  // namespace shapepress::imaging
