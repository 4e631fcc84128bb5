#pragma once
// A bed of bodies in a die: what `pack` writes and `compact --packing` reads. A body is a plain
// sphere, a bonded multi-sphere (BMS) particle or a rigid clump (CMS), each a template of `fill`
// scaled to its drawn volume-equivalent diameter, turned and placed in the periodic x/y box.
//
// packed.h5 (SI units in "unit" attributes, provenance as root attributes):
//   /                      format = "shapepress packing 1", box_x, box_y (m, the periodic
//                          cross-section), floor (m, the die floor's z), top (m, where the punch
//                          rests above the bed)
//   /templates/name        strings: "sphere", "bms/<name>", "cms/<name>"
//   /templates/source      strings: the templates file each came from ("" for sphere)
//   /templates/kind        int32: BodyKind
//   /templates/<t>/centres (N, 3), radii (N), bonds (B, 2) int32 — the template at scale 1 in
//                          its body frame (centre of mass at the origin, principal axes)
//   /bodies/template       int32 (M): index into /templates
//   /bodies/kind           int32 (M): BodyKind
//   /bodies/scale          (M): template lengths × scale
//   /bodies/orientation    (M, 4): unit quaternion w, x, y, z turning body axes into the box's
//   /bodies/centre         (M, 3) m: the centre of mass
//   /bodies/shape_volume   (M) m³: the particle shape's volume (the mesh's; a sphere's own)
//   /bodies/sphere_volume  (M) m³: Σ sub-sphere volumes (BMS, sphere), the union's (CMS)
//   /bodies/body_volume    (M) m³: the volume the body occupies in a bed (BodyTemplate); the
//                          bed's solid fraction and the body's mass are by it
//   /templates/<t>         attributes shape_volume, sphere_volume, body_volume (m³, scale 1);
//                          datasets principal_inertia (3) of the sub-spheres, body_inertia (3)
//                          of the body volume, m⁵ per unit density about the body axes
//   /bodies/first_particle (M+1) int32: body b's sub-spheres are [first[b], first[b + 1])
//   /particles/position    (N, 3) m, /particles/radius (N) m, /particles/body (N) int32
//   /bonds/pairs           (B, 2) int32: particle indices i < j of one BMS body, sorted
//   /bonds/rest_length     (B) m: the centre distance at which the bond carries no force
//   /measures/<name>       one-element datasets: what `pack` measured (PackMeasures)
// and an XDMF sidecar (packed.xmf) that shows the sub-spheres in ParaView, coloured by body.
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "common/provenance.hpp"
#include "packing/packing.hpp"
#include "simulate/rigid_body.hpp"
#include "simulate/state.hpp"

namespace shapepress::packing {

enum class BodyKind : std::int32_t { sphere = 0, bms = 1, cms = 2 };

// A template at scale 1 in its body frame.
struct BodyTemplate {
  std::string name;    // "sphere", "bms/<name>" or "cms/<name>"
  std::string source;  // the templates file it came from; empty for "sphere"
  BodyKind kind = BodyKind::sphere;
  std::vector<Vector3> centres;                    // m
  std::vector<double> radii;                       // m
  std::vector<std::array<std::int32_t, 2>> bonds;  // BMS only, i < j
  double shape_volume = 0.0;                       // m³, of the particle's shape at scale 1
  double sphere_volume = 0.0;  // m³, Σ sub-sphere volumes (BMS) or the union's (CMS)
  // m³, the volume the body occupies in a bed (geometry::body_mass_properties: the union of its
  // sub-spheres closed by a ball of their median radius; a sphere's own): its solid fraction
  // and its mass ρ × body_volume are by it, so a bed's solid fraction does not move with the
  // sub-sphere count as the mesh volume's does (docs/models.md, "A body's volume").
  double body_volume = 0.0;
  // Per unit density about the body axes, ascending, m⁵: of the sub-spheres (BMS: their sum
  // with the parallel-axis terms; CMS: the union's).
  Vector3 principal_inertia = {0.0, 0.0, 0.0};
  // Per unit density about the body axes, m⁵: of the body volume, the inertia of the body.
  Vector3 body_inertia = {0.0, 0.0, 0.0};
  // The diameter of the sphere of the shape's volume, (6 V / π)^(1/3), at scale 1.
  double volume_equivalent_diameter() const;
};

// body_volume and body_inertia from the template's sub-spheres (a template or packing written
// before body volumes were kept).
void set_body_volume(BodyTemplate& shape);

struct PackedBody {
  std::int32_t template_index = 0;
  double scale = 1.0;
  Quaternion orientation;  // body axes → box
  Vector3 centre = {0.0, 0.0, 0.0};
  double shape_volume = 0.0;   // m³, at this scale
  double sphere_volume = 0.0;  // m³, at this scale
  double body_volume = 0.0;    // m³, at this scale
};

// What `pack` measured on its bed, written to /measures and to run.json.
struct PackMeasures {
  double solid_fraction = 0.0;             // Σ body volumes / (box area × bed height)
  double solid_fraction_shape = 0.0;       // Σ shape volumes / (box area × bed height)
  double solid_fraction_spheres = 0.0;     // Σ sub-sphere volumes (CMS: unions) / the same
  double bed_height = 0.0;                 // m, highest sub-sphere top above the floor
  double coordination = 0.0;               // body–body contacts × 2 / bodies
  double x10 = 0.0, x50 = 0.0, x90 = 0.0;  // m, achieved, of the weighting
  double target_x10 = 0.0, target_x50 = 0.0, target_x90 = 0.0;  // m, asked
  // Orientation order of the bodies' long axes against the punch (z) axis, ⟨P2(cos θ)⟩:
  // 0 isotropic, 1 all along z, -1/2 all in the x/y plane.
  double orientation_order = 0.0;
  double largest_overlap = 0.0;  // m, between sub-spheres of different bodies or with a wall
  double largest_overlap_relative = 0.0;  // the same over the smaller radius
};

// Each measure as (name, SI unit, value), one table for /measures and run.json.
template <class Measures, class Visit>
void for_each_measure(Measures& m, Visit&& visit) {
  visit("solid_fraction", "1", m.solid_fraction);
  visit("solid_fraction_shape", "1", m.solid_fraction_shape);
  visit("solid_fraction_spheres", "1", m.solid_fraction_spheres);
  visit("bed_height", "m", m.bed_height);
  visit("coordination", "1", m.coordination);
  visit("x10", "m", m.x10);
  visit("x50", "m", m.x50);
  visit("x90", "m", m.x90);
  visit("target_x10", "m", m.target_x10);
  visit("target_x50", "m", m.target_x50);
  visit("target_x90", "m", m.target_x90);
  visit("orientation_order", "1", m.orientation_order);
  visit("largest_overlap", "m", m.largest_overlap);
  visit("largest_overlap_relative", "1", m.largest_overlap_relative);
}

struct BodyPacking {
  std::vector<BodyTemplate> templates;
  std::vector<PackedBody> bodies;
  // Sub-spheres of every body, body by body; first_particle has bodies.size() + 1 entries.
  SphereList particles;
  std::vector<std::int32_t> particle_body;
  std::vector<std::int32_t> first_particle;
  // Bonds within BMS bodies: particle indices i < j, sorted, and their force-free length.
  std::vector<std::array<std::int32_t, 2>> bonds;
  std::vector<double> bond_rest_length;  // m
  Box box;
  double floor = 0.0;  // m
  double top = 0.0;    // m
  PackMeasures measures;

  std::size_t size() const { return bodies.size(); }
  BodyKind kind(std::size_t body) const { return templates[bodies[body].template_index].kind; }
};

// The sub-spheres of `body` in the box: template centres × scale turned by the orientation
// and moved to the centre (not wrapped into the periodic box), radii × scale.
void place_body(const BodyTemplate& shape, const PackedBody& body, std::vector<Vector3>& centres,
                std::vector<double>& radii);

// Fills particles, particle_body, first_particle, bonds and bond_rest_length from templates and
// bodies, and the body volumes of templates and bodies that have none (set_body_volume).
void place_bodies(BodyPacking& packing);

// packed.h5 and its sidecar packed.xmf beside it, each written atomically. InputError naming the
// file when the folder cannot be written.
void write_packing(const std::filesystem::path& path, const BodyPacking& packing,
                   const Provenance& provenance);
// Whether `path` is an HDF5 file written by write_packing (a bed of bodies), as against a plain
// sphere list (packing.hpp). False for a file that is not HDF5.
bool is_body_packing(const std::filesystem::path& path);

// InputError naming the file and the dataset or attribute that is missing or inconsistent
// (a bond across bodies, a particle range that does not match, a template index out of range).
BodyPacking read_packing(const std::filesystem::path& path);

}  // namespace shapepress::packing
