#pragma once
// A denser start for pack's settle ([settle] insertion = "deposit"): the bodies the pour inserted
// (insert_bodies: bounding spheres apart in a region several times the settled bed's height) are
// laid down geometrically before the gravity settle, so that the settle starts from a bed near
// its settled height and has little to fall and little to bring to rest.
//
// The lay-down is a zero-temperature Monte Carlo of the bed's potential energy under gravity
// (a "drop and shake" deposition, in the manner of Visscher & Bolsterli 1972, Nature 239, 504, for
// bodies of sub-spheres): sweep after sweep, the bodies in order of height, lowest first, each is
// moved straight down to its first contact with the floor or another body (the largest drop
// found exactly from the sub-sphere pairs, no stepping), then tries a few random moves (a shift in
// x/y and a small turn), each kept only when, dropped again, it leaves the body lower. No two
// bodies' sub-spheres ever overlap and no sub-sphere passes the floor; the bodies keep their
// sizes and templates, so the drawn size distribution is the pour's.
#include <cstdint>
#include <vector>

#include "packing/body_packing.hpp"
#include "packing/packing.hpp"

namespace shapepress::packing {

// 10 sweeps of 30 moves: with 4 of 8 a bed of 150 BMS spheres (seed 1) was laid on single
// contacts and collapsed, its settle 33,200 steps against the pour's 30,600; with 10 of 30 it
// settled in 17,000 (docs/measurements.md, "A denser start for pack"). The lay-down costs
// seconds where the settle costs minutes.
struct DepositionMoves {
  int sweeps = 10;          // passes over the bed, lowest body first
  int trials = 30;          // random moves per body per sweep
  double shift = 0.5;       // largest x/y shift of a move, in the body's bounding radius
  double turn = 0.5;        // largest turn of a move, rad, about a random axis
  double clearance = 1e-3;  // left between touching sub-spheres, in the smallest radius
  std::uint64_t seed = 1;
};

// Lays `bodies` (placed without overlap, centres anywhere above `floor`) down in the periodic
// box of lengths box.length_x, box.length_y; returns the highest reach of a body's bounding
// sphere above its centre (m), the top of the laid bed's bounding spheres. Orientations change by
// the turns; centres are wrapped into the box in x and y.
double deposit_bodies(const std::vector<BodyTemplate>& templates, std::vector<PackedBody>& bodies,
                      const Box& box, double floor, const DepositionMoves& moves);

// The largest overlap between sub-spheres of different bodies (periodic in x and y), and of a
// sub-sphere through the floor, in m; 0 when none overlap (the check of a start without overlap).
double largest_start_overlap(const std::vector<BodyTemplate>& templates,
                             const std::vector<PackedBody>& bodies, const Box& box, double floor);

}  // namespace shapepress::packing
