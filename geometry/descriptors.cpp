#include "geometry/descriptors.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/random.hpp"

namespace shapepress::geometry {
namespace {

using Vec2 = Eigen::Vector2d;

double cross(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

// Andrew's monotone chain; counter-clockwise, no collinear points.
std::vector<Vec2> convex_hull_2d(std::vector<Vec2> p) {
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (p.size() < 3) return p;
  std::vector<Vec2> hull(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0.0)
      --k;
    hull[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], p[i]) <= 0.0)
      --k;
    hull[k++] = p[i];
  }
  hull.resize(k - 1);
  return hull;
}

}  // namespace

Feret projected_feret(const std::vector<Vec3>& points, const Vec3& direction) {
  const Vec3 d = direction.normalized();
  const Vec3 u = d.unitOrthogonal();
  const Vec3 v = d.cross(u);
  std::vector<Vec2> projected;
  projected.reserve(points.size());
  for (const Vec3& p : points)
    projected.emplace_back(p.dot(u), p.dot(v));
  const std::vector<Vec2> hull = convex_hull_2d(std::move(projected));
  Feret feret;
  const std::size_t n = hull.size();
  if (n < 3) return feret;
  feret.min = std::numeric_limits<double>::infinity();
  // Max: the hull's diameter. Min: the smallest width, attained with one side flush on an edge.
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = hull[i];
    const Vec2& b = hull[(i + 1) % n];
    const double length = (b - a).norm();
    double width = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
      width = std::max(width, std::abs(cross(a, b, hull[j])) / length);
      feret.max = std::max(feret.max, (hull[j] - a).norm());
    }
    feret.min = std::min(feret.min, width);
  }
  return feret;
}

ShapeDescriptors describe(const TriangleMesh& mesh, const DescribeOptions& options) {
  ShapeDescriptors d;
  d.volume_m3 = signed_volume(mesh);
  d.area_m2 = surface_area(mesh);
  const OrientedBox box = minimum_oriented_box(mesh.vertices, options.seed);
  d.L_m = box.lengths[0];
  d.I_m = box.lengths[1];
  d.S_m = box.lengths[2];
  d.asr = d.S_m / d.L_m;         // Eq. 8
  d.elongation = d.I_m / d.L_m;  // Eq. 9
  d.flatness = d.S_m / d.I_m;    // Eq. 9
  d.sphericity = std::cbrt(std::numbers::pi) * std::pow(6.0 * d.volume_m3, 2.0 / 3.0) / d.area_m2;
  d.convexity = d.volume_m3 / convex_hull_volume(mesh.vertices);
  d.volume_equivalent_diameter_m = std::cbrt(6.0 * d.volume_m3 / std::numbers::pi);
  d.projected_equivalent_diameter_m = std::sqrt(d.area_m2 / std::numbers::pi);
  std::vector<Vec3> hull;
  for (std::size_t i : convex_hull_vertices(mesh.vertices))
    hull.push_back(mesh.vertices[i]);
  Rng rng(options.seed);
  double sum = 0.0, sum_sq = 0.0;
  for (int k = 0; k < options.directions; ++k) {
    const double ratio = projected_feret(hull, random_direction(rng)).ratio();
    d.projected_asr.push_back(ratio);
    sum += ratio;
    sum_sq += ratio * ratio;
  }
  const double n = std::max(1, options.directions);
  d.projected_asr_mean = sum / n;
  d.projected_asr_std =
      std::sqrt(std::max(0.0, sum_sq / n - d.projected_asr_mean * d.projected_asr_mean));
  return d;
}

const std::array<std::string_view, descriptor_scalar_count> descriptor_scalar_names = {
    "volume_m3",
    "area_m2",
    "L_m",
    "I_m",
    "S_m",
    "asr",
    "elongation",
    "flatness",
    "sphericity",
    "convexity",
    "volume_equivalent_diameter_m",
    "projected_equivalent_diameter_m",
    "projected_asr_mean",
    "projected_asr_std"};

std::array<double*, descriptor_scalar_count> descriptor_scalars(ShapeDescriptors& d) {
  return {&d.volume_m3,
          &d.area_m2,
          &d.L_m,
          &d.I_m,
          &d.S_m,
          &d.asr,
          &d.elongation,
          &d.flatness,
          &d.sphericity,
          &d.convexity,
          &d.volume_equivalent_diameter_m,
          &d.projected_equivalent_diameter_m,
          &d.projected_asr_mean,
          &d.projected_asr_std};
}

}  // namespace shapepress::geometry
