// CMS filler (sphere_fill.hpp): a greedy cover of the voxelised interior by inscribed balls.
#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "common/error.hpp"
#include "geometry/sphere_fill.hpp"
#include "geometry/template_quality.hpp"

namespace shapepress::geometry {
namespace {

struct InteriorGrid {
  Vec3 origin;   // centre of cell (0, 0, 0)
  double h = 0;  // cell size
  Eigen::Vector3i n;
  std::vector<double> depth;  // -distance at cell centres; <= 0 outside
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(i) * static_cast<std::size_t>(n.y()) +
            static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(n.z()) +
           static_cast<std::size_t>(k);
  }
  Vec3 centre(std::size_t id) const {
    const auto nz = static_cast<std::size_t>(n.z()), ny = static_cast<std::size_t>(n.y());
    const auto k = id % nz, j = (id / nz) % ny, i = id / (nz * ny);
    return origin +
           h * Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
  }
};

InteriorGrid sample_interior(const SignedDistance& shape, int resolution) {
  InteriorGrid grid;
  const Vec3 size = shape.bounds.size();
  grid.h = size.maxCoeff() / resolution;
  grid.n = ((size / grid.h).array().ceil().cast<int>() + 1).matrix();
  grid.origin = shape.bounds.lower + 0.5 * (size - grid.h * (grid.n.cast<double>() - Vec3::Ones()));
  grid.depth.assign(static_cast<std::size_t>(grid.n.prod()), 0.0);
#pragma omp parallel for schedule(static)
  for (int i = 0; i < grid.n.x(); ++i)
    for (int j = 0; j < grid.n.y(); ++j)
      for (int k = 0; k < grid.n.z(); ++k) {
        const std::size_t id = grid.index(i, j, k);
        grid.depth[id] = -shape(grid.centre(id));
      }
  return grid;
}

// The largest inscribed ball that still contains p: walk from p against the outward normal,
// c(t) = p - t n, while the ball at c(t) (radius = depth there) reaches back to p.
std::pair<Vec3, double> maximal_ball_through(const SignedDistance& shape, const Vec3& p, double h) {
  Vec3 n = shape.gradient(p, 0.5 * h);
  const double norm = n.norm();
  double best_r = -shape(p);
  Vec3 best_c = p;
  if (norm == 0.0) return {best_c, best_r};
  n /= norm;
  const double step = 0.25 * h;
  for (double t = step;; t += step) {
    const Vec3 c = p - t * n;
    const double r = -shape(c);
    if (r < t - 0.25 * h) break;  // the ball no longer covers p: past the medial axis
    if (r > best_r) {
      best_r = r;
      best_c = c;
    }
  }
  return {best_c, best_r};
}

// Bisection on a common radius increment δ ≥ 0 so that V(union of r_i + δ) = V_shape, both
// measured by voxels of the same size.
void match_union_volume(SphereTemplate& spheres, double shape_volume, int resolution) {
  const std::vector<double> base = spheres.radii;
  auto volume_with = [&](double delta) {
    std::vector<double> grown = base;
    for (double& r : grown)
      r += delta;
    return union_mass_properties(spheres.centres, grown, resolution).volume;
  };
  double lo = 0.0, hi = 0.25 * *std::max_element(base.begin(), base.end());
  if (volume_with(lo) >= shape_volume) return;
  while (volume_with(hi) < shape_volume)
    hi *= 2.0;
  for (int iteration = 0; iteration < 24; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (volume_with(mid) < shape_volume ? lo : hi) = mid;
  }
  for (std::size_t i = 0; i < base.size(); ++i)
    spheres.radii[i] = base[i] + 0.5 * (lo + hi);
}

}  // namespace

SphereTemplate fill_rigid(const SignedDistance& shape, const RigidFillOptions& options) {
  options.check();
  const InteriorGrid grid = sample_interior(shape, options.resolution);
  std::vector<std::size_t> interior;
  for (std::size_t id = 0; id < grid.depth.size(); ++id)
    if (grid.depth[id] > 0.0) interior.push_back(id);
  if (interior.empty())
    throw ComputationError(
        fmt::format("{} has no interior at {} cells per side: refine the "
                    "resolution",
                    shape.description, options.resolution));
  // Deepest first; ties broken by index so the order is deterministic.
  std::stable_sort(interior.begin(), interior.end(),
                   [&](std::size_t a, std::size_t b) { return grid.depth[a] > grid.depth[b]; });
  std::vector<char> covered(grid.depth.size(), 0);
  SphereTemplate result;
  result.kind = TemplateKind::rigid;
  double r_max = 0.0;
  std::size_t cursor = 0;
  while (result.centres.size() < static_cast<std::size_t>(options.sphere_count)) {
    while (cursor < interior.size() && covered[interior[cursor]])
      ++cursor;
    if (cursor == interior.size()) break;
    const std::size_t seed_cell = interior[cursor];
    auto [c, r] = maximal_ball_through(shape, grid.centre(seed_cell), grid.h);
    r_max = std::max(r_max, r);
    const double r_min = options.min_radius_fraction * r_max;
    covered[seed_cell] = 1;
    if (r < std::max(r_min, 0.5 * grid.h)) continue;  // a sliver finer than the grid resolves
    result.centres.push_back(c);
    result.radii.push_back(r);
    const Eigen::Vector3i lo =
        (((c - grid.origin) / grid.h).array() - r / grid.h).floor().cast<int>().max(0).matrix();
    const Eigen::Vector3i hi = (((c - grid.origin) / grid.h).array() + r / grid.h)
                                   .ceil()
                                   .cast<int>()
                                   .min(grid.n.array() - 1)
                                   .matrix();
    for (int i = lo.x(); i <= hi.x(); ++i)
      for (int j = lo.y(); j <= hi.y(); ++j)
        for (int k = lo.z(); k <= hi.z(); ++k) {
          const std::size_t id = grid.index(i, j, k);
          if ((grid.centre(id) - c).squaredNorm() <= r * r) covered[id] = 1;
        }
  }
  if (result.centres.empty())
    throw ComputationError(fmt::format("no sphere fits in {}", shape.description));
  if (options.match_volume)
    match_union_volume(result, static_cast<double>(interior.size()) * grid.h * grid.h * grid.h,
                       options.resolution);
  return result;
}

}  // namespace shapepress::geometry
