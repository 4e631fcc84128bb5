#pragma once
// templates.h5: sub-sphere templates for the pack and compact stages. One group per kind,
// one subgroup per template; SI units in "unit" attributes; provenance root attributes.
//
//   /                         attributes: format = "shapepress templates 1", template_count
//   /bms/<name>, /cms/<name>  attributes: source (mesh path or analytic shape), kind, seed,
//                             bond_multiplier (bms), sphere_count
//     centres      (N, 3) m    sub-sphere centres in the body frame: origin at the template's
//                              centre of mass, axes its principal axes of inertia
//     radii        (N)    m
//     bonds        (B, 2) int32, i < j (bms only; Eq. 10 of Giannis et al. 2023)
//     volume       (1)    m^3  of the template (sum of spheres for bms, voxelised union for cms)
//     principal_inertia (3) m^5  per unit density, ascending, about the body axes
//     shape_volume (1)    m^3, shape_principal_inertia (3) m^5: the mesh's exact values
//     body_volume  (1)    m^3  the volume the body occupies in a bed: the union of its
//                              sub-spheres closed by a ball of body_probe_radius (templates
//                              files without it get it computed on reading)
//     body_inertia (3)    m^5  per unit density, of that volume about the body axes (diagonal)
//     body_probe_radius (1) m  the closing ball: the median sub-sphere radius
//     body_origin  (3)    m    the body origin in the mesh's frame
//     body_axes    (3, 3)      columns: body axes in the mesh's frame (x_mesh = origin + R x_body)
//     quality/<metric>    one-element datasets: volume_fraction, volume_error, surface_rms_m,
//                         hausdorff_m, surface_rms_relative, hausdorff_relative, inertia_error,
//                         extent_error, min_radius_m, max_radius_m, bond_count,
//                         mean_coordination, connected (1/0), sphere_count, shape_extents_m (3),
//                         union_extents_m (3)
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "common/provenance.hpp"
#include "geometry/template_quality.hpp"

namespace shapepress::geometry {

struct TemplateRecord {
  std::string name;
  std::string source;
  std::uint64_t seed = 0;
  double bond_multiplier = 0.0;
  SphereTemplate body;        // centres in the body frame
  MassProperties mass;        // of the template, in the body frame (diagonal inertia)
  MassProperties shape_mass;  // of the shape, in the mesh's frame
  // The body's volume in a bed (body_mass_properties): volume, and the diagonal of its inertia
  // about the body origin in the body frame (`inertia`); principal values as computed.
  MassProperties body_mass;
  double body_probe_radius = 0.0;  // m
  Vec3 body_origin = Vec3::Zero();
  Mat3 body_axes = Mat3::Identity();
  FillQuality quality;
};

// The volume a body of these sub-spheres occupies in a bed, per unit density: the union closed
// by a ball of the median sub-sphere radius (a neighbour's sub-sphere of that size cannot enter
// what the closing fills; docs/models.md, "A body's volume"), its inertia about the body origin
// (the sub-spheres' centre of mass, where the engine puts the body's) with its off-diagonal part
// in the body frame dropped. Exact for one sphere.
MassProperties body_mass_properties(const SphereTemplate& body_frame_spheres,
                                    double* probe_radius = nullptr, int cells = 320);

// Moves the filled spheres (mesh frame) into the body frame and assembles the record.
TemplateRecord make_template_record(std::string name, std::string source,
                                    const SphereTemplate& filled,
                                    const MassProperties& template_mass,
                                    const MassProperties& shape_mass, const FillQuality& quality);

void write_templates(const std::filesystem::path& path, const std::vector<TemplateRecord>& records,
                     const Provenance& provenance);
std::vector<TemplateRecord> read_templates(const std::filesystem::path& path);

}  // namespace shapepress::geometry
