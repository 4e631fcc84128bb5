#pragma once
// The particle's volume as quadratic tetrahedra (CalculiX C3D10), meshed by Gmsh (Debian's gmsh,
// run as a child process) from the closed surface: Gmsh classifies the triangles into smooth
// patches, rebuilds a geometry on them and remeshes it, so the element size is the one asked
// for, not the input triangles'. Midside nodes lie on the rebuilt surface (curved elements).
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/mesh.hpp"

namespace shapepress::fem {

struct TetMesh {
  std::vector<geometry::Vec3> nodes;          // [m]
  std::vector<std::array<int, 10>> elements;  // 0-based, CalculiX C3D10 node order
  std::vector<int> anchors;                   // the nodes at the requested embedded points
};

struct TetSizes {
  double at_plates = 0.0;  // element size within `band` of the top or the bottom [m]
  double elsewhere = 0.0;  // element size in the middle [m]
  double band = 0.0;       // [m]
};

// Meshes `surface` (press frame, m) in `folder` as job.stl / job.geo → job.msh (kept there, log
// in job-gmsh.log, lengths in the deck's unit, `units_per_m` of them per metre) with `program`
// (gmsh). `embedded` points become mesh nodes (anchors, in that
// order). InputError (exit 2) naming the program when it cannot be started; ComputationError
// when Gmsh fails or yields no tetrahedra (its log named).
TetMesh tetrahedral_mesh(const geometry::TriangleMesh& surface, const TetSizes& sizes,
                         const std::vector<geometry::Vec3>& embedded,
                         const std::filesystem::path& folder, const std::string& job,
                         const std::string& program, double units_per_m);

// Reads the nodes and 10-node tetrahedra of a Gmsh MSH 2.2 ASCII file (lengths × `scale`),
// ordering each element's midside nodes as C3D10 wants them (5: edge 1–2, 6: 2–3, 7: 3–1,
// 8: 1–4, 9: 2–4, 10: 3–4) and its corners so that its volume is positive.
TetMesh read_gmsh_tetrahedra(const std::filesystem::path& msh, double scale);

// The faces of the mesh's boundary as (element, CalculiX face number 1–4).
std::vector<std::pair<int, int>> boundary_faces(const TetMesh& mesh);
// The corner nodes (0-based) of face `face` (1–4) of a C3D10 element.
std::array<int, 3> face_corners(const std::array<int, 10>& element, int face);

}  // namespace shapepress::fem
