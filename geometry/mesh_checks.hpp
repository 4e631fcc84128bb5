#pragma once
// What a mesh must be before it can be filled or described: closed, 2-manifold, free of
// self-intersections, outward-oriented, not degenerate and not tiny. Repairs that CGAL's
// Polygon Mesh Processing can do (merge duplicate points, drop degenerate and duplicate faces,
// orient a soup, split non-manifold vertices, stitch borders, fill holes) are made and reported;
// the rest is an InputError naming the mesh and the cause. CGAL stays inside the .cpp.
#include <string>
#include <vector>

#include "geometry/mesh.hpp"

namespace shapepress::geometry {

struct MeshCheck {
  bool closed = false;
  bool manifold = false;
  bool self_intersecting = false;
  bool valid() const { return closed && manifold && !self_intersecting; }
};

// The checks alone, no repair (the generator redraws a particle that fails them).
MeshCheck check_mesh(const TriangleMesh& mesh);

// Repairs what can be repaired (each repair appended to `repairs` as a sentence), then refuses
// open, non-manifold, self-intersecting, inside-out, degenerate (flat) or tiny meshes.
// `min_size_m`: a mesh whose longest side is smaller is refused as tiny (wrong units?).
TriangleMesh prepare_mesh(const TriangleMesh& mesh, const std::string& name,
                          std::vector<std::string>* repairs, double min_size_m = 1e-8);

}  // namespace shapepress::geometry
