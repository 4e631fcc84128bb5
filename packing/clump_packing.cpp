#include "packing/clump_packing.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <fmt/format.h>

#include "common/error.hpp"

namespace shapepress::packing {

Quaternion random_rotation(std::mt19937_64& random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double u1 = unit(random), u2 = unit(random), u3 = unit(random);
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  const double two_pi = 2.0 * std::numbers::pi;
  return {a * std::sin(two_pi * u2), a * std::cos(two_pi * u2), b * std::sin(two_pi * u3),
          b * std::cos(two_pi * u3)};
}

namespace {

struct Bound {
  double x, y, z, r;
};

}  // namespace

void insert_clumps(SphereState& state, ClumpSet& clumps, const Box& box,
                   const ClumpInsertion& request, double density, int material) {
  if (request.templates.empty()) throw InputError("clumps: no template to insert");
  if (!box.periodic_x() || !box.periodic_y())
    throw InputError("clumps: insertion needs a periodic box (box.x and box.y)");
  // A bad template (zero volume, not one overlapping group) is named before any placement.
  for (const BodyTemplate& t : request.templates)
    clump_geometry(t.centres, t.radii, t.name, request.integration_cells);
  // Bounding spheres of what is already there; clumps join them as they are placed.
  std::vector<Bound> taken;
  for (std::size_t i = 0; i < state.size(); ++i)
    if (clumps.clump_of.size() <= i || clumps.clump_of[i] < 0)
      taken.push_back(
          {state.position.x[i], state.position.y[i], state.position.z[i], state.radius[i]});
  for (std::size_t c = 0; c < clumps.size(); ++c) {
    double reach = 0.0;
    for (std::int32_t i = clumps.first[c]; i < clumps.last[c]; ++i)
      reach = std::max(reach, std::hypot(state.position.x[i] - clumps.centre.x[c],
                                         state.position.y[i] - clumps.centre.y[c],
                                         state.position.z[i] - clumps.centre.z[c]) +
                                  state.radius[i]);
    taken.push_back({clumps.centre.x[c], clumps.centre.y[c], clumps.centre.z[c], reach});
  }
  std::mt19937_64 random(request.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::int64_t k = 0; k < request.count; ++k) {
    const BodyTemplate& t =
        request.templates[static_cast<std::size_t>(k) % request.templates.size()];
    // The template about its own centroid of sphere centres, so a rotation keeps it compact.
    Vector3 mid = {0.0, 0.0, 0.0};
    for (const Vector3& c : t.centres)
      for (int a = 0; a < 3; ++a)
        mid[a] += c[a] / static_cast<double>(t.centres.size());
    double reach = 0.0;
    for (std::size_t i = 0; i < t.centres.size(); ++i)
      reach = std::max(reach, std::hypot(t.centres[i][0] - mid[0], t.centres[i][1] - mid[1],
                                         t.centres[i][2] - mid[2]) +
                                  t.radii[i]);
    if (request.z_high - request.z_low < 2.0 * reach)
      throw InputError(
          fmt::format("clumps: template {} ({:.3g} m across) does not fit between "
                      "the heights {:.3g} and {:.3g} m",
                      t.name, 2.0 * reach, request.z_low, request.z_high));
    bool placed = false;
    for (int attempt = 0; attempt < request.attempts_per_clump && !placed; ++attempt) {
      const Quaternion turn = random_rotation(random);
      const double x = box.length_x * unit(random), y = box.length_y * unit(random);
      const double z =
          request.z_low + reach + (request.z_high - request.z_low - 2.0 * reach) * unit(random);
      placed = std::none_of(taken.begin(), taken.end(), [&](const Bound& b) {
        double dx = b.x - x, dy = b.y - y;
        dx -= box.length_x * std::nearbyint(dx / box.length_x);
        dy -= box.length_y * std::nearbyint(dy / box.length_y);
        const double dz = b.z - z, gap = b.r + reach;
        return dx * dx + dy * dy + dz * dz < gap * gap;
      });
      if (!placed) continue;
      std::vector<Vector3> centres;
      for (const Vector3& c : t.centres) {
        const Vector3 r = rotate_to_world(turn, {c[0] - mid[0], c[1] - mid[1], c[2] - mid[2]});
        centres.push_back({x + r[0], y + r[1], z + r[2]});
      }
      const std::size_t c = add_clump(state, clumps, centres, t.radii, density, material, t.name,
                                      request.integration_cells);
      taken.push_back({clumps.centre.x[c], clumps.centre.y[c], clumps.centre.z[c],
                       reach + std::hypot(clumps.centre.x[c] - x, clumps.centre.y[c] - y,
                                          clumps.centre.z[c] - z)});
    }
    if (!placed)
      throw InputError(
          fmt::format("clumps: clump {} of {} ({}) found no free place in {} tries: "
                      "fewer clumps or spheres, or a taller region",
                      k + 1, request.count, t.name, request.attempts_per_clump));
  }
}

}  // namespace shapepress::packing
