#pragma once
// A dense random packing of N equal spheres inside any SignedDistance: the random alternative to
// the bonded filler's lattices (sphere_fill.hpp, BondedFillOptions::lattice = random).
//
// Why: a lattice fill has one sub-sphere at each pole of a sphere, so a plate first presses on a
// point, and its close-packed layers slip at loads that depend on N and on the lattice's
// orientation (docs/models.md, the rubber-sphere study). A random packing has no slip planes,
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
  // A surface-conforming outer layer (below): this many of the N spheres (the first ones) keep
  // their centres on the offset surface sdf = -r, so they touch the surface. 0: none.
  int shell_count = 0;
  // Shell spheres keep this × 2r apart from each other (a soft spacing that spreads them evenly
  // before they touch; below the bond reach m_b, so shell neighbours still bond).
  double shell_spacing = 1.0;
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

// A piece of a bulk random packing ("carved" fill): the shape cut out of a dense random packing
// of a larger shape, so the sub-spheres near the surface keep the bulk's structure instead of
// the layer a wall orders (a packing against a wall puts its outer sub-spheres on the wall, with
// about 5.5 bonds each against 8.5 inside: a skin whose share of the body and whose stiffness
// against bulging both grow with r/R; docs/models.md, "BMS: an elastic network, and a carved
// fill").
// How: the shape offset outward by a margin of `carve_margin` estimated sub-sphere radii is
// packed as dense_random_packing does, with enough spheres that the shape's own region holds
// more than N; the packing is then scaled about the shape's box centre by the largest factor
// s ≤ 1 at which exactly N spheres lie wholly inside the shape (each sphere's threshold s_i by
// bisection; the N largest are kept, the N-th touches the surface; scaling keeps every distance
// at least 2 s r). A kept sphere without a kept neighbour within 2r (1 + contact_gap) is dropped
// and the next one taken. Assumes the shape is star-shaped about its box centre (spheres,
// ellipsoids and most particles); costs one packing of the larger shape (about 2.5× N spheres
// for a sphere of 545-1322 sub-spheres).
RandomPacking carved_random_packing(const SignedDistance& shape,
                                    const RandomPackingOptions& options);
inline constexpr double carve_margin = 5.0;

// The surface-conforming fill: an outer layer ("shell") of spheres that all touch the surface,
// spread evenly over it, around a dense random interior. Why: in a plain random packing the
// outer spheres lie at random depths below the surface (up to a fraction of r) and at random
// places, so a plate first meets whichever sits highest, and the force at small deformation is a
// sum over a handful of randomly placed contacts (models.md, "The fill"). With every outer
// sphere's extent on the surface, the plate meets a smooth envelope (the surface offset by r,
// sampled evenly), and the number of loaded sub-spheres grows with the contact area as in the
// continuum.
// How: the same growth as dense_random_packing, with `shell_count` spheres held on the offset
// surface (projected onto sdf = -r along the gradient after each sweep, from either side) and
// the rest wholly inside. The shell count is `shell_area_fraction` of the offset surface's area
// in disks of the plain packing's radius (found first), so that the interior still jams at
// about that radius; `shell_spacing` > 1 keeps shell spheres that far apart from each other.
// How even it is, and the area fraction and spacing tried: docs/models.md, "A surface-conforming
// fill". Not the plate rig's default: its sub-spheres have few bonds into the interior, so the
// plate first presses a compliant skin, and the BMS force then depends on N more, not less
// (docs/models.md, "A surface-conforming fill").
struct ShellPackingOptions {
  RandomPackingOptions packing;
  double shell_area_fraction = 0.6;
  double shell_spacing = 1.0;  // keep < m_b so that shell neighbours bond
};
struct ShellPacking {
  RandomPacking packing;  // centres: the shell's first
  int shell_count = 0;
  double plain_radius = 0.0;  // m, the plain packing's jammed radius (the shell count's basis)
  double offset_area = 0.0;   // m², of the surface sdf = -plain_radius
};
ShellPacking surface_conforming_packing(const SignedDistance& shape,
                                        const ShellPackingOptions& options);

}  // namespace shapepress::geometry
