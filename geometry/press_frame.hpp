#pragma once
// The plate tests' frame (fem-plate's 3D model, plate's BMS templates): a closed triangle mesh made
// ready for the 3D plate test: read (STL/OFF/PLY), refused when it
// cannot bound a solid, and turned into the press frame, where the plates' axis is z and the
// origin the particle's centroid. The axis is a principal axis of inertia (the long axis has the
// smallest moment, the short axis the largest) or a given direction.
#include <array>
#include <filesystem>
#include <string>

#include "geometry/mesh.hpp"
#include "geometry/press_axis.hpp"

namespace shapepress::geometry {

struct PressedParticle {
  TriangleMesh surface;            // in the press frame [m]
  Vec3 centroid = Vec3::Zero();    // in the mesh file's frame [m]
  Mat3 frame = Mat3::Identity();   // rows: the press frame's x, y, z axes
  double top = 0.0, bottom = 0.0;  // the highest and lowest z of the surface [m]
  double volume = 0.0;             // [m³]
  double height() const { return top - bottom; }
};

// InputError naming `path` for an unreadable mesh, an open, non-manifold or self-intersecting
// one (what is wrong, and how much), or a zero direction. `unit`: metres per file unit.
PressedParticle pressed_particle(const std::filesystem::path& path, double unit, PressAxis axis,
                                 const std::array<double, 3>& direction);

// The press frame of a solid whose principal axes (columns, ascending moments) are `axes`:
// rows x, y, z with z along `axis`, right-handed.
Mat3 press_frame(const Mat3& axes, PressAxis axis, const std::array<double, 3>& direction);

// The principal radii of curvature (R1 ≥ R2) of the surface where a plate touches it, from a
// least-squares quadric over the vertices within `depth` of the extreme z (top: the highest,
// else the lowest). Infinite radii for a flat face.
std::array<double, 2> contact_curvature_radii(const TriangleMesh& surface, bool top, double depth);

}  // namespace shapepress::geometry
