#pragma once
// Sub-sphere templates from any SignedDistance (one mechanism for analytic shapes and meshes):
//  - bonded multi-sphere (BMS): equal, touching, non-overlapping spheres on a randomly oriented
//    FCC or HCP lattice, or in a jammed dense random packing (random_packing.hpp), bonded by
//    Eq. 10 of Giannis et al. 2023, |x_i - x_j| < (r_i + r_j) m_b;
//  - conventional multi-sphere (CMS): overlapping spheres, each the largest ball inscribed in the
//    shape that covers the deepest still-uncovered interior point (a distance-transform greedy
//    cover, in the spirit of OpenVDB's fillWithSpheres).
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
// random packing of exactly the target count (random_packing.hpp; a count, not a radius).
enum class Lattice { fcc, hcp, random };
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
  int sphere_count = 150;
  int resolution = 64;                // grid cells along the longest side of the shape's box
  double min_radius_fraction = 0.02;  // smallest sphere, as a fraction of the largest
  // Grow every radius by one common amount until the union's volume equals the shape's: the
  // inscribed balls alone always fall short, by the slivers between them and the surface.
  bool match_volume = true;
  void check() const;
};
SphereTemplate fill_rigid(const SignedDistance& shape, const RigidFillOptions& options);

// Pairs i < j with |x_i - x_j| < (r_i + r_j) * multiplier (Eq. 10), in lexicographic order.
std::vector<Bond> pairs_within(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                               double multiplier);
// Labels of connected components (0..k-1, by first appearance) of the graph.
std::vector<int> connected_components(std::size_t node_count, const std::vector<Bond>& edges);
bool is_connected(std::size_t node_count, const std::vector<Bond>& edges);

}  // namespace shapepress::geometry
