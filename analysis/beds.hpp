#pragma once
// What a compaction's bed was before the punch pressed it, and what its bodies are like, for the
// report's table of beds and its shape-effect charts (peak stress, elastic recovery and Py
// against the bodies' aspect ratio; paper §4.4, Fig. 8). Followed as typed data from the run's
// run.json to the `pack` that made its packing (that pack's run.json: settled and pre-compressed
// solid fraction, loop seconds) and measured on the packing itself (packed.h5: the projected
// aspect ratio of every body as an image of it would measure it).
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "analysis/compaction.hpp"

namespace shapepress::analysis {

// The sub-spheres of one body, in any frame.
struct SphereUnion {
  std::vector<std::array<double, 3>> centre;  // m
  std::vector<double> radius;                 // m
};

// Feret min / Feret max of the silhouette of a union of spheres seen along `direction` (a unit
// vector): the silhouette is a union of discs, whose caliper width at in-plane angle φ is
// max(c·u + r) − min(c·u − r). Sampled every 2° and refined around the narrowest and widest
// sample by golden section, to 1e-6 of the width.
double projected_aspect_ratio(const SphereUnion& body, const std::array<double, 3>& direction);

// `directions` viewing directions uniform on the sphere, the same for every caller with one seed:
// the mean over them is the aspect ratio an image of the body lying at random measures on
// average (imaging's Feret min/max, the paper's ASR of Fig. 7).
std::vector<std::array<double, 3>> viewing_directions(int directions, std::uint64_t seed = 1);
double mean_projected_aspect_ratio(const SphereUnion& body,
                                   const std::vector<std::array<double, 3>>& directions);

struct BedFacts {
  std::string particle_kind;  // compact's run.json: sphere, bms or cms
  std::int64_t bodies = 0;    // bodies, or spheres for a bed of plain spheres
  double sub_spheres_per_body = 1.0;
  // By shape volume: after the pack's settle under gravity, and what its punch pressed the bed
  // to (absent: not pre-compressed). A bed `compact` poured itself: the solid fraction at the
  // start of the loading, as settled.
  std::optional<double> settled_solid_fraction, precompression_solid_fraction;
  // The bodies' mean projected aspect ratio and its standard deviation over the bodies (1 for
  // spheres).
  std::optional<double> projected_aspect_ratio, projected_aspect_ratio_sd;
  // Wall seconds of the pack's and the compaction's stepping loops (run.json loop_s).
  std::optional<double> pack_seconds, compaction_seconds;
  // Why a fact is missing: a packing moved, changed since the run, or not made by `pack`.
  std::vector<std::string> notes;
};

// The facts of the compaction run whose run.json is `run_json` and whose curve is `curve`. A
// relative input path is looked for from the working directory, then from the run folder's
// parent. Never throws for a missing or changed packing: the notes say why facts are missing.
BedFacts bed_facts(const std::filesystem::path& run_json, const PunchCurve& curve,
                   int directions = 64);

}  // namespace shapepress::analysis
