#include "geometry/template_quality.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace shapepress::geometry {
namespace {

// Fibonacci points on the unit sphere: near-uniform, deterministic.
std::vector<Vec3> fibonacci_sphere(int count) {
  std::vector<Vec3> points;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count;
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    points.emplace_back(s * std::cos(golden * i), s * std::sin(golden * i), z);
  }
  return points;
}

// Signed distance to a union of spheres: exact outside, the deepest ball's depth inside.
double union_distance(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                      const Vec3& p) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < centres.size(); ++i)
    d = std::min(d, (p - centres[i]).norm() - radii[i]);
  return d;
}

Vec3 extents_along(const std::vector<Vec3>& points, const std::vector<double>& pad,
                   const Mat3& axes) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 q = axes.transpose() * points[i];
    const double r = pad.empty() ? 0.0 : pad[i];
    lo = lo.cwiseMin(q - Vec3::Constant(r));
    hi = hi.cwiseMax(q + Vec3::Constant(r));
  }
  return hi - lo;
}

}  // namespace

namespace {

// Cells of a regular grid over the union's box, `pad` wider on every side: 1 where the cell's
// centre lies in some ball.
struct VoxelGrid {
  Vec3 origin = Vec3::Zero();  // centre of cell (0, 0, 0)
  double h = 0.0;              // cell size
  Eigen::Vector3i n = Eigen::Vector3i::Zero();
  std::vector<char> inside;
  std::size_t index(std::size_t i, std::size_t j, std::size_t k) const {
    return (i * static_cast<std::size_t>(n.y()) + j) * static_cast<std::size_t>(n.z()) + k;
  }
};

VoxelGrid voxelise_union(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                         int cells, double pad, double finest = 0.0) {
  Aabb box{Vec3::Constant(std::numeric_limits<double>::infinity()),
           Vec3::Constant(-std::numeric_limits<double>::infinity())};
  for (std::size_t i = 0; i < centres.size(); ++i) {
    box.lower = box.lower.cwiseMin(centres[i] - Vec3::Constant(radii[i]));
    box.upper = box.upper.cwiseMax(centres[i] + Vec3::Constant(radii[i]));
  }
  VoxelGrid g;
  g.h = std::max((box.size().maxCoeff() + 2.0 * pad) / cells, finest);
  if (pad > 0.0) pad += 2.0 * g.h;
  box.lower -= Vec3::Constant(pad);
  box.upper += Vec3::Constant(pad);
  g.n = (box.size() / g.h).array().ceil().cast<int>().max(1).matrix();
  g.origin = box.lower + Vec3::Constant(0.5 * g.h);
  g.inside.assign(static_cast<std::size_t>(g.n.x()) * static_cast<std::size_t>(g.n.y()) *
                      static_cast<std::size_t>(g.n.z()),
                  0);
  for (std::size_t s = 0; s < centres.size(); ++s) {
    const Vec3 c = (centres[s] - g.origin) / g.h;
    const double r = radii[s] / g.h;
    // Rows of cells along z: each (i, j) column crosses the ball in one interval of k, so a
    // ball costs (2r/h)² instead of (2r/h)³.
    const int i0 = std::max(0, static_cast<int>(std::ceil(c.x() - r)));
    const int i1 = std::min(g.n.x() - 1, static_cast<int>(std::floor(c.x() + r)));
    const int j0 = std::max(0, static_cast<int>(std::ceil(c.y() - r)));
    const int j1 = std::min(g.n.y() - 1, static_cast<int>(std::floor(c.y() + r)));
    for (int i = i0; i <= i1; ++i)
      for (int j = j0; j <= j1; ++j) {
        const double rest = r * r - (i - c.x()) * (i - c.x()) - (j - c.y()) * (j - c.y());
        if (rest < 0.0) continue;
        const double half = std::sqrt(rest);
        const int k0 = std::max(0, static_cast<int>(std::ceil(c.z() - half)));
        const int k1 = std::min(g.n.z() - 1, static_cast<int>(std::floor(c.z() + half)));
        if (k0 > k1) continue;
        char* row = &g.inside[g.index(static_cast<std::size_t>(i), static_cast<std::size_t>(j), 0)];
        std::fill(row + k0, row + k1 + 1, char{1});
      }
  }
  return g;
}

// Squared Euclidean distance (in cells²) from every cell to the nearest cell where `target` is
// 1 (Felzenszwalb & Huttenlocher 2012: the lower envelope of parabolas, one axis at a time).
std::vector<float> squared_distance_to(const VoxelGrid& g, const std::vector<char>& target) {
  constexpr double far = 1e20;
  std::vector<float> d(target.size());
  for (std::size_t c = 0; c < target.size(); ++c)
    d[c] = target[c] ? 0.0f : static_cast<float>(far);
  const std::array<std::size_t, 3> n = {static_cast<std::size_t>(g.n.x()),
                                        static_cast<std::size_t>(g.n.y()),
                                        static_cast<std::size_t>(g.n.z())};
  const std::array<std::size_t, 3> stride = {n[1] * n[2], n[2], 1};
  std::vector<double> f, out;
  std::vector<std::size_t> v;
  std::vector<double> z;
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t len = n[axis];
    f.resize(len), out.resize(len), v.resize(len), z.resize(len + 1);
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    for (std::size_t p = 0; p < n[a]; ++p)
      for (std::size_t q = 0; q < n[b]; ++q) {
        const std::size_t base = p * stride[a] + q * stride[b];
        for (std::size_t x = 0; x < len; ++x)
          f[x] = d[base + x * stride[axis]];
        std::size_t k = 0;
        v[0] = 0;
        z[0] = -far, z[1] = far;
        for (std::size_t x = 1; x < len; ++x) {
          const auto xd = static_cast<double>(x);
          for (;;) {
            const auto vk = static_cast<double>(v[k]);
            const double s = ((f[x] + xd * xd) - (f[v[k]] + vk * vk)) / (2.0 * (xd - vk));
            if (s <= z[k] && k > 0) {
              --k;
              continue;
            }
            if (s <= z[k]) {  // k == 0: the new parabola lies below the first everywhere
              v[0] = x;
              z[0] = -far, z[1] = far;
              break;
            }
            ++k;
            v[k] = x, z[k] = s, z[k + 1] = far;
            break;
          }
        }
        k = 0;
        for (std::size_t x = 0; x < len; ++x) {
          const auto xd = static_cast<double>(x);
          while (z[k + 1] < xd)
            ++k;
          const auto vk = static_cast<double>(v[k]);
          out[x] = (xd - vk) * (xd - vk) + f[v[k]];
        }
        for (std::size_t x = 0; x < len; ++x)
          d[base + x * stride[axis]] = static_cast<float>(out[x]);
      }
  }
  return d;
}

MassProperties grid_mass_properties(const VoxelGrid& g, const std::vector<char>& inside) {
  MassProperties props;
  double count = 0.0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  for (std::size_t i = 0; i < static_cast<std::size_t>(g.n.x()); ++i)
    for (std::size_t j = 0; j < static_cast<std::size_t>(g.n.y()); ++j)
      for (std::size_t k = 0; k < static_cast<std::size_t>(g.n.z()); ++k) {
        if (!inside[g.index(i, j, k)]) continue;
        const Vec3 q(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
        count += 1.0;
        first += q;
        second += q * q.transpose();
      }
  if (count == 0.0) return props;
  const double cell_volume = g.h * g.h * g.h;
  props.volume = count * cell_volume;
  const Vec3 mean = first / count;
  props.centre = g.origin + g.h * mean;
  // Each cell's own second moment h²/12 per axis is added back (midpoint rule of a cube).
  const Mat3 covariance =
      g.h * g.h * (second / count - mean * mean.transpose() + Mat3::Identity() / 12.0);
  const Mat3 moments = props.volume * covariance;
  props.inertia = moments.trace() * Mat3::Identity() - moments;
  diagonalise(props);
  return props;
}

}  // namespace

MassProperties union_mass_properties(const std::vector<Vec3>& centres,
                                     const std::vector<double>& radii, int cells) {
  if (centres.empty()) return {};
  const VoxelGrid g = voxelise_union(centres, radii, cells, 0.0);
  return grid_mass_properties(g, g.inside);
}

MassProperties closed_union_mass_properties(const std::vector<Vec3>& centres,
                                            const std::vector<double>& radii, double probe_radius,
                                            int cells) {
  if (centres.empty()) return {};
  if (!(probe_radius > 0.0)) return union_mass_properties(centres, radii, cells);
  // Two probe radii around the union: every cell a probe's centre can reach near the union is in
  // the grid, so the erosion sees them all.
  // Cells of a sixteenth of the probe resolve the closing of a tight cluster within about 1 %
  // (13 touching spheres: 1.9 % at a twelfth, 0.1 % at a twentieth), of a random packing better
  // (the Avicel bodies: 0.2 % between a fifth and a twelfth); a finer grid only costs, and
  // `cells` caps it along the longest side.
  const VoxelGrid g =
      voxelise_union(centres, radii, cells, 2.0 * probe_radius, probe_radius / 16.0);
  // Closing: the cells within the probe radius of the union (where a probe's centre cannot go),
  // then of those the cells farther than the probe radius from every cell a probe's centre can
  // reach. What remains is the union with every pore and crevice a probe cannot enter filled.
  const double probe_cells = probe_radius / g.h;
  const double probe_squared = probe_cells * probe_cells;
  const std::vector<float> to_union = squared_distance_to(g, g.inside);
  std::vector<char> reachable(g.inside.size());
  for (std::size_t c = 0; c < reachable.size(); ++c)
    reachable[c] = to_union[c] > probe_squared ? 1 : 0;
  const std::vector<float> to_reachable = squared_distance_to(g, reachable);
  std::vector<char> closed(g.inside.size());
  for (std::size_t c = 0; c < closed.size(); ++c)
    closed[c] = to_reachable[c] > probe_squared ? 1 : 0;
  return grid_mass_properties(g, closed);
}

MassProperties sphere_sum_mass_properties(const std::vector<Vec3>& centres,
                                          const std::vector<double>& radii) {
  MassProperties props;
  Vec3 first = Vec3::Zero();
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const double v = 4.0 / 3.0 * std::numbers::pi * std::pow(radii[i], 3);
    props.volume += v;
    first += v * centres[i];
  }
  if (props.volume == 0.0) return props;
  props.centre = first / props.volume;
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const double v = 4.0 / 3.0 * std::numbers::pi * std::pow(radii[i], 3);
    const Vec3 d = centres[i] - props.centre;
    props.inertia += 0.4 * v * radii[i] * radii[i] * Mat3::Identity() +
                     v * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
  }
  diagonalise(props);
  return props;
}

MassProperties ellipsoid_mass_properties(const Vec3& e, const Vec3& centre) {
  MassProperties props;
  props.volume = 4.0 / 3.0 * std::numbers::pi * e.prod();
  props.centre = centre;
  const Vec3 sq = e.cwiseProduct(e);
  props.inertia =
      (props.volume / 5.0 * Vec3(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y())).asDiagonal();
  diagonalise(props);
  return props;
}

MassProperties template_mass_properties(const SphereTemplate& spheres, int integration_cells) {
  return spheres.kind == TemplateKind::bonded
             ? sphere_sum_mass_properties(spheres.centres, spheres.radii)
             : union_mass_properties(spheres.centres, spheres.radii, integration_cells);
}

FillQuality assess_fill(const SphereTemplate& spheres, const SignedDistance& shape,
                        const MassProperties& shape_props, const QualityOptions& options) {
  FillQuality q;
  const auto& c = spheres.centres;
  const auto& r = spheres.radii;
  q.sphere_count = static_cast<int>(c.size());
  q.min_radius_m = *std::min_element(r.begin(), r.end());
  q.max_radius_m = *std::max_element(r.begin(), r.end());
  q.bond_count = static_cast<int>(spheres.bonds.size());
  q.mean_coordination = 2.0 * q.bond_count / std::max(1, q.sphere_count);
  q.connected = spheres.kind == TemplateKind::rigid || is_connected(c.size(), spheres.bonds);

  const MassProperties u = template_mass_properties(spheres, options.integration_cells);
  q.volume_fraction = u.volume / shape_props.volume;
  q.volume_error = std::abs(q.volume_fraction - 1.0);
  const Vec3 g_union = u.principal_moments / u.volume;
  const Vec3 g_shape = shape_props.principal_moments / shape_props.volume;
  q.inertia_error = ((g_union - g_shape).cwiseAbs().cwiseQuotient(g_shape)).maxCoeff();

  // Shape surface -> union surface.
  const std::vector<Vec3> shape_surface = surface_samples(shape, options.surface_cells);
  double sum_sq = 0.0, worst = 0.0;
  std::vector<double> to_union(shape_surface.size());
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < shape_surface.size(); ++i)
    to_union[i] = std::abs(union_distance(c, r, shape_surface[i]));
  for (double d : to_union) {
    sum_sq += d * d;
    worst = std::max(worst, d);
  }
  // Union surface -> shape surface. The union's surface is its outer envelope: a point on a
  // sub-sphere counts when the ray from it along that sphere's outward normal escapes the two
  // shells of neighbours around it, so the faces touching spheres turn to each other (inside a
  // BMS agglomerate) and the parts buried in overlapping spheres (CMS) are left out.
  const std::vector<Vec3> unit = fibonacci_sphere(options.points_per_sphere);
  const std::vector<Bond> near = pairs_within(c, r, 3.0);
  std::vector<std::vector<std::int32_t>> neighbours(c.size());
  for (const Bond& b : near) {
    neighbours[static_cast<std::size_t>(b[0])].push_back(b[1]);
    neighbours[static_cast<std::size_t>(b[1])].push_back(b[0]);
  }
  auto blocked = [&](std::size_t s, const Vec3& p, const Vec3& u) {
    for (std::int32_t j : neighbours[s]) {
      const auto jj = static_cast<std::size_t>(j);
      const Vec3 to_centre = c[jj] - p;
      const double r2 = r[jj] * r[jj] * (1.0 - 1e-9);
      if (to_centre.squaredNorm() < r2) return true;  // buried inside the neighbour
      const double along = to_centre.dot(u);
      if (along > 0.0 && to_centre.squaredNorm() - along * along < r2) return true;
    }
    return false;
  };
  std::vector<double> to_shape(c.size() * unit.size(), -1.0);
#pragma omp parallel for schedule(dynamic, 16)
  for (std::size_t s = 0; s < c.size(); ++s)
    for (std::size_t k = 0; k < unit.size(); ++k) {
      const Vec3 p = c[s] + r[s] * unit[k];
      if (!blocked(s, p, unit[k])) to_shape[s * unit.size() + k] = std::abs(shape(p));
    }
  std::size_t union_samples = 0;
  for (double d : to_shape) {
    if (d < 0.0) continue;
    sum_sq += d * d;
    worst = std::max(worst, d);
    ++union_samples;
  }
  const double total = static_cast<double>(shape_surface.size() + union_samples);
  q.surface_rms_m = std::sqrt(sum_sq / std::max(total, 1.0));
  q.hausdorff_m = worst;
  const double d_eq = std::cbrt(6.0 * shape_props.volume / std::numbers::pi);
  q.surface_rms_relative = q.surface_rms_m / d_eq;
  q.hausdorff_relative = q.hausdorff_m / d_eq;

  // Extents along the shape's principal axes (largest first).
  const Mat3 axes = shape_props.principal_axes;  // ascending moments: longest axis first
  q.shape_extents = extents_along(shape_surface, {}, axes);
  q.union_extents = extents_along(c, r, axes);
  q.extent_error =
      ((q.union_extents - q.shape_extents).cwiseAbs().cwiseQuotient(q.shape_extents)).maxCoeff();
  return q;
}

}  // namespace shapepress::geometry
