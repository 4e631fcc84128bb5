#include "geometry/sphere_fill.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "common/error.hpp"
#include "geometry/random.hpp"
#include "geometry/random_packing.hpp"

namespace shapepress::geometry {
namespace {

// Lattice sites (unit nearest-neighbour distance) in a ball of `reach` neighbour distances.
std::vector<Vec3> lattice_sites(Lattice lattice, double reach) {
  std::vector<Vec3> sites;
  const int n = static_cast<int>(std::ceil(reach)) + 2;
  if (lattice == Lattice::fcc) {
    const double a = std::sqrt(2.0);  // cubic cell edge for unit neighbour distance
    const Vec3 basis[4] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    const int m = static_cast<int>(std::ceil(reach / a)) + 1;
    for (int i = -m; i <= m; ++i)
      for (int j = -m; j <= m; ++j)
        for (int k = -m; k <= m; ++k)
          for (const Vec3& b : basis) {
            const Vec3 p = a * (Vec3(i, j, k) + b);
            if (p.norm() <= reach) sites.push_back(p);
          }
  } else {
    // Hexagonal layers A, B, A, … with layer spacing sqrt(2/3).
    const double h = std::sqrt(3.0) / 2.0, dz = std::sqrt(2.0 / 3.0);
    for (int k = -n; k <= n; ++k) {
      const bool b_layer = (k % 2 != 0);
      for (int j = -n; j <= n; ++j)
        for (int i = -n; i <= n; ++i) {
          Vec3 p(i + 0.5 * j, h * j, dz * k);
          if (b_layer) p += Vec3(0.5, h / 3.0, 0.0);
          if (p.norm() <= reach) sites.push_back(p);
        }
    }
  }
  return sites;
}

struct LatticeFrame {
  Mat3 rotation;
  Vec3 offset;  // in units of the neighbour distance
};

// Sites of the lattice with spacing 2r accepted by the placement rule, ordered as generated.
std::vector<Vec3> accepted_sites(const SignedDistance& shape, const std::vector<Vec3>& unit_sites,
                                 const LatticeFrame& frame, double r, Placement placement) {
  const Vec3 centre = 0.5 * (shape.bounds.lower + shape.bounds.upper);
  const double limit = placement == Placement::inside ? -r : 0.0;
  std::vector<Vec3> kept;
  for (const Vec3& unit : unit_sites) {
    const Vec3 p = centre + frame.rotation * ((unit + frame.offset) * 2.0 * r);
    if ((p.array() < shape.bounds.lower.array() - r).any() ||
        (p.array() > shape.bounds.upper.array() + r).any())
      continue;
    if (shape(p) <= limit) kept.push_back(p);
  }
  return kept;
}

// The largest connected cluster of the touching-sphere graph (Eq. 10 with m_b).
std::vector<Vec3> largest_cluster(const std::vector<Vec3>& sites, double r, double m_b) {
  if (sites.empty()) return sites;
  const std::vector<double> radii(sites.size(), r);
  const std::vector<int> label =
      connected_components(sites.size(), pairs_within(sites, radii, m_b));
  const int count = *std::max_element(label.begin(), label.end()) + 1;
  if (count == 1) return sites;
  std::vector<int> size(static_cast<std::size_t>(count), 0);
  for (int l : label)
    ++size[static_cast<std::size_t>(l)];
  const int keep = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
  std::vector<Vec3> kept;
  for (std::size_t i = 0; i < sites.size(); ++i)
    if (label[i] == keep) kept.push_back(sites[i]);
  return kept;
}

}  // namespace

std::string kind_name(TemplateKind kind) {
  return kind == TemplateKind::bonded ? "bms" : "cms";
}

Lattice lattice_from_name(const std::string& name) {
  for (std::size_t k = 0; k < std::size(lattice_names); ++k)
    if (name == lattice_names[k]) return static_cast<Lattice>(k);
  throw InputError(
      fmt::format("unknown lattice '{}' (known: {})", name,
                  fmt::join(std::begin(lattice_names), std::end(lattice_names), ", ")));
}

void BondedFillOptions::check() const {
  if (sub_sphere_radius < 0.0 || !std::isfinite(sub_sphere_radius))
    throw InputError(
        fmt::format("sub-sphere radius {} must be > 0 (or 0 to use the count)", sub_sphere_radius));
  if (sub_sphere_radius == 0.0 && (target_count < 1 || target_count > 1000000))
    throw InputError(fmt::format("sub-sphere count {} must be in [1, 1000000]", target_count));
  if (!(bond_multiplier >= 1.0 && bond_multiplier < std::sqrt(2.0)))
    throw InputError(fmt::format(
        "bond multiplier m_b = {} must be in [1, 1.414): below 1 touching spheres do not bond, "
        "from sqrt(2) second lattice neighbours would bond too",
        bond_multiplier));
  if (is_random_packing(lattice) && sub_sphere_radius > 0.0)
    throw InputError(fmt::format(
        "sub-sphere radius {} m: the random fill takes a count, not a radius (the packing's "
        "radius is where it jams); use the fcc or hcp lattice for a fixed radius",
        sub_sphere_radius));
}

void RigidFillOptions::check() const {
  if (sphere_count < 1 || sphere_count > 100000)
    throw InputError(fmt::format("sphere count {} must be in [1, 100000]", sphere_count));
  if (resolution < 8 || resolution > 1024)
    throw InputError(fmt::format("resolution {} must be in [8, 1024] cells", resolution));
  if (!(min_radius_fraction >= 0.0 && min_radius_fraction < 1.0))
    throw InputError(
        fmt::format("minimum radius fraction {} must be in [0, 1)", min_radius_fraction));
  if (!(max_radius >= 0.0 && std::isfinite(max_radius)))
    throw InputError(
        fmt::format("maximum radius {} must be > 0 (or 0 to use the count)", max_radius));
}

SphereTemplate fill_bonded(const SignedDistance& shape, const BondedFillOptions& options) {
  options.check();
  Rng rng(options.seed);
  const LatticeFrame frame{random_rotation(rng),
                           Vec3(uniform01(rng), uniform01(rng), uniform01(rng))};
  const double half_diagonal = 0.5 * shape.bounds.size().norm();

  auto sites_for = [&](double r) {
    const auto unit = lattice_sites(options.lattice, half_diagonal / (2.0 * r) + 2.0);
    return largest_cluster(accepted_sites(shape, unit, frame, r, options.placement), r,
                           options.bond_multiplier);
  };

  double r = options.sub_sphere_radius;
  std::vector<Vec3> sites;
  if (is_random_packing(options.lattice)) {
    RandomPackingOptions packing;
    packing.count = options.target_count;
    packing.wholly_inside = options.placement == Placement::inside;
    packing.seed = options.seed;
    packing.contact_gap = options.bond_multiplier - 1.0;
    RandomPacking packed =
        options.lattice == Lattice::shell    ? surface_conforming_packing(shape, {packing}).packing
        : options.lattice == Lattice::carved ? carved_random_packing(shape, packing)
                                             : dense_random_packing(shape, packing);
    r = packed.radius;
    sites = largest_cluster(packed.centres, r, options.bond_multiplier);
  } else if (r > 0.0) {
    sites = sites_for(r);
  } else {
    // Bisection in log r for the smallest radius that still gives >= N spheres: the count
    // falls (stepwise) as r grows.
    const double n = options.target_count;
    double hi = 0.5 * shape.bounds.size().minCoeff();
    double lo = hi * 1e-3;
    for (int iteration = 0; iteration < 40 && hi / lo > 1.0 + 1e-6; ++iteration) {
      const double mid = std::sqrt(lo * hi);
      (static_cast<double>(sites_for(mid).size()) >= n ? lo : hi) = mid;
    }
    r = lo;
    sites = sites_for(r);
    if (sites.size() > static_cast<std::size_t>(options.target_count)) {
      // Drop the spheres closest to the surface until the count is exact, keeping the order.
      std::vector<std::size_t> order(sites.size());
      std::iota(order.begin(), order.end(), 0);
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return shape(sites[a]) < shape(sites[b]);
      });
      order.resize(static_cast<std::size_t>(options.target_count));
      std::sort(order.begin(), order.end());
      std::vector<Vec3> kept;
      for (std::size_t i : order)
        kept.push_back(sites[i]);
      sites = largest_cluster(kept, r, options.bond_multiplier);
    }
  }
  // Fewer than three sub-spheres across its thinnest side, a template neither follows the shape
  // nor deforms like a body (paper §3.2: coarse fills leave the converged curve first).
  const double thinnest = shape.bounds.size().minCoeff();
  if (6.0 * r > thinnest)
    throw InputError(fmt::format(
        "{} sub-spheres are too few for {}: their diameter {:.4g} m is more than a third of its "
        "thinnest extent {:.4g} m (ask for more sub-spheres or a smaller --radius)",
        options.sub_sphere_radius > 0.0 ? fmt::format("{:.4g} m", r)
                                        : fmt::format("{}", options.target_count),
        shape.description, 2.0 * r, thinnest));
  if (sites.empty())
    throw ComputationError(
        fmt::format("no sub-sphere of radius {:.4g} m fits in {}", r, shape.description));
  SphereTemplate result;
  result.kind = TemplateKind::bonded;
  result.centres = std::move(sites);
  result.radii.assign(result.centres.size(), r);
  result.bonds = pairs_within(result.centres, result.radii, options.bond_multiplier);
  return result;
}

std::vector<Bond> pairs_within(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                               double multiplier) {
  std::vector<Bond> pairs;
  if (centres.empty()) return pairs;
  const double r_max = *std::max_element(radii.begin(), radii.end());
  const double cell = std::max(2.0 * r_max * multiplier, 1e-300);
  const Vec3 lower = bounding_box(centres).lower;
  auto cell_of = [&](const Vec3& p) {
    return Eigen::Vector3i(((p - lower) / cell).array().floor().cast<int>());
  };
  auto key = [](const Eigen::Vector3i& c) {
    return (std::int64_t{c.x()} << 42) ^ (std::int64_t{c.y()} << 21) ^ std::int64_t{c.z()};
  };
  std::unordered_map<std::int64_t, std::vector<std::int32_t>> grid;
  for (std::size_t i = 0; i < centres.size(); ++i)
    grid[key(cell_of(centres[i]))].push_back(static_cast<std::int32_t>(i));
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const Eigen::Vector3i c = cell_of(centres[i]);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = grid.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == grid.end()) continue;
          for (std::int32_t j : it->second) {
            if (static_cast<std::size_t>(j) <= i) continue;
            const double reach = (radii[i] + radii[static_cast<std::size_t>(j)]) * multiplier;
            if ((centres[i] - centres[static_cast<std::size_t>(j)]).squaredNorm() < reach * reach)
              pairs.push_back({static_cast<std::int32_t>(i), j});
          }
        }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<int> connected_components(std::size_t node_count, const std::vector<Bond>& edges) {
  std::vector<std::size_t> parent(node_count);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t x) {
    while (parent[x] != x)
      x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const Bond& e : edges) {
    const std::size_t a = find(static_cast<std::size_t>(e[0]));
    const std::size_t b = find(static_cast<std::size_t>(e[1]));
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  std::vector<int> label(node_count, -1);
  std::unordered_map<std::size_t, int> ids;
  for (std::size_t i = 0; i < node_count; ++i) {
    auto [it, inserted] = ids.try_emplace(find(i), static_cast<int>(ids.size()));
    label[i] = it->second;
  }
  return label;
}

bool is_connected(std::size_t node_count, const std::vector<Bond>& edges) {
  if (node_count <= 1) return true;
  const auto label = connected_components(node_count, edges);
  return *std::max_element(label.begin(), label.end()) == 0;
}

}  // namespace shapepress::geometry
