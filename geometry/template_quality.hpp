#pragma once
// Mass properties of a sub-sphere template and how well it reproduces its shape.
#include <vector>

#include "geometry/sphere_fill.hpp"

namespace shapepress::geometry {

// Volume, centre and inertia (per unit density) of the *union* of possibly overlapping spheres,
// by midpoint voxel integration on a grid of `cells` along the longest side of the union's box
// (overlaps counted once; Giannis et al. 2023 §2.4 use Monte Carlo for the same reason).
MassProperties union_mass_properties(const std::vector<Vec3>& centres,
                                     const std::vector<double>& radii, int cells = 128);
// The same of the union closed by a ball of `probe_radius` (dilated, then eroded): every pore and
// crevice of the union that such a ball cannot enter is filled. A BMS or CMS body's volume as a
// neighbouring sub-sphere of that radius sees it (docs/models.md, "A body's volume"). The grid's
// cells are a sixteenth of the probe radius, or coarser so that at most `cells` span the longest
// side of the box around the union.
MassProperties closed_union_mass_properties(const std::vector<Vec3>& centres,
                                            const std::vector<double>& radii, double probe_radius,
                                            int cells = 320);
// Exact for spheres that do not overlap (BMS): sums of spheres with the parallel-axis theorem.
MassProperties sphere_sum_mass_properties(const std::vector<Vec3>& centres,
                                          const std::vector<double>& radii);
MassProperties ellipsoid_mass_properties(const Vec3& semi_axes, const Vec3& centre = Vec3::Zero());

struct FillQuality {
  int sphere_count = 0;
  double min_radius_m = 0.0, max_radius_m = 0.0;
  int bond_count = 0;
  double mean_coordination = 0.0;  // bonds per sphere x 2
  bool connected = true;
  double volume_fraction = 0.0;       // V_union / V_shape
  double volume_error = 0.0;          // |V_union - V_shape| / V_shape
  double surface_rms_m = 0.0;         // symmetric RMS distance between the two surfaces
  double hausdorff_m = 0.0;           // symmetric Hausdorff distance
  double surface_rms_relative = 0.0;  // / equivalent-volume sphere diameter of the shape
  double hausdorff_relative = 0.0;
  // max_k |g_k(union) - g_k(shape)| / g_k(shape) over the principal values of I/V (squared radii
  // of gyration): what matters once the sub-sphere density is scaled to the particle's mass.
  double inertia_error = 0.0;
  // max |Δ| / extent over the extents along the shape's principal axes (L, I, S).
  double extent_error = 0.0;
  Vec3 shape_extents = Vec3::Zero();  // descending
  Vec3 union_extents = Vec3::Zero();
};

struct QualityOptions {
  int integration_cells = 128;  // voxel grid for the union's mass properties (CMS)
  int surface_cells = 48;       // grid for the shape's surface samples
  int points_per_sphere = 48;   // samples on each sub-sphere surface
};

// `shape_properties` are the shape's exact properties (mesh_mass_properties for a mesh).
FillQuality assess_fill(const SphereTemplate& spheres, const SignedDistance& shape,
                        const MassProperties& shape_properties, const QualityOptions& options = {});

// Mass properties of the template as used by the simulation: exact sums for BMS, the voxelised
// union for CMS.
MassProperties template_mass_properties(const SphereTemplate& spheres, int integration_cells = 128);

}  // namespace shapepress::geometry
