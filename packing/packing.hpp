#pragma once
// Plain-sphere packings for `compact --packing`: read from a plain `x y z r` text file or an
// HDF5 file (/particles/position N×3, /particles/radius N); and the random sequential insertion
// of non-overlapping spheres into the box that pours a compact config's [generate] (settled by
// pack's settle phase, settle_for_time in pack.hpp).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "simulate/state.hpp"

namespace shapepress::packing {

using namespace simulate;

struct SphereList {
  std::vector<double> x, y, z, radius;  // m
  std::size_t size() const { return radius.size(); }
};

// `x y z r` per line in metres; '#' starts a comment. InputError naming file and line.
SphereList read_sphere_text(const std::filesystem::path& path);
// /particles/position (N×3) and /particles/radius (N), as written by snapshots and `pack`.
SphereList read_sphere_hdf5(const std::filesystem::path& path);
// By extension: .h5/.hdf5 → HDF5, anything else → text.
SphereList read_spheres(const std::filesystem::path& path);

// A particle size distribution given by quantiles, as a laser or image analyser reports it
// (paper Table 2: x10, x50, x90 of Q3): Q(x) is interpolated linearly in (ln x, probit Q)
// between the points and extrapolated with the end segments (a log-normal piece between each
// pair of quantiles), truncated to [diameter_min, diameter_max] of the request.
struct SizeQuantiles {
  std::vector<double> diameters;  // m, increasing
  std::vector<double> levels;     // Q at each diameter, increasing in (0, 1)
  bool volume_weighted = true;    // Q3 (mass) or Q0 (number)
  void check() const;             // InputError naming what is wrong
};

// Number-weighted cumulative distribution of the truncated distribution on a log grid of
// diameters, for sampling by inversion (and for tests).
struct SizeTable {
  std::vector<double> diameter;    // m, increasing from diameter_min to diameter_max
  std::vector<double> cumulative;  // Q0 in [0, 1]
  double sample(double u) const;   // the diameter at Q0 = u
};
SizeTable size_table(const SizeQuantiles& quantiles, double diameter_min, double diameter_max);
// The fraction of the stated weighting's distribution between diameter_min and diameter_max
// (Q(max) - Q(min)), to refuse a truncation that keeps (almost) nothing.
double retained_fraction(const SizeQuantiles& quantiles, double diameter_min, double diameter_max);

struct InsertionRequest {
  std::int64_t count = 0;
  double diameter_min = 0.0;  // diameters uniform in [min, max], or the truncation of `sizes`
  double diameter_max = 0.0;
  double z_low = 0.0;  // region where centres may go, with the radius kept inside it
  double z_high = 0.0;
  std::uint64_t seed = 1;
  int attempts_per_sphere = 1000;
  std::optional<SizeQuantiles> sizes = std::nullopt;  // else uniform diameters
};

// Random sequential insertion, periodic in x/y over the box. InputError when a sphere cannot be
// placed in `attempts_per_sphere` tries (the region is too small for the count).
SphereList insert_random_spheres(const Box& box, const InsertionRequest& request);

// The same spheres numbered in cell order (z, then y, then x, cells of size `cell`): spheres that
// touch then get nearby indices, which the engine's force loop wants (chunks of consecutive
// spheres, engine.hpp SphereSums, and its caches); random insertion order scatters every
// sphere's neighbours over the whole bed.
SphereList in_cell_order(const SphereList& list, double cell);

// Spheres into a state, all of one material and density.
SphereState make_state(const SphereList& spheres, double density, int material);

}  // namespace shapepress::packing
