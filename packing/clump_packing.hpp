#pragma once
// Rigid clumps (CMS particles) poured into a compaction box by `compact`'s [clumps]: templates
// (BodyTemplate: a templates file's /cms groups, load_body_templates, or given inline in the
// config) placed at random positions and orientations where they overlap nothing (random
// sequential insertion of their bounding spheres) by pour(), then settled with the rest of the
// bed by settle_for_time (pack.hpp) and compacted.
#include <cstdint>
#include <random>
#include <vector>

#include "packing/body_packing.hpp"
#include "simulate/clumps.hpp"
#include "simulate/state.hpp"

namespace shapepress::packing {

using namespace simulate;

// A uniformly random rotation (Shoemake 1992: a uniform point on the unit 3-sphere).
Quaternion random_rotation(std::mt19937_64& random);

struct ClumpInsertion {
  // Used in turn: their name, sub-sphere centres (any origin: add_clump finds the centre of
  // mass) and radii.
  std::vector<BodyTemplate> templates;
  std::int64_t count = 0;
  double z_low = 0.0, z_high = 0.0;  // region the clumps lie in, their whole reach inside it
  std::uint64_t seed = 1;
  int attempts_per_clump = 1000;
  int integration_cells = 128;  // voxels along a clump's longest side (mass, inertia)
};

// Appends `count` clumps of `density` and `material` to `state` and `clumps`, each a template
// turned by a uniformly random rotation and placed at a random point of the periodic box where
// its bounding sphere overlaps no sphere already in `state` and no other clump's. InputError
// when a clump cannot be placed in attempts_per_clump tries, or for a bad template (add_clump).
void insert_clumps(SphereState& state, ClumpSet& clumps, const Box& box,
                   const ClumpInsertion& request, double density, int material);

}  // namespace shapepress::packing
