// The CGAL parts of descriptors.hpp: the optimal bounding box and the convex hull.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/optimal_bounding_box.h>

#include <algorithm>
#include <array>
#include <map>
#include <numeric>

#include "geometry/descriptors.hpp"

namespace shapepress::geometry {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

std::vector<Point> to_points(const std::vector<Vec3>& points) {
  std::vector<Point> out;
  out.reserve(points.size());
  for (const Vec3& p : points)
    out.emplace_back(p.x(), p.y(), p.z());
  return out;
}

}  // namespace

namespace {

// One run of CGAL's optimal-box search (a seeded evolutionary heuristic) as a rotation.
Mat3 optimal_box_rotation(const std::vector<Point>& hull, unsigned seed) {
  Kernel::Aff_transformation_3 transformation;
  CGAL::oriented_bounding_box(hull, transformation,
                              CGAL::parameters::random_seed(seed).use_convex_hull(false));
  Mat3 rotation;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      rotation(i, j) = CGAL::to_double(transformation.m(i, j));
  return rotation;
}

}  // namespace

OrientedBox minimum_oriented_box(const std::vector<Vec3>& points, std::uint64_t seed) {
  std::vector<Point> hull;
  CGAL::extreme_points_3(to_points(points), std::back_inserter(hull));
  // The search is a heuristic: different seeds can settle on different boxes when two sides
  // are nearly equal. The smallest of three runs makes L, I, S stable to the seed.
  constexpr int runs = 3;
  Mat3 rotation = Mat3::Identity();
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  double best_volume = std::numeric_limits<double>::infinity();
  for (int run = 0; run < runs; ++run) {
    const Mat3 r = optimal_box_rotation(hull, static_cast<unsigned>(seed + 7919 * run));
    Vec3 l = Vec3::Constant(std::numeric_limits<double>::infinity()), h = -l;
    for (const Point& p : hull) {
      const Vec3 q = r * Vec3(p.x(), p.y(), p.z());
      l = l.cwiseMin(q);
      h = h.cwiseMax(q);
    }
    if ((h - l).prod() < best_volume) {
      best_volume = (h - l).prod();
      rotation = r;
      lo = l;
      hi = h;
    }
  }
  const Vec3 extents = hi - lo;
  std::array<int, 3> order = {0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int a, int b) { return extents[a] > extents[b]; });
  OrientedBox box;
  for (int k = 0; k < 3; ++k) {
    box.lengths[k] = extents[order[static_cast<std::size_t>(k)]];
    box.axes.col(k) = rotation.row(order[static_cast<std::size_t>(k)]).transpose();
  }
  if (box.axes.determinant() < 0.0) box.axes.col(2) = -box.axes.col(2);
  box.centre = rotation.transpose() * (0.5 * (lo + hi));
  return box;
}

std::vector<std::size_t> convex_hull_vertices(const std::vector<Vec3>& points) {
  const std::vector<Point> cgal_points = to_points(points);
  std::vector<Point> extreme;
  CGAL::extreme_points_3(cgal_points, std::back_inserter(extreme));
  std::map<std::array<double, 3>, std::size_t> index;
  for (std::size_t i = 0; i < points.size(); ++i)
    index.try_emplace({points[i].x(), points[i].y(), points[i].z()}, i);
  std::vector<std::size_t> ids;
  for (const Point& p : extreme)
    ids.push_back(index.at({p.x(), p.y(), p.z()}));
  std::sort(ids.begin(), ids.end());
  return ids;
}

double convex_hull_volume(const std::vector<Vec3>& points) {
  const std::vector<Point> cgal_points = to_points(points);
  CGAL::Surface_mesh<Point> hull;
  CGAL::convex_hull_3(cgal_points.begin(), cgal_points.end(), hull);
  // The hull's faces come in an order that follows CGAL's random state, which differs from call
  // to call in one process and from thread to thread; summed in an order of their own (each face
  // from its least vertex, the faces sorted) the volume has the same bits every time, so a
  // resumed generate describes a particle as the uninterrupted run did.
  std::vector<std::array<double, 9>> faces;
  for (const auto face : hull.faces()) {
    std::array<Point, 3> corner;
    std::size_t k = 0;
    for (const auto vertex : CGAL::vertices_around_face(hull.halfedge(face), hull))
      if (k < 3) corner[k++] = hull.point(vertex);
    std::rotate(corner.begin(), std::min_element(corner.begin(), corner.end()), corner.end());
    faces.push_back({corner[0].x(), corner[0].y(), corner[0].z(), corner[1].x(), corner[1].y(),
                     corner[1].z(), corner[2].x(), corner[2].y(), corner[2].z()});
  }
  std::sort(faces.begin(), faces.end());
  double six_volume = 0.0;  // Σ a · (b × c): the tetrahedra from the origin to each face
  for (const std::array<double, 9>& f : faces)
    six_volume += f[0] * (f[4] * f[8] - f[5] * f[7]) + f[1] * (f[5] * f[6] - f[3] * f[8]) +
                  f[2] * (f[3] * f[7] - f[4] * f[6]);
  return six_volume / 6.0;
}

}  // namespace shapepress::geometry
