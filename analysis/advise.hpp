#pragma once
// What `shapepress advise` concludes from a ladder of runs (issue 21, points 2 and 3): every
// rung (a sub-sphere count and a time-step fraction) against the finest stable rung, which rungs
// hold the answer within a tolerance, the cheapest of them, and the stability map (stable and
// within tolerance, stable but off, diverged). Running the rungs is the stage's
// (scenarios/cli_advise.cpp); this is the judgement, on curves and CPU seconds, so a test can
// hand it a synthetic ladder.
#include <filesystem>
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

// One run of the ladder as it ended.
struct Rung {
  std::string label;              // its folder under the advise folder
  int sub_spheres = 0;            // the count asked of the filler (1: one sphere)
  double time_step_fraction = 0;  // of the critical step
  RunEnd end = RunEnd::finished;
  std::string cause;    // a named cause ("overlap", "energy", "non-finite", …) when not finished
  std::string message;  // the run's error line when not finished
  bool stable() const { return end == RunEnd::finished; }
  Curve curve;                // force against deformation along the loading
  double cpu_seconds = -1.0;  // of the whole run (< 0: unknown)
};

enum class RungStatus { reference, within, off, diverged, refused };
// "reference", "within", "off", "diverged", "refused"
const char* status_name(RungStatus status);

struct AdviceRow {
  const Rung* rung = nullptr;
  RungStatus status = RungStatus::diverged;
  CurveDifference versus_reference;  // zero for the reference and for rungs without a curve
};

struct Advice {
  std::vector<AdviceRow> rows;  // in the order of the rungs
  double tolerance = 0.05;      // on the RMS relative difference from the reference
  double from = 0.05, to = 0.40;
  std::optional<std::size_t> reference;  // row of the finest stable rung
  std::optional<std::size_t> pick;       // row of the cheapest rung within the tolerance
};

// The reference is the stable rung with the most sub-spheres, of those the one with the smallest
// time-step fraction. Every other stable rung is compared with it by the RMS relative difference
// of the force over [from, to] (clipped to the deformation every stable rung reaches), as the
// plate study compares each N with the finest (plate_study.hpp), and is `within` when that is at
// most the tolerance. The pick is the within (or reference) rung of least CPU seconds; ties go to
// fewer sub-spheres, then the larger step. No reference when no rung is stable.
Advice advise(const std::vector<Rung>& rungs, double tolerance, double from = 0.05,
              double to = 0.40);

// advice.csv: label, status, cause ("-" for a finished run), sub_spheres, time_step_fraction,
// cpu_s, rms_vs_reference, max_vs_reference (nan without a curve), picked (1 or 0).
void write_advice_csv(const std::filesystem::path& path, const Advice& advice);

// Speed against accuracy: the RMS difference from the reference against CPU seconds, one series
// per time-step fraction, the tolerance line and the pick (as the plate study's chart).
Chart speed_accuracy_chart(const Advice& advice);
// The stability map: time-step fraction against sub-sphere count, one series per status.
Chart stability_map_chart(const Advice& advice);

}  // namespace shapepress::analysis
