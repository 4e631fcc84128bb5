#pragma once
// A structured quadrilateral mesh of the quarter disc r² + z² ≤ R², r, z ≥ 0: the meridian
// section of a sphere that an axisymmetric model (CalculiX CAX4) turns about the z axis, with the
// plane z = 0 a plane of symmetry. Three mapped blocks (an "O-grid"): a square core at the centre
// and two blocks between the core and the arc, so no element is degenerate at the axis or the
// pole, and no external mesher is needed.
#include <array>
#include <vector>

namespace shapepress::fem {

struct QuarterDiscMesh {
  double radius = 0.0;        // a: along r (the equator)
  double polar_radius = 0.0;  // c: along z, the pressing axis (= radius for a sphere)
  // Node i (1-based in the deck) at nodes[i - 1] = (r, z).
  std::vector<std::array<double, 2>> nodes;
  // Four 1-based node ids each, counter-clockwise in the (r, z) plane (CalculiX's CAX4 order).
  std::vector<std::array<int, 4>> quads;
  // The element faces on the arc r² + z² = R²: (1-based element id, face 1…4; face k joins the
  // element's nodes k and k + 1).
  std::vector<std::array<int, 2>> arc_faces;
  std::vector<int> axis_nodes;     // r = 0: no radial displacement
  std::vector<int> equator_nodes;  // z = 0: the symmetry plane
  int pole_node = 0;               // (0, R): the first point the plate touches
};

// `arc_elements` elements along each 45° of the arc (the core has arc_elements² elements, each
// outer block arc_elements × ⌈0.6 arc_elements⌉). The arc spacing is graded towards the pole
// (z = R), where the contact starts and its radius is smallest, and the radial spacing towards
// the surface: both sizes are what the contact's pressure distribution needs resolved.
QuarterDiscMesh quarter_disc_mesh(double radius, int arc_elements);

// The same mesh stretched along z to the quarter ellipse (r/a)² + (z/c)² ≤ 1: the meridian
// section of a spheroid with polar semi-axis c pressed along its axis of revolution. An affine
// map keeps the structure, and the arc nodes land on the ellipse.
QuarterDiscMesh stretched_to_spheroid(QuarterDiscMesh mesh, double polar_radius);

// The arc element size next to the pole, [m]: the contact's resolution at small deformation.
double pole_element_size(const QuarterDiscMesh& mesh);

}  // namespace shapepress::fem
