#include "geometry/cli_mesh_input.hpp"

#include <spdlog/spdlog.h>

#include "common/units.hpp"
#include "geometry/mesh_checks.hpp"

namespace shapepress::geometry {

TriangleMesh load_checked_mesh(const std::string& path, const std::string& unit_text) {
  TriangleMesh mesh = read_mesh(path);
  scale_mesh(mesh, parse_quantity(unit_text, dim::length, "mesh-unit"));
  std::vector<std::string> repairs;
  mesh = prepare_mesh(mesh, path, &repairs);
  for (const std::string& repair : repairs)
    spdlog::warn("mesh '{}': repaired: {}", path, repair);
  return mesh;
}

}  // namespace shapepress::geometry
