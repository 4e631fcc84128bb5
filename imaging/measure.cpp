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

// One unit pixel edge of a traced outline: the inside pixel p and the outside pixel q.
struct BoundaryEdge {
  int px, py, qx, qy;
};

std::vector<BoundaryEdge> boundary_edges(const std::vector<Point2>& corners,
                                         const LabelImage& labels, int label) {
  std::vector<BoundaryEdge> edges;
  auto is_label = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < labels.width && y < labels.height && labels.at(x, y) == label;
  };
  for (std::size_t i = 0, n = corners.size(); i < n; ++i) {
    const Point2& a = corners[i];
    const Point2& b = corners[(i + 1) % n];
    const double length = std::abs(b.x - a.x) + std::abs(b.y - a.y);  // axis-aligned
    const double ux = (b.x - a.x) / length, uy = (b.y - a.y) / length;
    for (double t = 0.5; t < length; t += 1.0) {
      const double mx = a.x + ux * t, my = a.y + uy * t;
      // The two pixels on either side of this unit edge, along its normal (-uy, ux).
      BoundaryEdge e{
          static_cast<int>(std::floor(mx - 0.5 * uy)), static_cast<int>(std::floor(my + 0.5 * ux)),
          static_cast<int>(std::floor(mx + 0.5 * uy)), static_cast<int>(std::floor(my - 0.5 * ux))};
      if (!is_label(e.px, e.py)) e = {e.qx, e.qy, e.px, e.py};
      edges.push_back(e);
    }
  }
  return edges;
}

// The particle's own mid-contrast level: half-way between the intensity two pixels inside
// its outline and two pixels outside, averaged along the outline. Shading that survives the
// background flattening changes the contrast from particle to particle; a global level would
// then move each outline in or out by a fraction of the edge blur.
double local_level(const std::vector<BoundaryEdge>& edges, const LabelImage& labels, int label,
                   const GrayImage& intensity, double global_level) {
  double inside_sum = 0, outside_sum = 0;
  int inside_n = 0, outside_n = 0;
  auto label_at = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < labels.width && y < labels.height ? labels.at(x, y) : -1;
  };
  for (const BoundaryEdge& e : edges) {
    const int dx = e.qx - e.px, dy = e.qy - e.py;
    if (label_at(e.px - 2 * dx, e.py - 2 * dy) == label) {
      inside_sum += intensity.at(e.px - 2 * dx, e.py - 2 * dy);
      ++inside_n;
    }
    if (label_at(e.qx + 2 * dx, e.qy + 2 * dy) == 0) {
      outside_sum += intensity.at(e.qx + 2 * dx, e.qy + 2 * dy);
      ++outside_n;
    }
  }
  constexpr int min_samples = 8;
  if (inside_n < min_samples || outside_n < min_samples) return global_level;
  return 0.5 * (inside_sum / inside_n + outside_sum / outside_n);
}

// Points where the outline crosses from inside to outside: the midpoint of each unit pixel
// edge or, with an intensity image, the point between the two pixel centres where the
// interpolated intensity equals the particle's mid-contrast level. Calipers of the
// pixel-corner outline (ImageJ's Feret) exceed true widths by up to 0.7 px per side
// diagonally and quantise them to whole pixels along the axes; these points do neither.
std::vector<Point2> boundary_crossings(const std::vector<Point2>& corners, const LabelImage& labels,
                                       int label, const GrayImage* intensity, double level) {
  std::vector<BoundaryEdge> edges = boundary_edges(corners, labels, label);
  if (intensity) level = local_level(edges, labels, label, *intensity, level);
  std::vector<Point2> points;
  points.reserve(edges.size());
  for (const BoundaryEdge& e : edges) {
    double f = 0.5;  // fraction of the way from the inside centre to the outside centre
    bool outside_is_background = e.qx >= 0 && e.qy >= 0 && e.qx < labels.width &&
                                 e.qy < labels.height && labels.at(e.qx, e.qy) == 0;
    if (intensity && outside_is_background) {
      double inside_value = intensity->at(e.px, e.py), outside_value = intensity->at(e.qx, e.qy);
      if (inside_value > outside_value)
        f = std::clamp((inside_value - level) / (inside_value - outside_value), 0.0, 1.0);
    }
    points.push_back({e.px + 0.5 + f * (e.qx - e.px), e.py + 0.5 + f * (e.qy - e.py)});
  }
  return points;
}

// Everything that depends only on the outline polygon and the area. `shape_outline` is the
// outline the aspect ratio and the Fourier descriptors are taken from.
void measure_outline(ParticleMeasurement& m, double perimeter,
                     const std::vector<Point2>& shape_outline, bool subpixel) {
  m.perimeter = perimeter;
  m.outline_area = subpixel ? polygon_area(shape_outline) : m.area;
  m.equivalent_diameter = std::sqrt(4.0 * m.outline_area / std::numbers::pi);
  std::vector<Point2> hull = convex_hull(m.outline);
  m.feret = feret_diameters(hull);
  m.feret_imagej_ratio = m.feret.max > 0 ? m.feret.min / m.feret.max : 0.0;
  Feret unbiased = feret_diameters(convex_hull(shape_outline));
  m.aspect_ratio = unbiased.max > 0 ? unbiased.min / unbiased.max : 0.0;
  m.circularity = perimeter > 0
                      ? std::min(1.0, 4.0 * std::numbers::pi * m.area / (perimeter * perimeter))
                      : 0.0;
  double hull_area = polygon_area(hull);
  m.solidity = hull_area > 0 ? std::min(1.0, m.area / hull_area) : 0.0;
  m.convexity = perimeter > 0 ? std::min(1.0, polygon_perimeter(hull) / perimeter) : 0.0;
  m.fourier =
      fourier_descriptors(radius_function(shape_outline, m.centroid), &m.fourier_mean_radius);
}

}  // namespace

std::vector<ParticleMeasurement> measure_particles(const LabelImage& labels,
                                                   const GrayImage* intensity, double level) {
  if (intensity && intensity->empty()) intensity = nullptr;
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
    measure_outline(m, traced_perimeter(m.outline),
                    boundary_crossings(m.outline, labels, l, intensity, level),
                    intensity != nullptr);
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
  measure_outline(m, polygon_perimeter(polygon), polygon, true);
  return m;
}

}  // namespace shapepress::imaging
