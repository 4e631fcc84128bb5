#pragma once
// Calibration on a compaction curve (docs/stages.md, "calibrate"), as Giannis et al. 2023
// calibrated k1 to their experiment: the named contact or bond parameters that make a
// compaction run match a measured curve (stress against strain, or solid fraction against
// stress) over a window, by a bounded search (BOBYQA or Nelder–Mead) on the parameters'
// logarithms. Every evaluation
// presses the same bed (the config's, settled once with its own values, or the packing given),
// so the objective changes with the parameters only, not with a new pour.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>
#include "scenarios/namespaces.hpp"

#include "analysis/measured_curve.hpp"
#include "scenarios/calibrate.hpp"
#include "scenarios/compact_setup.hpp"
#include "scenarios/config_io.hpp"

namespace shapepress::scenarios {

// Names of the parameters a compaction calibration can fit, each in the config's SI unit:
//   loading_stiffness       k1 [N/m^1.5] of every multi-contact interaction of the particles
//   loading_modulus         E_L [Pa] of the particle material: k1 = 4/3 E*_L √R* per contact
//                           (its youngs_modulus when the config states none)
//   youngs_modulus          E [Pa] of the particle material (k1 = 4/3 E* √R* when k1 is absent)
//   plasticity_ratio        λp in (0, 1] of every multi-contact interaction of the particles
//   multicontact_prefactor  β of the same interactions
//   normal_stiffness, shear_stiffness   [bond] k̄n, k̄s [N/m³] of a packing's BMS bodies
//   modulus                 [bond] Ē [Pa] (a modulus_fraction moves with it)
//   yield_stress, shear_yield_stress, hardening_ratio   σy, τy [Pa] and H of elastic_plastic
//                           bonds: the bodies' yield
std::vector<std::string> compaction_parameter_names();

// Reads and writes one named parameter (InputError for an unknown name, or one the config does
// not have: no multi-contact interaction, no [bond]). A config whose multi-contact law takes k1
// from E has no loading_stiffness: then get_parameter gives Hertz's 4/3 E* √R* for two spheres
// of the mean of [generate]'s diameter bounds, where there is a [generate].
double get_parameter(const CompactConfig& config, const std::string& name);
void set_parameter(CompactConfig& config, const std::string& name, double value);

// The two forms of the loading branch's stiffness carried into each other at one size: a k1 fitted
// for the bed states the loading modulus E_L with k1 = 4/3 E*_L √R* between two particles of the
// bed's mean diameter d (R* = d/4, E*_L = E_L / (2 (1 - ν²)), the particle's own ν), and back.
// The rule that keeps a calibrated k1 the same material at another size (docs/models.md, "One
// material"); `calibrate` states it beside what it fitted.
double implied_loading_modulus(double loading_stiffness, double diameter, double poisson_ratio);
double implied_loading_stiffness(double loading_modulus, double diameter, double poisson_ratio);

// The bed every evaluation presses: a packing (`pack`'s bodies, or spheres), or the config's
// [generate] bed settled once.
struct CompactionBed {
  std::optional<BodyPacking> bodies;
  std::optional<SphereList> spheres;
  double punch = 0.0;  // where the punch starts above a settled bed (NaN: the config's)
};
// `packing` empty: generate and settle `config`'s bed once. InputError for [clumps].
CompactionBed compaction_bed(const CompactConfig& config, const std::filesystem::path& packing);

// One compaction of the bed: its records, the prepared run (engine, setup, H0) and its summary.
struct CompactionTrial {
  std::vector<PunchRecord> records;
  PreparedCompaction prepared;
  CompactionSummary summary;
  double wall_seconds = 0.0;
};
CompactionTrial run_compaction_trial(const CompactConfig& config, const CompactionBed& bed);

// The trial's loading branch on the measured curve's axes against the measured curve over
// [from, to] (analysis/measured_curve.hpp).
analysis::MeasuredMismatch trial_mismatch(const CompactionTrial& trial,
                                          const analysis::MeasuredCurve& reference, double from,
                                          double to);

struct CompactionCalibrationOptions {
  std::vector<std::string> parameters;
  analysis::MeasuredCurve reference;
  double from = 0.0, to = 1.0;  // window in the reference's x (strain, or stress in Pa)
  int max_evaluations = 40;
  analysis::SearchMethod method = analysis::SearchMethod::bobyqa;
  double initial_factor = 2.0;
  std::vector<std::pair<std::string, double>> start;
  // Evaluations already made (a resumed calibration): a trial point equal to one of them takes
  // its value without running again. The search is deterministic, so it asks for the same
  // points in the same order and ends where the uninterrupted one would.
  std::vector<CalibrationEvaluation> known;
  // Mass scaling of the evaluations only (run.density_scale, the cheaper scene); the calibrated
  // config keeps the config's own.
  std::optional<double> density_scale;
  // The elastic recovery the bed must also reach after unloading ((H_unloaded − H_min)/H_min,
  // a fraction): the objective is then sqrt((e_curve² + e_recovery²)/2), e_recovery the
  // recovery's error over the target, as the plate rig weighs its unloading. The config's punch
  // must unload. None: the curve alone.
  std::optional<double> target_recovery;
};

// The objective of one trial: the curve's RMS in the window, and with a recovery target
// sqrt((e_curve² + e_recovery²)/2). InputError when the window holds no point of the run's
// loading curve, or the target asks for a recovery the run never unloads to give.
double compaction_objective(const CompactionTrial& trial,
                            const CompactionCalibrationOptions& options);
// The trial's elastic recovery (CompactionMetrics::elastic_recovery); NaN when it did not unload.
double trial_recovery(const CompactionTrial& trial);

struct CompactionCalibrationResult {
  CompactConfig config;  // the config with the fitted values (density_scale its own)
  std::vector<double> start, values;
  analysis::MeasuredMismatch error;  // of the best trial
  double recovery = 0.0;             // the best trial's elastic recovery (NaN: not unloaded)
  double objective = 0.0;            // compaction_objective of the best trial
  std::vector<CalibrationEvaluation> evaluations;
  bool converged = false;
  CompactionTrial best;  // the run with the fitted values, on the evaluations' scene
};

// `packing` empty: the config's [generate] bed, settled once with the config's values (and the
// evaluations' density_scale). `progress` is called after each evaluation, in the search's order
// (a resumed one's known evaluations included); up to `threads` evaluations of a batch
// (Nelder–Mead's first simplex, a shrink; BOBYQA asks one point at a time) run side by side, one
// engine thread each: the result does not depend on it.
CompactionCalibrationResult calibrate_compaction(
    const CompactConfig& config, const std::filesystem::path& packing,
    const CompactionCalibrationOptions& options, int threads,
    const std::function<void(const CalibrationEvaluation&)>& progress = {});

}  // namespace shapepress::scenarios
