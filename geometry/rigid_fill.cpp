// CMS filler (sphere_fill.hpp): a greedy cover of the voxelised interior by inscribed balls, with
// a cap on the radius of the balls that reach the surface so that N balls are needed.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include <fmt/format.h>

#include "common/error.hpp"
#include "geometry/sphere_fill.hpp"
#include "geometry/template_quality.hpp"

namespace shapepress::geometry {
namespace {

constexpr double no_cap = std::numeric_limits<double>::infinity();

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

// The radius a ball centred at `depth` below the surface may have under the cap: either it
// reaches the surface and is no larger than the cap (the surface is drawn by balls of the cap's
// size), or it stays at least one cap below the surface (it fills the core without smoothing
// the surface). Without a cap (infinity) it is the inscribed radius, the medial-axis cover.
double capped_radius(double depth, double cap) {
  return std::min(depth, std::max(cap, depth - cap));
}

// The largest capped inscribed ball that still contains p: walk from p against the outward
// normal, c(t) = p - t n, while the ball at c(t) reaches back to p. Among equal radii the first
// (shallowest) centre wins, so a capped ball through a point near the surface touches the
// surface there.
std::pair<Vec3, double> capped_ball_through(const SignedDistance& shape, const Vec3& p, double h,
                                            double cap) {
  Vec3 n = shape.gradient(p, 0.5 * h);
  const double norm = n.norm();
  double best_r = capped_radius(-shape(p), cap);
  Vec3 best_c = p;
  if (norm == 0.0) return {best_c, best_r};
  n /= norm;
  const double step = 0.25 * h;
  for (double t = step;; t += step) {
    const Vec3 c = p - t * n;
    const double r = capped_radius(-shape(c), cap);
    if (r < t - 0.25 * h) break;  // the ball no longer covers p: past the medial axis
    // Only a ball that contains p is a candidate: within the walk's tolerance a capped ball
    // deep inside would be taken for p's and cover nothing new.
    if (r > best_r && r >= t) {
      best_r = r;
      best_c = c;
    }
  }
  return {best_c, best_r};
}

struct Cover {
  std::vector<Vec3> centres;
  std::vector<double> radii;
  bool complete = true;  // every interior cell is covered (or a skipped sliver)
};

// Deepest uncovered interior cell first (ties by index, so the order is deterministic): the
// capped ball through it, until every cell is covered or `limit` balls are placed.
Cover greedy_cover(const SignedDistance& shape, const InteriorGrid& grid,
                   const std::vector<std::size_t>& deepest_first, double cap,
                   double min_radius_fraction, std::size_t limit) {
  std::vector<char> covered(grid.depth.size(), 0);
  Cover cover;
  double r_max = 0.0;
  std::size_t cursor = 0;
  for (;;) {
    while (cursor < deepest_first.size() && covered[deepest_first[cursor]])
      ++cursor;
    if (cursor == deepest_first.size()) break;
    if (cover.centres.size() == limit) {
      cover.complete = false;
      break;
    }
    const std::size_t seed_cell = deepest_first[cursor];
    auto [c, r] = capped_ball_through(shape, grid.centre(seed_cell), grid.h, cap);
    r_max = std::max(r_max, r);
    covered[seed_cell] = 1;
    // A sliver finer than the grid resolves.
    if (r < std::max(min_radius_fraction * r_max, 0.5 * grid.h)) continue;
    cover.centres.push_back(c);
    cover.radii.push_back(r);
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
  return cover;
}

// The largest cap for which the cover needs the whole count: infinity when the medial-axis
// cover already does (elongated and irregular shapes), else bisection in log(cap) between a cap
// that needs N balls and one that needs fewer. The count is a step function of the cap, not
// strictly monotone, so the bisection returns a cap at one edge of a step; the cover there is
// cut at N balls and the few cells it leaves are within a step of the next cap's cover.
double cap_for_count(const SignedDistance& shape, const InteriorGrid& grid,
                     const std::vector<std::size_t>& deepest_first,
                     const RigidFillOptions& options) {
  const auto n = static_cast<std::size_t>(options.sphere_count);
  auto needs_all = [&](double cap) {
    return !greedy_cover(shape, grid, deepest_first, cap, options.min_radius_fraction, n).complete;
  };
  if (needs_all(no_cap)) return no_cap;
  double hi = grid.depth[deepest_first.front()];  // the inscribed radius: a cap that never binds
  double lo = 0.5 * hi;
  while (!needs_all(lo)) {
    hi = lo;
    lo *= 0.5;
    if (lo < 0.5 * grid.h)
      throw InputError(fmt::format(
          "{}: {} overlapping spheres need balls finer than the fill grid ({} cells across, cell "
          "{:.4g} m): raise the resolution",
          shape.description, options.sphere_count, options.resolution, grid.h));
  }
  while (hi / lo > 1.0 + 1e-3) {
    const double mid = std::sqrt(lo * hi);
    (needs_all(mid) ? lo : hi) = mid;
  }
  return lo;
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

SphereTemplate fill_rigid(const SignedDistance& shape, const RigidFillOptions& options,
                          RigidFillInfo* info) {
  options.check();
  const auto start = std::chrono::steady_clock::now();
  const InteriorGrid grid = sample_interior(shape, options.resolution);
  // Seeds of the cover: the interior cells deeper than half a cell. The grid does not resolve
  // the shell of cells closer to the surface; asked to cover it, a cap just under the inscribed
  // radius would need one near-whole ball per cell of that shell.
  std::vector<std::size_t> interior;
  std::size_t interior_cells = 0;
  for (std::size_t id = 0; id < grid.depth.size(); ++id) {
    interior_cells += grid.depth[id] > 0.0;
    if (grid.depth[id] > 0.5 * grid.h) interior.push_back(id);
  }
  if (interior.empty())
    throw ComputationError(
        fmt::format("{} has no interior at {} cells per side: refine the "
                    "resolution",
                    shape.description, options.resolution));
  // Deepest first; ties broken by index so the order is deterministic.
  std::stable_sort(interior.begin(), interior.end(),
                   [&](std::size_t a, std::size_t b) { return grid.depth[a] > grid.depth[b]; });
  const double cap =
      options.max_radius > 0.0 ? options.max_radius : cap_for_count(shape, grid, interior, options);
  Cover cover = greedy_cover(shape, grid, interior, cap, options.min_radius_fraction,
                             static_cast<std::size_t>(options.sphere_count));
  if (cover.centres.empty())
    throw ComputationError(fmt::format("no sphere fits in {}", shape.description));
  SphereTemplate result;
  result.kind = TemplateKind::rigid;
  result.centres = std::move(cover.centres);
  result.radii = std::move(cover.radii);
  const double cell_volume = grid.h * grid.h * grid.h;
  if (options.match_volume)
    match_union_volume(result, static_cast<double>(interior_cells) * cell_volume,
                       options.resolution);
  if (info) {
    info->radius_cap = cap;
    info->grid_cell = grid.h;
    info->cover_complete = cover.complete;
    info->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return result;
}

RadialDeviation radial_deviation(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                                 const Vec3& centre, double radius, int directions) {
  RadialDeviation d;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  double sum_sq = 0.0;
  d.max_inward = d.max_outward = 0.0;
  for (int i = 0; i < directions; ++i) {
    // Fibonacci directions: near-uniform over the sphere, deterministic.
    const double z = 1.0 - (2.0 * i + 1.0) / directions;
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Vec3 u(s * std::cos(golden * i), s * std::sin(golden * i), z);
    // Farthest exit of the ray centre + t u from any ball: |centre + t u - c|² = r².
    double reach = 0.0;
    for (std::size_t b = 0; b < centres.size(); ++b) {
      const Vec3 q = centres[b] - centre;
      const double along = q.dot(u);
      const double rest = radii[b] * radii[b] - (q.squaredNorm() - along * along);
      if (rest >= 0.0) reach = std::max(reach, along + std::sqrt(rest));
    }
    const double deviation = reach - radius;
    sum_sq += deviation * deviation;
    d.max_inward = std::max(d.max_inward, -deviation);
    d.max_outward = std::max(d.max_outward, deviation);
  }
  d.rms = std::sqrt(sum_sq / directions);
  d.max_abs = std::max(d.max_inward, d.max_outward);
  return d;
}

}  // namespace shapepress::geometry
