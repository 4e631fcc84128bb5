#pragma once
// The single-particle accuracy-against-cost study (paper §3.2, Fig. 2; the rubber-sphere study,
// pipelines/rubber-sphere): several plate runs of one sphere, as BMS agglomerates of N sub-spheres
// and as one Hertz sphere, compared with the finest agglomerate (convergence) and with Tatara's
// large-deformation curve (accuracy), against the CPU seconds each run took.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "analysis/plot.hpp"
#include "analysis/report_html.hpp"

namespace shapepress::analysis {

// One 1 % step of deformation of a run against the finest: the convergence test reads
// these. For a mean of K fills the standard errors are sd/√K of each mean; a difference smaller
// than a few of its standard errors is not told apart from zero by these fills.
struct PlateStep {
  double deformation = 0.0;
  double force = 0.0;                // N
  double force_error = 0.0;          // N, standard error of the mean of fills (0 for one fill)
  double versus_finest = 0.0;        // F / F_finest − 1
  double versus_finest_error = 0.0;  // its standard error from both runs' fills
};

struct PlateStudyRow {
  std::string label;
  int sub_spheres = 0;  // 1: the single (Hertz) sphere
  int fills = 1;
  double cpu_seconds = -1.0, wall_seconds = -1.0;
  CurveDifference versus_finest;                 // over the window; zero for the finest itself
  std::optional<CurveDifference> versus_tatara;  // with ν
  double max_step_versus_finest = 0.0;           // largest |F − F_finest|/F_finest at 1 % steps
  std::vector<PlateStep> steps;                  // every 1 % step of the window
  std::optional<CurveDifference> versus_fem;     // against the finest FEM run, when there is one
};

// An FEM run of the same sphere (shapepress fem-plate): its cost and its difference from the
// finest FEM run, the other half of the paper's Fig. 2b (elements instead of sub-spheres).
struct FemStudyRow {
  std::string label;
  int elements = 0;
  double cpu_seconds = -1.0, wall_seconds = -1.0;
  CurveDifference versus_finest_fem;  // zero for the finest itself
};

struct PlateStudy {
  std::vector<PlateStudyRow> rows;  // in the order of the runs
  std::string finest;               // label of the run with the most sub-spheres
  double from = 0.05, to = 0.40;    // deformation window of the comparisons
  std::vector<FemStudyRow> fem;     // FEM runs, by elements; the last is the finest
};

// Needs two or more plate runs with a sub-sphere count (force.csv of shapepress plate); returns
// nothing otherwise. The window is clipped to the deformation all runs reach. Rigid multi-sphere
// (CMS) runs are left out: they are the convergence study's (below), not this ladder's.
std::optional<PlateStudy> plate_study(const std::vector<LoadedRun>& runs,
                                      std::optional<double> poisson_ratio, double from = 0.05,
                                      double to = 0.40);

// (b) CPU seconds against N (paper Fig. 2b); (c) speed–accuracy: RMS error against the finest
// run and against Tatara versus CPU seconds; (d) convergence: every N against the finest at the
// 1 % steps, the next-finest with ±2 standard errors of the difference, and the ±2 % lines.
std::vector<Chart> plate_study_charts(const PlateStudy& study);

// plate_study.csv: label, sub_spheres, fills, cpu_s, wall_s, rms/max relative errors, and how
// many 1 % steps lie within 2 % of the finest (and within 2 % plus two standard errors).
void write_plate_study_csv(const std::filesystem::path& path, const PlateStudy& study);
// fem_study.csv: label, elements, cpu_s, wall_s and the RMS and largest relative differences
// from the finest FEM run over the study's window (nothing written without FEM runs).
void write_fem_study_csv(const std::filesystem::path& path, const PlateStudy& study);
// plate_steps.csv: every run's force at every 1 % step with its standard error, and its
// difference from the finest run with that difference's standard error.
void write_plate_steps_csv(const std::filesystem::path& path, const PlateStudy& study);

// The convergence question (paper §3.3 and Fig. 3; issue 6): do the force curves of one method
// settle as its number of sub-spheres N grows? Per method (the particle kind in force.csv: bms,
// cms), the loading force at fixed deformations for every N, its change from the next coarser
// N, and the spread (max − min)/mean over the runs with N ≥ spread_from (the paper's CMS
// representations 150…3000, the BMS pair 819 and 1322). Dropouts: loading rows where the force
// falls by more than 1 % of the previous row's, or where the contact count falls.
struct ConvergenceRun {
  std::string label;
  int sub_spheres = 0;
  double cpu_seconds = -1.0;
  double reached = 0.0;        // largest deformation of the run
  std::vector<double> force;   // N, at each deformation; NaN beyond `reached`
  std::vector<double> change;  // |F − F_coarser| / mean of the two; NaN for the coarsest
  int force_drops = 0;         // loading rows with F_i < 0.99 F_{i−1}
  int contact_drops = 0;       // loading rows with fewer contacts than the row before
  bool finite = true;          // every force and contact count is a finite number
};

struct MethodConvergence {
  std::string method;                // "bms", "cms", …
  std::vector<ConvergenceRun> runs;  // ascending N
  int spread_from = 0;               // smallest N of the spread
  int spread_to = 0;                 // largest N of the spread
  int spread_runs = 0;               // runs in the spread
  std::vector<double> spread;        // (max − min)/mean at each deformation
};

struct ConvergenceStudy {
  std::vector<double> deformations;        // Δ/(2R), 0.2, 0.3, 0.4 by default
  std::vector<MethodConvergence> methods;  // sorted by name
};

// Needs two or more CMS plate runs (N > 1); returns nothing otherwise. `spread_from` maps a
// method to the smallest N of its spread (default: its two finest runs). InputError when a
// method named there has fewer than two runs at or above that N.
std::optional<ConvergenceStudy> convergence_study(const std::vector<LoadedRun>& runs,
                                                  const std::map<std::string, int>& spread_from,
                                                  std::vector<double> deformations = {0.2, 0.3,
                                                                                      0.4});

// (a) the CMS force curves of every N with the finest run of each other method, Hertz and
// Tatara (with ν); (b) the CMS contact count against deformation (the dropouts); (c) the change
// of the force from the next coarser N, against N, every method; (d) the spread at each
// deformation, one series per method with its N range in the legend.
std::vector<Chart> convergence_charts(const ConvergenceStudy& study,
                                      const std::vector<LoadedRun>& runs,
                                      std::optional<double> poisson_ratio);

// convergence_runs.csv: a row per (method, N); convergence_spread.csv: a row per (method,
// deformation) with the N range and the spread.
void write_convergence_csv(const std::filesystem::path& folder, const ConvergenceStudy& study);

}  // namespace shapepress::analysis
