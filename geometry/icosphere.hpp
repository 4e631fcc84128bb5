#pragma once
// The subdivided icosahedron on the unit sphere: near-uniform vertices, every subdivision
// multiplies the triangles by 4 (level 4: 2562 vertices, 5120 triangles).
#include "geometry/mesh.hpp"

namespace shapepress::geometry {

TriangleMesh icosphere(int subdivisions);

// The icosphere with vertex v moved to semi_axes ∘ v: a closed ellipsoid mesh.
TriangleMesh ellipsoid_mesh(const Vec3& semi_axes, int subdivisions);

}  // namespace shapepress::geometry
