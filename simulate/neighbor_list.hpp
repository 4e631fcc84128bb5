#pragma once
// Linked cells + a Verlet half list with a skin (docs/architecture.md, "Inside the engine"):
// every pair closer than ri + rj + skin appears once, as (first < second), sorted by
// (first, second). The list is rebuilt when some sphere moved more than half the skin since the
// last build. Periodic in x and y: a pair across a boundary carries the image shift to add to
// x_second - x_first. Contact history lives in an array aligned with the pairs and is carried
// over a rebuild by merging the old and new sorted pair lists (carry_history), never hashed.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "simulate/contact_law.hpp"
#include "simulate/state.hpp"

namespace shapepress::simulate {

struct PairList {
  std::vector<std::int32_t> first;
  std::vector<std::int32_t> second;
  // The periodic image of second seen from first, as one byte per pair: the pair loop streams
  // the list every step, and two doubles of shift per pair were most of its bytes. image_shift
  // holds (x, y) for each code, to be added to x[second] - x[first].
  std::vector<std::uint8_t> image;
  std::array<double, 18> image_shift{};
  const double* shift(std::size_t p) const { return &image_shift[2 * image[p]]; }
  // Per-sphere gather lists in fixed order. Pairs are sorted by first, so the pairs where i is
  // first are the contiguous range [first_offset[i], first_offset[i+1]); the pairs where i is
  // second are second_pairs[second_offset[i] .. second_offset[i+1]) (CSR), in increasing pair
  // index, which is increasing partner index. A sphere sums its "second" pairs (partners < i),
  // then its "first" pairs (partners > i): the order of a sum over a sphere's contacts never
  // depends on threads or on the list's non-touching pairs.
  std::vector<std::int32_t> first_offset;
  std::vector<std::int32_t> second_offset;
  std::vector<std::int32_t> second_pairs;
  std::size_t size() const { return first.size(); }
};

// Builds the half list. InputError when a periodic length is not more than twice the reach
// 2 r_max + skin: then a pair could meet through two images. `rigid_group` (empty, or one entry
// per sphere): spheres of the same group ≥ 0 never pair (the sub-spheres of one rigid clump).
PairList build_pair_list(const SphereState& state, const Box& box, double skin,
                         std::span<const std::int32_t> rigid_group = {});

// History of pairs present in both lists is moved to the new list's slots; new pairs start
// from zero history. Both lists must be sorted by (first, second).
std::vector<ContactHistory> carry_history(const PairList& old_pairs,
                                          const std::vector<ContactHistory>& old_history,
                                          const PairList& new_pairs);

// Moves positions back into [0, L) in the periodic directions (only at list builds, so the
// shifts stored in the list stay valid between builds).
void wrap_positions(SphereState& state, const Box& box);
// A coordinate brought into [0, length) (unchanged when length <= 0: not periodic).
double wrapped(double v, double length);

}  // namespace shapepress::simulate
