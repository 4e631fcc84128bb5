#pragma once
// What `shapepress advise` concludes from a ladder of runs (issue 21, points 2 and 3): every
// rung (a sub-sphere count and a time-step fraction) against the finest stable rung, which rungs
// hold the answer within a tolerance, the cheapest of them, and the stability map (stable and
// within tolerance, stable but off, diverged). Running the rungs is the stage's
// (scenarios/cli_advise.cpp); this is the judgement, on curves and counted costs, so a test can
// hand it a synthetic ladder.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/curves.hpp"
#include "analysis/plot.hpp"

namespace shapepress::analysis {

// How a run of the ladder ended: its curve; exit 1, the engine's divergence checks stopped it;
// exit 2, its input checks refused the step before it ran (steps per collision, the bonds'
// stability limit).
enum class RunEnd { finished, diverged, refused };

// A compaction rung's numbers beside its curve (analysis/compaction.hpp's, from its punch.csv):
// what the report states per bed, so a pick holds them too, not the curve alone.
struct CompactionFigures {
  double peak_stress = 0.0;       // Pa
  double elastic_recovery = 0.0;  // (H_unloaded − H_min)/H_min
  double yield_pressure = 0.0;    // Heckel's Py [Pa]
};

// One run of the ladder as it ended.
struct Rung {
  std::string label;              // its folder under the advise folder
  int sub_spheres = 0;            // the count asked of the filler (1: one sphere)
  double time_step_fraction = 0;  // of the critical step
  double density_scale = 1.0;     // a compaction's mass scaling (run.density_scale)
  int seed = 0;                   // a compaction's packing seed: rungs of one seed share a bed
  RunEnd end = RunEnd::finished;
  std::string cause;    // a named cause ("overlap", "energy", "non-finite", …) when not finished
  std::string message;  // the run's error line when not finished
  bool stable() const { return end == RunEnd::finished; }
  Curve curve;  // force against deformation (stress against strain) on loading
  // The run's counted cost (simulate/work_count.hpp: its sub-sphere-steps, contact-steps and
  // bond-steps summed; its run.json's counted_cost), the same on any machine and under any load:
  // what the pick goes by. < 0: unknown.
  std::int64_t counted_cost = -1;
  double cpu_seconds = -1.0;  // of the whole run, measured, reported beside it (< 0: unknown)
  std::optional<CompactionFigures> compaction;  // a compaction rung's peak, recovery and Py
};

enum class RungStatus { reference, within, off, diverged, refused };
// "reference", "within", "off", "diverged", "refused"
const char* status_name(RungStatus status);

struct AdviceRow {
  const Rung* rung = nullptr;
  RungStatus status = RungStatus::diverged;
  CurveDifference versus_reference;  // zero for the reference and for rungs without a curve
  // Compaction rungs: relative differences (rung − reference)/reference of the peak stress,
  // the elastic recovery and Py (NaN, and not in the error, where either value is not finite:
  // Py of a bed that never yields); zero otherwise.
  double peak_difference = 0.0, recovery_difference = 0.0, yield_pressure_difference = 0.0;
  // What the tolerance is held against: the curve's RMS relative difference, and for a
  // compaction rung the largest of it and the three figures' |differences|.
  double error = 0.0;
};

struct Advice {
  std::vector<AdviceRow> rows;  // in the order of the rungs
  double tolerance = 0.05;      // on the RMS relative difference from the reference
  double from = 0.05, to = 0.40;
  std::optional<std::size_t> reference;  // row of the finest stable rung (of the first seed)
  std::vector<std::size_t> references;   // the finest stable rung of each seed
  // The largest error of another seed's finest rung from the first seed's (of the same setting);
  // empty with one seed.
  std::optional<double> seed_scatter;
  std::optional<std::size_t> pick;  // row of the cheapest setting within the tolerance
};

// The reference is the stable rung with the most sub-spheres, of those the one with the smallest
// time-step fraction, then the smallest density scale. Every other stable rung is compared with
// it by the RMS relative difference of the force over [from, to] (clipped to the deformation
// every stable rung reaches), as the plate study compares each N with the finest
// (plate_study.hpp), and is `within` when its error is at most the tolerance. Compaction rungs
// (those with figures) are compared from where the reference's stress first reaches a tenth of
// its peak (below it the relative difference of a near-zero stress measures nothing, as the
// quasi-static figures start there too), and their error also takes the peak stress, the elastic
// recovery and Py. With several seeds (packings of the same bed) each rung is compared with its
// own seed's finest; a setting holds when its rung of every seed does, and the seeds' finest
// rungs against the first seed's give the seed-to-seed scatter. The pick is the setting that
// holds of least counted cost (summed over the seeds; its row of the first seed; a rung of unknown
// cost only when no other holds), never of least CPU seconds, which a loaded machine changes;
// ties go to fewer sub-spheres, then the larger step. No reference when no rung is stable.
Advice advise(const std::vector<Rung>& rungs, double tolerance, double from = 0.05,
              double to = 0.40);

// advice.csv: label, status, cause ("-" for a finished run), sub_spheres, time_step_fraction,
// density_scale, seed, counted_cost, cpu_s (nan when unknown), rms_vs_reference, max_vs_reference,
// and for compaction rungs peak_vs_reference, recovery_vs_reference, py_vs_reference (signed),
// peak_stress_Pa, elastic_recovery, yield_pressure_Pa (nan without a curve or for plate rungs),
// error (what the tolerance judged), picked (1 or 0).
void write_advice_csv(const std::filesystem::path& path, const Advice& advice);

// An advise folder read back (report --advice): advice.csv's rows as rungs without their curves,
// the judgement as advise made it, and the facts of its run.json (pick, cost, scatter).
struct AdviceRecord {
  std::filesystem::path folder;
  std::shared_ptr<const std::vector<Rung>> rungs;  // what advice.rows point into
  Advice advice;
  bool compaction = false;          // a bed's ladder (the table has its peak, recovery and Py)
  std::optional<std::string> pick;  // run.json's pick, reference and their numbers
  std::optional<std::string> reference;
  std::optional<double> pick_error;
  // The reference's counted cost over the pick's, and the full run's predicted counted cost; the
  // same by the CPU seconds measured, beside them.
  std::optional<double> cost_saved_factor, predicted_full_run_counted_cost;
  std::optional<double> cpu_saved_factor, predicted_full_run_cpu_s;
  int full_bodies = 0;  // a bed's ladder: the full bed whose cost is predicted (0: a plate ladder)
};
// InputError naming the folder or file when it is not an advise folder (run.json of stage
// advise, advice.csv with advise's columns).
AdviceRecord read_advice(const std::filesystem::path& folder);

// Speed against accuracy: the error from the reference against the counted cost, one series
// per time-step fraction, the tolerance line and the pick (as the plate study's chart).
Chart speed_accuracy_chart(const Advice& advice);
// The stability map: time-step fraction against sub-sphere count, one series per status; at one
// count and several mass scalings against the mass scaling (log axis); with several of both, one
// series per status and mass scaling.
Chart stability_map_chart(const Advice& advice);

}  // namespace shapepress::analysis
