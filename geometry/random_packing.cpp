#include "geometry/random_packing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "common/error.hpp"
#include "geometry/random.hpp"

namespace shapepress::geometry {
namespace {

// Volume of the shape from a grid of `cells` per longest side (cell centres inside).
double grid_volume(const SignedDistance& shape, int cells) {
  const Vec3 size = shape.bounds.size();
  const double h = size.maxCoeff() / cells;
  const Eigen::Vector3i n = (size / h).array().ceil().cast<int>().max(1);
  std::int64_t inside = 0;
  for (int i = 0; i < n.x(); ++i)
    for (int j = 0; j < n.y(); ++j)
      for (int k = 0; k < n.z(); ++k)
        if (shape(shape.bounds.lower + h * (Vec3(i, j, k) + Vec3::Constant(0.5))) < 0.0) ++inside;
  return static_cast<double>(inside) * h * h * h;
}

// Linked cells over the shape's box (cells of side `cell`), rebuilt for each sweep: O(N).
class CellGrid {
 public:
  CellGrid(const Aabb& bounds, double cell) : cell_(cell) {
    lower_ = bounds.lower - Vec3::Constant(cell);
    dims_ = ((bounds.size() + Vec3::Constant(2.0 * cell)) / cell).array().ceil().cast<int>().max(1);
  }
  void build(const std::vector<Vec3>& x) {
    head_.assign(static_cast<std::size_t>(dims_.prod()), -1);
    next_.assign(x.size(), -1);
    for (std::size_t i = x.size(); i-- > 0;) {  // reversed so each cell lists in index order
      const std::int64_t c = index(cell_of(x[i]));
      next_[i] = head_[static_cast<std::size_t>(c)];
      head_[static_cast<std::size_t>(c)] = static_cast<std::int32_t>(i);
    }
  }
  // Calls f(j) for every sphere j in the 27 cells around p.
  template <class F>
  void for_each_near(const Vec3& p, F&& f) const {
    const Eigen::Vector3i c = cell_of(p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const Eigen::Vector3i q = c + Eigen::Vector3i(dx, dy, dz);
          if ((q.array() < 0).any() || (q.array() >= dims_.array()).any()) continue;
          for (std::int32_t j = head_[static_cast<std::size_t>(index(q))]; j >= 0;
               j = next_[static_cast<std::size_t>(j)])
            f(static_cast<std::size_t>(j));
        }
  }

 private:
  Eigen::Vector3i cell_of(const Vec3& p) const {
    const Eigen::Vector3i c = ((p - lower_) / cell_).array().floor().cast<int>();
    return c.cwiseMax(0).cwiseMin(dims_ - Eigen::Vector3i::Ones());
  }
  std::int64_t index(const Eigen::Vector3i& c) const {
    return (std::int64_t{c.x()} * dims_.y() + c.y()) * dims_.z() + c.z();
  }
  double cell_;
  Vec3 lower_;
  Eigen::Vector3i dims_;
  std::vector<std::int32_t> head_, next_;
};

// The shape's volume (grid_volume); ComputationError when it has no inside.
double inside_volume(const SignedDistance& shape) {
  const double volume = grid_volume(shape, 48);
  if (!(volume > 0.0))
    throw ComputationError(fmt::format("{} has no inside to fill", shape.description));
  return volume;
}

// The radius of n equal spheres that fill `volume` to `solid_fraction`.
double radius_at(double volume, std::size_t n, double solid_fraction) {
  return std::cbrt(solid_fraction * volume /
                   (static_cast<double>(n) * 4.0 / 3.0 * std::numbers::pi));
}

// Whether sphere i of x has another within `reach` (centre distance), from a built grid.
bool has_neighbour(const CellGrid& grid, const std::vector<Vec3>& x, std::size_t i, double reach) {
  bool found = false;
  grid.for_each_near(x[i], [&](std::size_t j) {
    found = found || (j != i && (x[j] - x[i]).squaredNorm() < reach * reach);
  });
  return found;
}

// How far sphere centre p lies outside where it may be (> 0: outside), for radius r.
double excursion(const SignedDistance& shape, const Vec3& p, double r, bool wholly_inside) {
  return shape(p) + (wholly_inside ? r : 0.0);
}

// Moves p onto the offset surface sdf = -level along the distance gradient (Newton steps).
void onto_offset_surface(const SignedDistance& shape, Vec3& p, double level, double r) {
  for (int k = 0; k < 20; ++k) {
    const double off = shape(p) + level;
    if (std::abs(off) < 1e-9 * r) return;
    const Vec3 g = shape.gradient(p, 0.05 * r);
    const double g2 = g.squaredNorm();
    if (!(g2 > 0.0)) return;
    p -= off * g / g2;
  }
}

// Area of the level set sdf = level, as the volume of the band |sdf - level| < h over 2h, on a
// grid of `cells` per longest side (h = 2 cells).
double level_set_area(const SignedDistance& shape, double level, int cells) {
  const Vec3 size = shape.bounds.size();
  const double c = size.maxCoeff() / cells;
  const double h = 2.0 * c;
  const Eigen::Vector3i n = (size / c).array().ceil().cast<int>().max(1);
  std::int64_t band = 0;
  for (int i = 0; i < n.x(); ++i)
    for (int j = 0; j < n.y(); ++j)
      for (int k = 0; k < n.z(); ++k)
        if (std::abs(shape(shape.bounds.lower + c * (Vec3(i, j, k) + Vec3::Constant(0.5))) -
                     level) < h)
          ++band;
  return static_cast<double>(band) * c * c * c / (2.0 * h);
}

// Relaxes overlaps at radius r: each sweep moves both spheres of every overlapping pair apart by
// half their overlap and every sphere that left the shape back along the distance gradient,
// updating positions at once (Gauss–Seidel sweeps over the pairs in a fixed order, so the result
// is deterministic). Pairs come from a Verlet list of reach 2r + skin, rebuilt when a sphere has
// moved half the skin since the last build. True when the largest overlap or excursion of a
// sweep fell below `tolerance` within `steps` sweeps.
// Spheres i < shell (the surface-conforming layer) are instead held on the offset surface
// sdf = -r, pulled back onto it from either side, and keep `shell_spacing` × 2r apart from
// each other.
bool relax(std::vector<Vec3>& x, double r, const SignedDistance& shape, bool wholly_inside,
           double tolerance, int steps, std::size_t shell = 0, double shell_spacing = 1.0) {
  const double skin = 0.2 * r;
  const double reach = 2.0 * r * (shell > 0 ? std::max(1.0, shell_spacing) : 1.0) + skin;
  CellGrid grid(shape.bounds, reach);
  std::vector<std::array<std::int32_t, 2>> pairs;
  std::vector<std::int32_t> near_surface;
  std::vector<Vec3> at_build;
  const auto build = [&] {
    grid.build(x);
    pairs.clear();
    near_surface.clear();
    for (std::size_t i = 0; i < x.size(); ++i) {
      grid.for_each_near(x[i], [&](std::size_t j) {
        if (j > i && (x[j] - x[i]).squaredNorm() < reach * reach)
          pairs.push_back({static_cast<std::int32_t>(i), static_cast<std::int32_t>(j)});
      });
      if (i < shell || excursion(shape, x[i], r, wholly_inside) > -skin)
        near_surface.push_back(static_cast<std::int32_t>(i));
    }
    at_build = x;
  };
  build();
  const double shell_contact = 2.0 * r * shell_spacing;
  for (int step = 0; step < steps; ++step) {
    double worst = 0.0;
    for (const auto& [a, b] : pairs) {
      Vec3& xi = x[static_cast<std::size_t>(a)];
      Vec3& xj = x[static_cast<std::size_t>(b)];
      const double contact =
          static_cast<std::size_t>(b) < shell ? shell_contact : 2.0 * r;  // a < b
      const Vec3 d = xj - xi;
      const double d2 = d.squaredNorm();
      if (d2 >= contact * contact) continue;
      const double length = std::sqrt(d2);
      // Coincident centres (only from the random start): part them along a fixed axis.
      const Vec3 n = length > 0.0 ? Vec3(d / length) : Vec3::UnitX();
      const double overlap = contact - length;
      worst = std::max(worst, overlap);
      xi -= 0.5 * overlap * n;
      xj += 0.5 * overlap * n;
    }
    for (std::int32_t i : near_surface) {
      Vec3& xi = x[static_cast<std::size_t>(i)];
      // A shell sphere is pulled back from inside too; the others only from outside.
      const double out = excursion(shape, xi, r, wholly_inside);
      if (out == 0.0 || (out < 0.0 && static_cast<std::size_t>(i) >= shell)) continue;
      worst = std::max(worst, std::abs(out));
      const Vec3 g = shape.gradient(xi, 0.05 * r);
      const double g2 = g.squaredNorm();
      if (g2 > 0.0) xi -= out * g / std::sqrt(g2);
    }
    if (worst <= tolerance) return true;
    double moved2 = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i)
      moved2 = std::max(moved2, (x[i] - at_build[i]).squaredNorm());
    if (moved2 > 0.25 * skin * skin) build();
  }
  return false;
}

}  // namespace

RandomPacking dense_random_packing(const SignedDistance& shape,
                                   const RandomPackingOptions& options) {
  const auto n = static_cast<std::size_t>(std::max(options.count, 1));
  const double volume = inside_volume(shape);
  const double sphere_volume_per_r3 = 4.0 / 3.0 * std::numbers::pi;
  // Start loose (solid fraction 0.3): random centres, overlaps allowed, relaxed first.
  double r = radius_at(volume, n, 0.3);
  Rng rng(options.seed);
  std::vector<Vec3> x;
  x.reserve(n);
  const Vec3 size = shape.bounds.size();
  for (std::int64_t tries = 0; x.size() < n; ++tries) {
    if (tries > 1000 * static_cast<std::int64_t>(n) + 100000)
      throw ComputationError(
          fmt::format("could not place {} sub-sphere centres inside {}", n, shape.description));
    const Vec3 p = shape.bounds.lower +
                   Vec3(uniform01(rng), uniform01(rng), uniform01(rng)).cwiseProduct(size);
    if (excursion(shape, p, r, options.wholly_inside) <= 0.0) x.push_back(p);
  }
  const auto shell = static_cast<std::size_t>(std::clamp(options.shell_count, 0, options.count));
  for (std::size_t i = 0; i < shell; ++i)
    onto_offset_surface(shape, x[i], options.wholly_inside ? r : 0.0, r);
  RandomPacking result;
  const double tolerance = 1e-3;  // of the radius: what the final exact radius gives up
  relax(x, r, shape, options.wholly_inside, tolerance * r, 10 * options.relaxation_steps, shell,
        options.shell_spacing);
  // Grow until jammed (see the header). A failed growth is undone, so the accepted state is
  // always relaxed at its radius.
  double factor = 0.02;
  while (factor >= options.jam_tolerance) {
    std::vector<Vec3> trial = x;
    const double grown = r * (1.0 + factor);
    if (relax(trial, grown, shape, options.wholly_inside, tolerance * grown,
              options.relaxation_steps, shell, options.shell_spacing)) {
      x = std::move(trial);
      r = grown;
      ++result.growth_steps;
      factor = std::min(1.5 * factor, 0.02);
    } else {
      factor *= 0.5;
    }
  }
  // Rattlers: onto their nearest neighbour (every other distance shrinks by at most the move,
  // and the nearest was the closest, so none falls below 2r).
  const double reach = 2.0 * r * (1.0 + options.contact_gap);
  CellGrid grid(shape.bounds, reach);
  grid.build(x);
  for (std::size_t i = 0; i < n; ++i) {
    if (has_neighbour(grid, x, i, reach)) continue;
    std::size_t nearest = i;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < n; ++j)
      if (j != i && (x[j] - x[i]).squaredNorm() < best)
        best = (x[j] - x[i]).squaredNorm(), nearest = j;
    if (nearest == i) continue;
    const double d = std::sqrt(best);
    const Vec3 moved = x[i] + (d - 2.0 * r) * (x[nearest] - x[i]) / d;
    if (excursion(shape, moved, r, options.wholly_inside) > 0.0) continue;  // left to the caller
    x[i] = moved;
    grid.build(x);
    ++result.rattlers_moved;
  }
  // The exact overlap-free radius of the final centres.
  CellGrid final_grid(shape.bounds, 2.0 * r);
  final_grid.build(x);
  double exact = r;
  for (std::size_t i = 0; i < n; ++i) {
    final_grid.for_each_near(x[i], [&](std::size_t j) {
      if (j > i) exact = std::min(exact, 0.5 * (x[j] - x[i]).norm());
    });
    if (options.wholly_inside) exact = std::min(exact, -shape(x[i]));
  }
  result.radius = exact;
  result.centres = std::move(x);
  result.solid_fraction =
      static_cast<double>(n) * sphere_volume_per_r3 * exact * exact * exact / volume;
  return result;
}

RandomPacking carved_random_packing(const SignedDistance& shape,
                                    const RandomPackingOptions& options) {
  const auto n = static_cast<std::size_t>(std::max(options.count, 1));
  const double volume = inside_volume(shape);
  const double sphere_volume_per_r3 = 4.0 / 3.0 * std::numbers::pi;
  // The bulk of this packing jams near a solid fraction of 0.6: the radius N spheres would have.
  const double estimate = radius_at(volume, n, 0.6);
  const double margin = carve_margin * estimate;
  SignedDistance outer;
  outer.distance = [shape, margin](const Vec3& p) { return shape(p) - margin; };
  outer.bounds = {shape.bounds.lower - Vec3::Constant(margin),
                  shape.bounds.upper + Vec3::Constant(margin)};
  outer.description = fmt::format("{} offset by {:.3g} m", shape.description, margin);
  const Vec3 centre = 0.5 * (shape.bounds.lower + shape.bounds.upper);
  if (!(shape(centre) < 0.0))
    throw ComputationError(
        fmt::format("{}: the carved fill scales about the box centre, which lies outside the shape",
                    shape.description));
  const double outer_volume = grid_volume(outer, 48);
  double spheres = static_cast<double>(n) * outer_volume / volume;
  for (int attempt = 0; attempt < 4; ++attempt) {
    RandomPackingOptions big = options;
    big.count = static_cast<int>(std::ceil(1.05 * spheres));
    big.shell_count = 0;
    big.relaxation_steps = 3 * options.relaxation_steps;
    const RandomPacking bulk = dense_random_packing(outer, big);
    const double r = bulk.radius;
    // Each sphere's largest scale s at which it lies wholly inside (star-shaped shape): kept
    // spheres are those of the N largest, scaled by the N-th's, which touches the surface.
    const auto inside_at = [&](const Vec3& c, double s) {
      return shape(centre + s * (c - centre)) <= -s * r;
    };
    std::vector<double> threshold(bulk.centres.size(), 0.0);
    for (std::size_t i = 0; i < bulk.centres.size(); ++i) {
      const Vec3& c = bulk.centres[i];
      double lo = 0.0, hi = 1.0;
      while (inside_at(c, hi) && hi < 1e6)
        lo = hi, hi *= 2.0;
      for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (inside_at(c, mid) ? lo : hi) = mid;
      }
      threshold[i] = lo;
    }
    std::vector<std::size_t> order(bulk.centres.size());
    for (std::size_t i = 0; i < order.size(); ++i)
      order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return threshold[a] > threshold[b]; });
    // Scale 1 carves the shape's own region; a smaller scale would reach into the margin (the
    // wall-ordered layer of the larger packing): pack more and retry.
    const auto at_one = static_cast<std::size_t>(
        std::count_if(threshold.begin(), threshold.end(), [](double t) { return t >= 1.0; }));
    if (at_one < n) {
      spheres *=
          1.1 * static_cast<double>(n) / static_cast<double>(std::max<std::size_t>(at_one, 1));
      continue;
    }
    // Take the N with the largest thresholds, dropping any left without a kept neighbour within
    // the bond reach (its neighbours were carved away) and taking the next instead.
    std::vector<char> dropped(order.size(), 0);
    std::vector<std::size_t> kept;
    for (int sweep = 0;; ++sweep) {
      kept.clear();
      for (std::size_t i : order)
        if (!dropped[i] && kept.size() < n) kept.push_back(i);
      if (kept.size() < n)
        throw ComputationError(fmt::format("carved fill of {}: fewer than {} connected spheres",
                                           shape.description, n));
      const double s = threshold[kept.back()];
      const double reach = 2.0 * r * s * (1.0 + options.contact_gap);
      std::vector<Vec3> x;
      for (std::size_t i : kept)
        x.push_back(centre + s * (bulk.centres[i] - centre));
      CellGrid grid(shape.bounds, reach);
      grid.build(x);
      bool any = false;
      for (std::size_t a = 0; a < x.size(); ++a)
        if (!has_neighbour(grid, x, a, reach)) dropped[kept[a]] = 1, any = true;
      if (any && sweep < 100) continue;
      RandomPacking result;
      result.centres = std::move(x);
      result.radius = r * s;
      result.growth_steps = bulk.growth_steps;
      result.rattlers_moved = bulk.rattlers_moved;
      result.solid_fraction = static_cast<double>(n) * sphere_volume_per_r3 * result.radius *
                              result.radius * result.radius / volume;
      return result;
    }
  }
  throw ComputationError(fmt::format(
      "carved fill of {}: a packing of the offset shape did not hold {} spheres inside it",
      shape.description, n));
}

ShellPacking surface_conforming_packing(const SignedDistance& shape,
                                        const ShellPackingOptions& options) {
  ShellPacking result;
  RandomPackingOptions plain = options.packing;
  plain.shell_count = 0;
  const RandomPacking reference = dense_random_packing(shape, plain);
  result.plain_radius = reference.radius;
  // The offset surface the shell's centres lie on (sdf = -r; the centres of wholly inside
  // spheres, or the surface itself when only centres must be inside).
  const double level = options.packing.wholly_inside ? -reference.radius : 0.0;
  result.offset_area = level_set_area(shape, level, 96);
  const double disk = std::numbers::pi * reference.radius * reference.radius;
  result.shell_count = std::clamp(
      static_cast<int>(std::lround(options.shell_area_fraction * result.offset_area / disk)), 0,
      options.packing.count);
  RandomPackingOptions shelled = options.packing;
  shelled.shell_count = result.shell_count;
  shelled.shell_spacing = options.shell_spacing;
  result.packing = dense_random_packing(shape, shelled);
  return result;
}

}  // namespace shapepress::geometry
