#pragma once
// Sub-sphere templates from any SignedDistance (one mechanism for analytic shapes and meshes):
//  - bonded multi-sphere (BMS): equal, touching, non-overlapping spheres on a randomly oriented
//    FCC or HCP lattice, or in a jammed dense random packing (random_packing.hpp), bonded by
//    Eq. 10 of Giannis et al. 2023, |x_i - x_j| < (r_i + r_j) m_b;
//  - conventional multi-sphere (CMS): overlapping spheres, each the largest ball inscribed in the
//    shape that covers the deepest still-uncovered interior point (a distance-transform greedy
//    cover, in the spirit of OpenVDB's fillWithSpheres), with a cap on the balls that reach the
//    surface when the shape needs fewer balls than asked (a sphere needs one).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/signed_distance.hpp"

namespace shapepress::geometry {

enum class TemplateKind { bonded, rigid };  // "bms", "cms" in files and on the command line
std::string kind_name(TemplateKind kind);

using Bond = std::array<std::int32_t, 2>;

struct SphereTemplate {
  TemplateKind kind = TemplateKind::bonded;
  std::vector<Vec3> centres;  // m, in the frame of the shape they were filled into
  std::vector<double> radii;  // m
  std::vector<Bond> bonds;    // BMS only, i < j
};

// fcc, hcp: a lattice at a random orientation and offset; random: no lattice, a jammed dense
// random packing of exactly the target count (random_packing.hpp; a count, not a radius);
// shell: the same with a surface-conforming outer layer (surface_conforming_packing).
enum class Lattice { fcc, hcp, random, shell, carved };
// Whether the lattice is a random packing (random, shell, carved): a count, not a radius.
constexpr bool is_random_packing(Lattice lattice) {
  return lattice == Lattice::random || lattice == Lattice::shell || lattice == Lattice::carved;
}
// The names configs and the CLI use: "fcc", "hcp", "random", "shell", "carved".
inline constexpr const char* lattice_names[] = {"fcc", "hcp", "random", "shell", "carved"};
// The lattice of one of lattice_names; InputError listing them otherwise.
Lattice lattice_from_name(const std::string& name);
enum class Placement {
  inside,  // every sub-sphere lies wholly inside the shape
  centre   // every sub-sphere centre lies inside (spheres may cross the surface by < r)
};

struct BondedFillOptions {
  int target_count = 350;          // used when sub_sphere_radius is 0
  double sub_sphere_radius = 0.0;  // m; > 0 fixes the radius instead of the count
  Lattice lattice = Lattice::fcc;
  Placement placement = Placement::inside;
  double bond_multiplier = 1.15;  // m_b of Eq. 10 (Giannis et al. 2023 use 1.15)
  std::uint64_t seed = 1;         // lattice orientation and offset, or the random packing
  void check() const;             // InputError naming the bad field
};

// Throws ComputationError when no sub-sphere fits. Keeps the largest bonded cluster, so the
// bond graph of the result is always connected.
SphereTemplate fill_bonded(const SignedDistance& shape, const BondedFillOptions& options);

struct RigidFillOptions {
  // Balls in the template. The cover stops at this count; when the shape's medial-axis cover
  // would need fewer (a sphere needs one), the radius of the balls that reach the surface is
  // capped, as much as needed for the cover to take this many (paper Fig. 3: a sphere as 50 …
  // 3000 overlapping spheres).
  int sphere_count = 150;
  int resolution = 64;                // grid cells along the longest side of the shape's box
  double min_radius_fraction = 0.02;  // smallest sphere, as a fraction of the largest
  double max_radius = 0.0;            // m; > 0 fixes the cap instead of choosing it by the count
  // Grow every radius by one common amount until the union's volume equals the shape's: the
  // inscribed balls alone always fall short, by the slivers between them and the surface.
  bool match_volume = true;
  void check() const;
};

// What the rigid filler chose (for reports): the cap (infinity when none binds), the grid cell,
// whether the N balls cover every interior cell, and the wall seconds the fill took.
struct RigidFillInfo {
  double radius_cap = 0.0;  // m
  double grid_cell = 0.0;   // m
  bool cover_complete = true;
  double seconds = 0.0;
};

// A greedy cover of the interior voxels, deepest uncovered cell first, each by the largest
// inscribed ball through it that the cap allows: a ball that reaches the surface has a radius at
// most the cap; a larger one stays one cap below the surface (so the surface is drawn by balls
// of the cap's size and the core by few large ones). The cap is the largest for which the cover
// takes `sphere_count` balls (bisection); then every radius grows by one amount to match the
// volume. Throws InputError when the count needs balls finer than the grid.
SphereTemplate fill_rigid(const SignedDistance& shape, const RigidFillOptions& options,
                          RigidFillInfo* info = nullptr);

// Bumpiness of a union of spheres that should be a sphere of `radius` about `centre`: along
// `directions` near-uniform rays, the union's outer surface (the farthest exit from any ball)
// against the radius. Metres.
struct RadialDeviation {
  double max_abs = 0.0, rms = 0.0;
  double max_inward = 0.0;   // deepest dip below the sphere (>= 0)
  double max_outward = 0.0;  // highest bump above it (>= 0)
};
RadialDeviation radial_deviation(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                                 const Vec3& centre, double radius, int directions = 20000);

// Pairs i < j with |x_i - x_j| < (r_i + r_j) * multiplier (Eq. 10), in lexicographic order.
std::vector<Bond> pairs_within(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                               double multiplier);
// Labels of connected components (0..k-1, by first appearance) of the graph.
std::vector<int> connected_components(std::size_t node_count, const std::vector<Bond>& edges);
bool is_connected(std::size_t node_count, const std::vector<Bond>& edges);

}  // namespace shapepress::geometry
