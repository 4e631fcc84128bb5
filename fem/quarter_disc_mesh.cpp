#include "fem/quarter_disc_mesh.hpp"

#include <cmath>
#include <map>
#include <numbers>
#include <tuple>

#include <fmt/format.h>

#include "common/error.hpp"

namespace shapepress::fem {
namespace {

// Grading exponents: block parameter s ∈ [0, 1] maps to s^arc_grading (denser at s = 0, the pole
// side of the upper block) and the radial parameter t to 1 − (1 − t)^radial_grading (denser at
// the arc). Mild values keep the elements' aspect ratios under ~3.
constexpr double arc_grading = 1.5;
constexpr double radial_grading = 1.3;
constexpr double core_fraction = 0.5;  // the core square's side, as a fraction of R

// Node ids keyed by (block, i, k) so that shared block edges get one node.
class NodeTable {
 public:
  explicit NodeTable(QuarterDiscMesh& mesh) : mesh_(mesh) {}
  int at(std::tuple<char, int, int> key, double r, double z) {
    const auto [it, added] = ids_.try_emplace(key, 0);
    if (added) {
      mesh_.nodes.push_back({r, z});
      it->second = static_cast<int>(mesh_.nodes.size());
    }
    return it->second;
  }
  int id(std::tuple<char, int, int> key) const { return ids_.at(key); }

 private:
  QuarterDiscMesh& mesh_;
  std::map<std::tuple<char, int, int>, int> ids_;
};

double signed_area(const QuarterDiscMesh& mesh, const std::array<int, 4>& quad) {
  double twice = 0.0;
  for (int k = 0; k < 4; ++k) {
    const auto& a = mesh.nodes[quad[k] - 1];
    const auto& b = mesh.nodes[quad[(k + 1) % 4] - 1];
    twice += a[0] * b[1] - b[0] * a[1];
  }
  return 0.5 * twice;
}

}  // namespace

QuarterDiscMesh quarter_disc_mesh(double radius, int arc_elements) {
  if (!(radius > 0.0)) throw InputError(fmt::format("sphere radius {} must be > 0", radius));
  if (arc_elements < 2 || arc_elements > 400)
    throw InputError(fmt::format("arc_elements {} must be within [2, 400]", arc_elements));
  const int n = arc_elements;
  const int m = std::max(2, static_cast<int>(std::ceil(0.6 * n)));
  const double c = core_fraction * radius;
  std::vector<double> s(n + 1), t(m + 1);
  for (int i = 0; i <= n; ++i)
    s[i] = std::pow(static_cast<double>(i) / n, arc_grading);
  for (int k = 0; k <= m; ++k)
    t[k] = 1.0 - std::pow(1.0 - static_cast<double>(k) / m, radial_grading);

  QuarterDiscMesh mesh;
  mesh.radius = radius;
  mesh.polar_radius = radius;
  NodeTable table(mesh);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      table.at({'c', i, j}, c * s[i], c * s[j]);
  // Outer block 'a' (towards the equator) spans the arc 0…45°, block 'b' (towards the pole)
  // 90…45°; both blend the core's edge (t = 0) linearly into the arc (t = 1). Their common edge
  // (i = n) lies on the diagonal and is keyed once ('d').
  const auto outer = [&](char block, int i, int k) {
    if (k == 0) return block == 'b' ? table.id({'c', i, n}) : table.id({'c', n, i});
    const double angle = block == 'b' ? std::numbers::pi / 2 - std::numbers::pi / 4 * s[i]
                                      : std::numbers::pi / 4 * s[i];
    const double core_r = block == 'b' ? c * s[i] : c;
    const double core_z = block == 'b' ? c : c * s[i];
    const double r = (1.0 - t[k]) * core_r + t[k] * radius * std::cos(angle);
    const double z = (1.0 - t[k]) * core_z + t[k] * radius * std::sin(angle);
    return table.at({i == n ? 'd' : block, i == n ? 0 : i, k}, i == 0 && block == 'b' ? 0.0 : r,
                    i == 0 && block == 'a' ? 0.0 : z);
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      mesh.quads.push_back({table.id({'c', i, j}), table.id({'c', i + 1, j}),
                            table.id({'c', i + 1, j + 1}), table.id({'c', i, j + 1})});
  for (char block : {'a', 'b'})
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < m; ++k)
        mesh.quads.push_back({outer(block, i, k), outer(block, i + 1, k),
                              outer(block, i + 1, k + 1), outer(block, i, k + 1)});
  for (auto& quad : mesh.quads)
    if (signed_area(mesh, quad) < 0.0) std::swap(quad[1], quad[3]);

  const double tolerance = 1e-9 * radius;
  std::vector<bool> on_arc(mesh.nodes.size());
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
    const auto [r, z] = mesh.nodes[i];
    on_arc[i] = std::fabs(std::hypot(r, z) - radius) < tolerance;
    if (r < tolerance) mesh.axis_nodes.push_back(static_cast<int>(i) + 1);
    if (z < tolerance) mesh.equator_nodes.push_back(static_cast<int>(i) + 1);
    if (r < tolerance && on_arc[i]) mesh.pole_node = static_cast<int>(i) + 1;
  }
  for (std::size_t e = 0; e < mesh.quads.size(); ++e)
    for (int f = 0; f < 4; ++f)
      if (on_arc[mesh.quads[e][f] - 1] && on_arc[mesh.quads[e][(f + 1) % 4] - 1])
        mesh.arc_faces.push_back({static_cast<int>(e) + 1, f + 1});
  return mesh;
}

QuarterDiscMesh stretched_to_spheroid(QuarterDiscMesh mesh, double polar_radius) {
  if (!(polar_radius > 0.0))
    throw InputError(fmt::format("polar radius {} must be > 0", polar_radius));
  const double stretch = polar_radius / mesh.polar_radius;
  for (auto& node : mesh.nodes)
    node[1] *= stretch;
  mesh.polar_radius = polar_radius;
  return mesh;
}

double pole_element_size(const QuarterDiscMesh& mesh) {
  double size = mesh.radius;
  const auto& pole = mesh.nodes[mesh.pole_node - 1];
  for (const auto& [element, face] : mesh.arc_faces) {
    const auto& quad = mesh.quads[element - 1];
    const auto& a = mesh.nodes[quad[face - 1] - 1];
    const auto& b = mesh.nodes[quad[face % 4] - 1];
    if (a == pole || b == pole) size = std::min(size, std::hypot(a[0] - b[0], a[1] - b[1]));
  }
  return size;
}

}  // namespace shapepress::fem
