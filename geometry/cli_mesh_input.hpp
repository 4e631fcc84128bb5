#pragma once
// Reading a user's mesh for describe and fill: units, repairs reported on the log, refusal
// naming the mesh.
#include <string>

#include "geometry/mesh.hpp"

namespace shapepress::geometry {

// `unit_text` is a length ("1 m", "1mm", "1um") the file's coordinates are in.
TriangleMesh load_checked_mesh(const std::string& path, const std::string& unit_text);

}  // namespace shapepress::geometry
