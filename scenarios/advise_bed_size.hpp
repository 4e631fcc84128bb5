#pragma once
// `shapepress advise --bed-runs` (issue 40, point 3): finished compactions of one powder at
// several bed sizes and resolutions, each packed with its own seed (a study's ladder, run by its
// pipeline locally or through Slurm), judged by analysis/bed_size.hpp: the bodies, sub-spheres
// and seeds that give the largest, finest bed's peak, recovery and Py within the tolerance, and
// their predicted cost.
#include <string>
#include <vector>

#include "common/stage.hpp"

namespace shapepress::scenarios {

struct BedSizeAdviseRequest {
  std::vector<std::string> runs;  // compact run folders (punch.csv, run.json)
  std::string out;
  double tolerance = 0.05;
};

// Writes bed_size.csv, bed_size_{peak_stress,elastic_recovery,yield_pressure}.svg,
// bed_speed_accuracy.svg (when gnuplot is there) and run.json into request.out; 0 with a pick,
// ComputationError (exit 1) when no setting holds the reference's answer; InputError naming the
// run when one is not a finished compaction of a packed bed, or when two runs press one packing.
int run_bed_size_advise(const BedSizeAdviseRequest& request, const RunContext& context);

}  // namespace shapepress::scenarios
