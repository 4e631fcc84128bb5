#include "geometry/icosphere.hpp"

#include <cmath>
#include <map>
#include <utility>

namespace shapepress::geometry {

TriangleMesh icosphere(int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh mesh;
  mesh.vertices = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& v : mesh.vertices)
    v.normalize();
  mesh.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> midpoints;
    auto midpoint = [&](std::int32_t a, std::int32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] =
          midpoints.try_emplace(key, static_cast<std::int32_t>(mesh.vertices.size()));
      if (inserted)
        mesh.vertices.push_back((mesh.vertices[static_cast<std::size_t>(a)] +
                                 mesh.vertices[static_cast<std::size_t>(b)])
                                    .normalized());
      return it->second;
    };
    std::vector<std::array<std::int32_t, 3>> finer;
    finer.reserve(4 * mesh.triangles.size());
    for (const auto& [a, b, c] : mesh.triangles) {
      const std::int32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      finer.push_back({a, ab, ca});
      finer.push_back({b, bc, ab});
      finer.push_back({c, ca, bc});
      finer.push_back({ab, bc, ca});
    }
    mesh.triangles = std::move(finer);
  }
  return mesh;
}

TriangleMesh ellipsoid_mesh(const Vec3& semi_axes, int subdivisions) {
  TriangleMesh mesh = icosphere(subdivisions);
  for (Vec3& v : mesh.vertices)
    v = v.cwiseProduct(semi_axes);
  return mesh;
}

}  // namespace shapepress::geometry
