#pragma once
// How big a bed (issue 40, point 3): from finished compactions of one powder at several bed sizes
// (bodies) and resolutions (sub-spheres per body), each packed with several seeds, which setting
// gives the largest, finest bed's answer within a tolerance, how many seeds bring its scatter
// under the tolerance, and at what predicted cost. Running the beds is the pipeline's or the
// user's; this is the judgement, on the figures and counted costs, so a test can hand it a
// synthetic ladder whose answer is known.
//
// A bed's figures scatter from one packing to the next (docs/measurements.md: ±15–20 % in the
// peak at 150 bodies), so a setting is judged by its seeds' mean against the reference's mean,
// and a single packing of it by its seeds' spread:
//   bias    = max over the figures of |mean − mean_ref| / mean_ref,
//   scatter = max over the figures of (sample standard deviation) / mean,
//   seeds   = ⌈(scatter / tolerance)²⌉, the packings whose mean has a standard error within the
//             tolerance (1 when the scatter already is),
//   cost    = the mean counted cost of one of its runs × seeds.
// The setting holds when its bias is within the tolerance; the pick is the holding setting of
// least cost (ties: fewer bodies, then fewer sub-spheres). The bias's own standard error
// (√(s²/n + s_ref²/n_ref) / mean_ref) is stated beside it: a bias smaller than it is not resolved
// by the seeds run, and `resolved` says whether bias + 2 standard errors is within the tolerance.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "analysis/plot.hpp"

namespace shapepress::analysis {

// One finished compaction of the ladder.
struct BedRun {
  std::string label;  // its folder
  int bodies = 0;
  int sub_spheres = 0;  // per body; 1: plain spheres
  std::uint64_t seed = 0;
  double bed_height_diameters = 0.0;  // the packed bed's height over the bodies' x50 (0: unknown)
  double peak_stress = 0.0;           // Pa
  double elastic_recovery = 0.0;      // fraction
  double yield_pressure = 0.0;        // Heckel's Py, Pa (not finite: not judged)
  std::int64_t counted_cost = -1;     // its run.json's counted_cost; < 0: unknown
};

// A figure's seeds: mean and sample standard deviation (NaN with one seed).
struct SeedStatistics {
  double mean = 0.0;
  double standard_deviation = 0.0;
  int seeds = 0;
};

enum class BedFigure { peak_stress, elastic_recovery, yield_pressure };
inline constexpr BedFigure bed_figures[] = {BedFigure::peak_stress, BedFigure::elastic_recovery,
                                            BedFigure::yield_pressure};
// "peak_stress", "elastic_recovery", "yield_pressure"
const char* figure_name(BedFigure figure);
double figure_of(const BedRun& run, BedFigure figure);

struct BedSetting {
  int bodies = 0;
  int sub_spheres = 0;
  std::vector<std::size_t> runs;      // into the ladder, in its order
  SeedStatistics figures[3];          // by BedFigure
  double bed_height_diameters = 0.0;  // the mean over its runs
  double bias = 0.0;                  // largest relative difference of a mean from the reference's
  double bias_standard_error = 0.0;   // of that figure's difference; NaN when a side has one seed
  double scatter = 0.0;               // largest relative standard deviation; NaN with one seed
  int seeds_needed = 1;          // ⌈(scatter/tolerance)²⌉; the seeds run when scatter is NaN
  double cost_per_run = -1.0;    // mean counted cost of its runs; < 0: unknown
  double predicted_cost = -1.0;  // cost_per_run × seeds_needed; < 0: unknown
  bool reference = false;
  bool holds = false;     // bias within the tolerance
  bool resolved = false;  // bias + 2 standard errors within the tolerance
};

struct BedSizeAdvice {
  double tolerance = 0.05;
  std::vector<BedSetting> settings;  // by bodies, then sub-spheres
  std::size_t reference = 0;         // the most bodies, then the most sub-spheres
  std::optional<std::size_t> pick;   // the holding setting of least predicted cost
};

// InputError when the ladder is empty, or a run's figures or counts are not positive and finite
// (a peak, a recovery ≥ 0, bodies and sub-spheres ≥ 1; Py may be infinite: a bed that never
// yields is then not judged on it), naming the run.
BedSizeAdvice advise_bed_size(const std::vector<BedRun>& ladder, double tolerance);

// bed_size.csv: one row per setting (bodies, sub_spheres, seeds, bed_height_diameters, each
// figure's mean and standard deviation, bias, bias_standard_error, scatter, seeds_needed,
// cost_per_run, predicted_cost, reference, holds, resolved, picked), a comment naming the rules.
void write_bed_size_csv(const std::filesystem::path& path, const BedSizeAdvice& advice);

// A figure against the bodies, one series per sub-sphere count, with the seeds' standard deviation
// as error bars (bed_size_<figure>.svg).
Chart bed_size_chart(const BedSizeAdvice& advice, BedFigure figure);
// Speed against accuracy for beds: the bias against the predicted cost (log axis), one series of
// the bed sizes at the reference's resolution and one of the resolutions at the reference's bed
// size, and the tolerance as a dashed line.
Chart bed_speed_accuracy_chart(const BedSizeAdvice& advice);

}  // namespace shapepress::analysis
