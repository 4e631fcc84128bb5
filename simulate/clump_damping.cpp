// The mass a clump's sub-sphere brings to its contacts' restitution damping (models.md, "Damping
// of a clump's contacts"). The damping of one contact, γ = 2√(5/6) β √(S m*) (LIGGGHTS `gran
// model hertz`), gives the input restitution when m* is the colliding bodies' effective mass: a
// clump sub-sphere must bring the clump's mass M, as LAMMPS/LIGGGHTS (pair gran: "if I or J part
// of rigid body, use body mass") and Yade do. When the clump meets one partner body through k
// sub-sphere contacts at once (a plate under a flat face, two overlapping sub-spheres of a
// neighbour), k contacts with M each would damp that body–body contact √k times more than one
// contact of their summed stiffness K = Σ S: Σ √(S M) = √k √(K M). Each of them therefore brings
// M/k, and the k together damp as √(K M), the body's own restitution damping, for any k; the
// plate rig's hundreds of sub-sphere contacts stay as stable as with M/n.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "simulate/engine.hpp"

namespace shapepress::simulate {

void Engine::share_clump_damping_mass() {
  const std::vector<std::int32_t>& clump_of = clumps_.clump_of;
  const auto clump_count = static_cast<std::int64_t>(clumps_.size());
  const auto sphere_count = static_cast<std::int64_t>(state_.size());
  const double* geometry = geometry_.data();
  double* motion = motion_.data();
  // (clump, partner, sub-sphere) of every touching contact of a sub-sphere, from the positions
  // the pair loop is about to use (so a restart computes the same masses). Partner: a clump c,
  // a free sphere s as clumps + s, a wall k as clumps + spheres + k.
  std::vector<std::array<std::int64_t, 3>>& touching = clump_contacts_;
  touching.clear();
  const auto partner = [&](std::int32_t s) -> std::int64_t {
    return clump_of[s] >= 0 ? clump_of[s] : clump_count + s;
  };
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const std::int32_t i = pairs_.first[p], j = pairs_.second[p];
    if (clump_of[i] < 0 && clump_of[j] < 0) continue;
    const double* gi = geometry + 4 * static_cast<std::size_t>(i);
    const double* gj = geometry + 4 * static_cast<std::size_t>(j);
    const double* shift = pairs_.shift(p);
    const double dx = gj[0] - gi[0] + shift[0], dy = gj[1] - gi[1] + shift[1], dz = gj[2] - gi[2];
    const double reach = gi[3] + gj[3];
    if (dx * dx + dy * dy + dz * dz >= reach * reach) continue;  // as the pair loop selects
    if (clump_of[i] >= 0) touching.push_back({clump_of[i], partner(j), i});
    if (clump_of[j] >= 0) touching.push_back({clump_of[j], partner(i), j});
  }
  for (std::int64_t c = 0; c < clump_count; ++c)
    for (std::int32_t i = clumps_.first[c]; i < clumps_.last[c]; ++i) {
      const double* g = geometry + 4 * static_cast<std::size_t>(i);
      for (std::size_t k = 0; k < walls_.size(); ++k)
        if (walls_[k].facing * (g[2] - walls_[k].position) < g[3])  // as the gather's wall test
          touching.push_back({c, clump_count + sphere_count + static_cast<std::int64_t>(k), i});
      motion[8 * static_cast<std::size_t>(i) + 6] = clumps_.mass[c];  // no contact: M
    }
  std::sort(touching.begin(), touching.end());
  for (std::size_t a = 0; a < touching.size();) {
    std::size_t b = a + 1;
    while (b < touching.size() && touching[b][0] == touching[a][0] &&
           touching[b][1] == touching[a][1])
      ++b;
    const double share = clumps_.mass[touching[a][0]] / static_cast<double>(b - a);
    // A sub-sphere touching two partners takes the smaller share (the more contacts).
    for (std::size_t k = a; k < b; ++k) {
      double& mass = motion[8 * static_cast<std::size_t>(touching[k][2]) + 6];
      mass = std::min(mass, share);
    }
    a = b;
  }
}

}  // namespace shapepress::simulate
