#pragma once
// The CalculiX input deck of the 3D plate test: the particle as C3D10 tetrahedra between two
// rigid plates (each one layer of C3D8 bricks whose nodes are all prescribed), moved towards each
// other by Δ/2 each, with penalty surface-to-surface contact. The particle's rigid-body motion is
// held by six single-point constraints at three nodes (the 3-2-1 rule: the centroid in x, y, z, a
// node on the x axis in y and z, one on the y axis in z), which are statically determinate: a
// balanced load leaves them without reaction.
#include <string>

#include "fem/calculix_deck.hpp"
#include "fem/fem_plate_config.hpp"
#include "fem/tet_mesh.hpp"

namespace shapepress::fem {

inline constexpr const char* top_plate_node_set = "TOP_PLATE";
inline constexpr const char* bottom_plate_node_set = "BOTTOM_PLATE";

// The deck's length unit puts the particle's height between 10 and 100 units (mm for the rubber
// sphere): CalculiX 2.20 refuses an element whose Jacobian determinant is below a fixed small
// number, which a 0.01 mm element of a powder particle written in mm is. Stresses stay in MPa,
// so forces are in MPa × unit².
double deck_units_per_m(double height);
// Newtons per deck force unit.
double deck_force_in_newtons(double units_per_m);

struct SolidPlates {
  double units_per_m = deck_length_per_m;  // the deck's length unit
  double top = 0.0, bottom = 0.0;          // z of the particle's highest and lowest points [m]
  double half_width = 0.0;                 // of each square plate [m]
  double contact_size = 0.0;  // element size where the plates touch [m]: penalty stiffness
};

// `mesh.anchors`: the centroid node, one on the +x axis, one on the +y axis.
std::string solid_plate_deck(const TetMesh& mesh, const SolidPlates& plates,
                             const FemPlateConfig& config);

}  // namespace shapepress::fem
