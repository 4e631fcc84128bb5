#pragma once
// A closed mesh as a SignedDistance: voxelised once with OpenVDB (narrow band outside, full
// interior), then sampled with trilinear interpolation. OpenVDB stays inside the .cpp.
#include <string>

#include "geometry/signed_distance.hpp"

namespace shapepress::geometry {

// `resolution`: voxels along the longest side of the mesh's bounding box. The mesh must be
// closed and outward-oriented (mesh_checks.hpp).
SignedDistance mesh_distance(const TriangleMesh& mesh, int resolution, std::string name = "mesh");

}  // namespace shapepress::geometry
