#pragma once
// The single-particle accuracy-against-cost study (paper §3.2, Fig. 2; issue "BMS and the
// rubber-sphere study"): several plate runs of one sphere, as BMS agglomerates of N sub-spheres
// and as one Hertz sphere, compared with the finest agglomerate (convergence) and with Tatara's
// large-deformation curve (accuracy), against the CPU seconds each run took.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "analysis/plot.hpp"
#include "analysis/report_html.hpp"

namespace shapepress::analysis {

struct PlateStudyRow {
  std::string label;
  int sub_spheres = 0;  // 1: the single (Hertz) sphere
  double cpu_seconds = -1.0, wall_seconds = -1.0;
  CurveDifference versus_finest;                 // over the window; zero for the finest itself
  std::optional<CurveDifference> versus_tatara;  // with ν
  double max_step_versus_finest = 0.0;           // largest |F − F_finest|/F_finest at 1 % steps
};

struct PlateStudy {
  std::vector<PlateStudyRow> rows;  // in the order of the runs
  std::string finest;               // label of the run with the most sub-spheres
  double from = 0.05, to = 0.40;    // deformation window of the comparisons
};

// Needs two or more plate runs with a sub-sphere count (force.csv of shapepress plate); returns
// nothing otherwise. The window is clipped to the deformation all runs reach.
std::optional<PlateStudy> plate_study(const std::vector<LoadedRun>& runs,
                                      std::optional<double> poisson_ratio, double from = 0.05,
                                      double to = 0.40);

// (b) CPU seconds against N (paper Fig. 2b); (c) speed–accuracy: RMS error against the finest
// run and against Tatara versus CPU seconds.
std::vector<Chart> plate_study_charts(const PlateStudy& study);

// plate_study.csv: label, sub_spheres, cpu_s, wall_s, rms/max relative errors.
void write_plate_study_csv(const std::filesystem::path& path, const PlateStudy& study);

}  // namespace shapepress::analysis
