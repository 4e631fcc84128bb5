#pragma once
// `shapepress advise` on a compaction config (issue 21, point 2): the bed's templates re-filled
// at each sub-sphere count and re-packed with the same seed (the same bodies, sizes and places
// drawn; only their sub-spheres differ), each reduced bed pressed at every time-step fraction
// and mass scaling of the ladder, and every rung judged against the finest on the stress–strain
// curve, the peak stress, the elastic recovery and Py (analysis/advise.hpp).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/stage.hpp"

namespace shapepress::scenarios {

struct CompactionAdviseRequest {
  std::string config;       // the compact config (with [punch])
  std::string templates;    // fill's templates.h5; its run.json names the meshes and options
  std::string pack_config;  // pack's config of the bed
  std::string out;
  std::vector<int> counts;             // sub-spheres per body; 1: a bed of plain spheres
  std::vector<double> fractions;       // of the critical step; empty: the config's
  std::vector<double> density_scales;  // run.density_scale; empty: the config's
  int bodies = 0;                      // of the reduced bed; 0: the pack config's count
  int full_bodies = 0;                 // of the run whose cost is predicted; 0: the same
  // pack's seeds (packings of the same bed, for the seed-to-seed scatter); empty: the config's
  std::vector<std::uint64_t> seeds;
  // The curve's abscissa: "strain" (from the punch's start) or "solid_fraction" (by shape
  // volume; beds packed to different densities compared where they are equally dense).
  std::string curve_axis = "strain";
  // Finished compact runs of the same bed made outside the ladder (a full study's, at a count the
  // ladder cannot afford), each taken as a rung of its seed: the finest, when it is.
  std::vector<std::string> reference_runs;
  double tolerance = 0.05;
  bool resume = false;
};

// Runs the ladder in request.out (beds in bed-<N>/, rungs in <kind>-<N>-f<fraction>-s<scale>/),
// writes advice.csv, speed_accuracy.svg, stability_map.svg and run.json; 0 with a pick,
// ComputationError (exit 1) when no rung finished.
int run_compaction_advise(const CompactionAdviseRequest& request, const RunContext& context);

}  // namespace shapepress::scenarios
