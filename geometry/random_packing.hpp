#pragma once
// A dense random packing of N equal spheres inside any SignedDistance: the random alternative to
// the bonded filler's lattices (sphere_fill.hpp, BondedFillOptions::lattice = random).
//
// Why: a lattice fill has one sub-sphere at each pole of a sphere, so a plate first presses on a
// point, and its close-packed layers slip at loads that depend on N and on the lattice's
// orientation (README "Models", the rubber-sphere study). A random packing has no slip planes,
// is isotropic on average, and its outer sub-spheres lie on the shape's surface (the walls order
// a random packing), so a plate meets a cap of spheres.
//
// How (a Lubachevsky–Stillinger growth in spirit, with overlap relaxation instead of
// event-driven dynamics, as in the force-biased packings of Bezrukov, Bargieł & Stoyan 2002):
// N centres at uniform random points inside the shape at a loose radius; then the radius grows
// by a factor, and a relaxation that moves every pair apart by its overlap and every sphere back
// inside by its excursion (along the distance gradient) removes the overlaps. A growth step that
// cannot be relaxed within its iteration budget is undone and retried with half the factor; the
// growth stops when the factor falls below `jam_tolerance`: the packing is jammed, so nearly
// every sphere touches its neighbours. Spheres left in a cage without a neighbour within
// `contact_gap` (rattlers) are then moved onto their nearest neighbour, which keeps every other
// distance at least 2r. The final radius is the exact overlap-free one.
#include <cstdint>
#include <vector>

#include "geometry/signed_distance.hpp"

namespace shapepress::geometry {

struct RandomPackingOptions {
  int count = 350;
  bool wholly_inside = true;    // spheres inside the shape (else only their centres)
  std::uint64_t seed = 1;       // the initial random centres
  double jam_tolerance = 1e-3;  // smallest radius growth factor tried before calling it jammed
  int relaxation_steps = 300;   // iteration budget of one growth step
  double contact_gap = 0.15;    // rattler test: no neighbour within 2r (1 + gap)
};

struct RandomPacking {
  std::vector<Vec3> centres;    // m
  double radius = 0.0;          // m, equal for all; no two spheres overlap, none leaves the shape
  double solid_fraction = 0.0;  // N (4/3) π r³ / the shape's volume (grid estimate)
  int growth_steps = 0;         // accepted radius growths (diagnostics)
  int rattlers_moved = 0;
};

// Throws ComputationError when `count` centres cannot be placed inside the shape.
RandomPacking dense_random_packing(const SignedDistance& shape,
                                   const RandomPackingOptions& options);

}  // namespace shapepress::geometry
