#pragma once
// Reading run folders for the report: a compaction run (punch.csv from `shapepress compact`) or
// a plate run (force.csv from `shapepress plate`). InputError names the file and the column.
#include <filesystem>
#include <string>
#include <vector>

#include "analysis/compaction.hpp"

namespace shapepress::analysis {

enum class RunKind { compaction, plate };

struct PlateCurve {
  std::vector<double> deformation;  // Δ/(2R)
  std::vector<double> approach;     // Δ, total plate approach [m]
  std::vector<double> top_force;    // N
  std::vector<double> hertz_force;  // N, as the run computed it
  // From runs that carry them (shapepress plate since the BMS issue): the sub-sphere count
  // ("# particle = …; sub_spheres = N" comment; 1 for a single sphere, 0 unknown) and the CPU
  // and wall seconds of the whole run (last row of cpu_s, wall_s; < 0 unknown).
  int sub_spheres = 0;
  double cpu_seconds = -1.0;
  double wall_seconds = -1.0;
  // The particle kind ("# particle = sphere|bms|cms"; empty when the run does not say) and the
  // contact count of every row (empty when force.csv has no contacts column).
  std::string particle;
  std::vector<double> contacts;
  // A mean of fills (`plate --fills K`, "# fills = K" comment and top_force_sd_N column): K and
  // the fills' sample standard deviation of the top force per row; 1 and empty for one fill.
  int fills = 1;
  std::vector<double> top_force_sd;
};

struct RunFiles {
  std::filesystem::path folder;
  std::filesystem::path csv;  // punch.csv or force.csv
  RunKind kind = RunKind::compaction;
  std::vector<std::string> comments;  // the '#' lines of the CSV: the run's provenance
};

// Which kind of run a folder holds; InputError if it is missing or has neither CSV.
RunFiles find_run(const std::filesystem::path& folder);

// The '#' lines at the top of a CSV, without the "# ".
std::vector<std::string> csv_comments(const std::filesystem::path& path);

// punch.csv: the columns time_s, gap_m, top_force_N, stress_Pa, solid_fraction, phase, and H0
// and the die area from the comment "strain from H0 = … m; die area … m^2".
PunchCurve read_punch_curve(const std::filesystem::path& path);
// force.csv: deformation, approach_m, top_force_N, hertz_force_N (contacts when present).
PlateCurve read_plate_curve(const std::filesystem::path& path);

}  // namespace shapepress::analysis
