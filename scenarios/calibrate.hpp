#pragma once
// Calibration of a BMS particle in the plate rig (docs/stages.md): the bond stiffnesses
// (and, if asked, the sub-spheres' contact modulus) that make the force–deformation curve match
// a reference curve, by a bounded search (BOBYQA or Nelder–Mead, analysis/optimize.hpp) on the
// logarithms of the parameters. The objective is the RMS relative force error over a deformation
// window, the number the acceptance criteria are stated in.
#include <functional>
#include <string>
#include <vector>
#include "scenarios/namespaces.hpp"

#include "analysis/optimize.hpp"
#include "scenarios/config_io.hpp"
#include "scenarios/plate_run.hpp"

namespace shapepress::scenarios {

// Names of the parameters calibrate can fit.
//   normal_stiffness, shear_stiffness  k̄n, k̄s [N/m³] (config [bond] in that form)
//   modulus, shear_ratio               Ē [Pa], k̄s/k̄n (config [bond] with modulus)
//   contact_modulus                    E of the sub-spheres' contact material [Pa] (a copy of
//                                      [bms] material, so the sphere's own E stays the bulk's)
//   radius_multiplier                  λ̄
//   yield_stress, shear_yield_stress,  σy, τy [Pa] and H of [bond] model = "elastic_plastic"
//   hardening_ratio                    (bond_models.hpp; fitted against a loading and unloading)
std::vector<std::string> calibration_parameter_names();

struct CalibrationEvaluation {
  std::vector<double> values;
  double rms_relative = 0.0;  // objective; +inf when the run failed
  double wall_seconds = 0.0;
  // Not run: taken from a resumed calibration's evaluations.csv or from an earlier evaluation
  // of the same point.
  bool reused = false;
};

struct CalibrationOptions {
  std::vector<std::string> parameters;
  std::vector<double> reference_deformation;  // increasing
  std::vector<double> reference_force;        // N
  // The reference's unloading branch (a fem-plate run with [plate] unload, force.csv step 2),
  // from its largest deformation down; empty: the loading alone is compared. Given, every
  // evaluation unloads too and the objective is sqrt((e_load² + e_unload²)/2), e_unload the
  // RMS unloading force error over the reference's peak force (plate_unloading_error).
  std::vector<double> reference_unloading_deformation;
  std::vector<double> reference_unloading_force;
  double from = 0.05;  // deformation window of the objective
  double to = 0.40;
  int max_evaluations = 40;
  analysis::SearchMethod method = analysis::SearchMethod::bobyqa;
  double initial_factor = 4.0;  // first step: each parameter × this factor
  // Start values that replace the config's (name, value); the fitted parameters start from the
  // config's values otherwise.
  std::vector<std::pair<std::string, double>> start;
  // Evaluations already made (a resumed calibration): a trial point equal to one of them takes
  // its value without running again (calibrate_compaction.hpp).
  std::vector<CalibrationEvaluation> known;
};

// The value of a known evaluation at exactly these parameters (a resumed calibration), if any.
const CalibrationEvaluation* known_evaluation(const std::vector<CalibrationEvaluation>& known,
                                              const std::vector<double>& values);

struct CalibrationResult {
  PlateConfig config;  // with the fitted values
  std::vector<double> start, values;
  double rms_relative = 0.0;  // the objective: the loading's, or with the unloading's
  double max_relative = 0.0;  // the loading's
  double loading_rms_relative = 0.0;
  double unloading_rms = 0.0;  // over the reference's peak force (0 without an unloading)
  std::vector<CalibrationEvaluation> evaluations;
  bool converged = false;
  PlateRunOutcome best;  // the run with the fitted values
};

// Reads and writes one named parameter of a config (InputError for an unknown name or one that
// does not match the config's bond form).
double get_parameter(const PlateConfig& config, const std::string& name);
// The [bond] parameters both calibrations fit, by the names above (normal_stiffness,
// shear_stiffness, modulus, shear_ratio, radius_multiplier, and an elastic_plastic model's
// yield_stress, shear_yield_stress, hardening_ratio): InputError when the bonds are in the
// other stiffness form or do not yield.
bool is_bond_parameter(const std::string& name);
double get_bond_parameter(const BondParameters& bond, const std::string& name);
void set_bond_parameter(BondParameters& bond, const std::string& name, double value);
void set_parameter(PlateConfig& config, const std::string& name, double value);

// RMS and maximum relative difference of the run's loading curve against the reference over
// [from, to] (200 points), the run's curve starting at (0, 0).
struct CurveError {
  double rms_relative = 0.0, max_relative = 0.0;
};
CurveError plate_curve_error(const std::vector<PlateRow>& rows,
                             const std::vector<double>& reference_deformation,
                             const std::vector<double>& reference_force, double from, double to);

// The RMS difference of the run's unloading curve (the rows after the first `records`, from the
// last loading row down) against the reference's unloading branch, over the reference's peak
// force, at 200 deformations evenly spaced from 0 to the smaller of the two curves' largest;
// each curve holds its end value beyond its ends (a curve that lets go above 0 stays at 0 force
// below its last row). Relative to the peak: the force passes through zero on the way down,
// where a relative error has no meaning.
double plate_unloading_error(const std::vector<PlateRow>& rows, int records,
                             const std::vector<double>& reference_deformation,
                             const std::vector<double>& reference_force);

CalibrationResult calibrate_plate(
    const PlateConfig& config, const CalibrationOptions& options,
    const std::function<void(const CalibrationEvaluation&)>& progress = {});

}  // namespace shapepress::scenarios
