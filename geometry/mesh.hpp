#pragma once
// Closed triangle meshes as plain arrays (vertices + index triples), and their file formats:
// STL (binary and ASCII) and OFF/PLY in, binary STL / OFF / ASCII PLY out. STL is a triangle
// soup; reading it merges coincident corners so the mesh has a topology to check.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace shapepress::geometry {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::int32_t, 3>> triangles;  // counter-clockwise seen from outside
};

// Reads .stl (binary or ASCII, told apart by content), .off or .ply (ASCII). InputError naming
// the file for an unreadable, truncated or empty file.
TriangleMesh read_mesh(const std::filesystem::path& path);

// Writes by extension (.stl binary, .off, .ply ASCII), atomically. The STL header is a fixed
// text (no timestamp), so the same mesh always gives the same bytes.
void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& path);

// Merges vertices that are bit-identical (STL corners) and drops unused ones.
TriangleMesh merge_duplicate_vertices(const TriangleMesh& soup);

// Signed volume by the divergence theorem: positive for outward-facing triangles.
double signed_volume(const TriangleMesh& mesh);
double surface_area(const TriangleMesh& mesh);

struct Aabb {
  Vec3 lower = Vec3::Constant(0.0);
  Vec3 upper = Vec3::Constant(0.0);
  Vec3 size() const { return upper - lower; }
};
Aabb bounding_box(const std::vector<Vec3>& points);

// Volume, centroid and inertia tensor (per unit density, about the centroid) of the solid a
// closed mesh encloses, exactly, from signed tetrahedra to the origin.
struct MassProperties {
  double volume = 0.0;                     // m^3
  Vec3 centre = Vec3::Zero();              // m
  Mat3 inertia = Mat3::Zero();             // m^5 (multiply by density for kg m^2)
  Vec3 principal_moments = Vec3::Zero();   // ascending
  Mat3 principal_axes = Mat3::Identity();  // columns, right-handed
};
MassProperties mesh_mass_properties(const TriangleMesh& mesh);
// Fills principal_moments/axes from inertia.
void diagonalise(MassProperties& properties);

// p -> scale * p, and p -> p + shift.
void scale_mesh(TriangleMesh& mesh, double scale);
void translate_mesh(TriangleMesh& mesh, const Vec3& shift);

}  // namespace shapepress::geometry
