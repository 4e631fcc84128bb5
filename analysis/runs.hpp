#pragma once
// Reading run folders for the report: a compaction run (punch.csv from `shapepress compact`) or
// a plate run (force.csv from `shapepress plate` or `calibrate`). The curves come from the CSV,
// the facts about the run (H0, die area, particle kind, sub-sphere count, fills) from the
// run.json beside it (common/run_metadata.hpp), never from the CSV's comment lines, which are
// for people and may be reworded. InputError names the folder or file, and the column or key.
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
  // The sub-sphere count (run.json sub_spheres; 1 for a single sphere) and, from runs that
  // carry them, the CPU and wall seconds of the whole run (last row of cpu_s, wall_s; < 0
  // unknown).
  int sub_spheres = 0;
  double cpu_seconds = -1.0;
  double wall_seconds = -1.0;
  // The particle kind (run.json particle_kind: sphere, bms or cms) and the contact count of
  // every row (empty when force.csv has no contacts column).
  std::string particle;
  std::vector<double> contacts;
  // A mean of fills (`plate --fills K`, run.json fills and the top_force_sd_N column): K and
  // the fills' sample standard deviation of the top force per row; 1 and empty for one fill.
  int fills = 1;
  std::vector<double> top_force_sd;
  // An FEM run (particle "fem", shapepress fem-plate): the sphere's element count, its
  // resolution in the cost chart (run.json elements); 0 for the other kinds.
  int elements = 0;
  // The normal contact law of a single sphere (run.json normal_law: hertz, multicontact; empty
  // when the run does not say).
  std::string normal_law;
};

struct RunFiles {
  std::filesystem::path folder;
  std::filesystem::path csv;  // punch.csv or force.csv
  RunKind kind = RunKind::compaction;
  std::filesystem::path metadata;     // run.json
  std::vector<std::string> comments;  // the '#' lines of the CSV: provenance, for people
};

// Which kind of run a folder holds; InputError if it is missing, has neither CSV, has no run.json,
// or its run.json is from a stage that does not write that CSV.
RunFiles find_run(const std::filesystem::path& folder);

// The name of the config a run was made with (the stem of run.json's input of role "config":
// "compact-demo" for pipelines/demo/compact-demo.toml); empty when run.json names none.
std::string config_name(const std::filesystem::path& run_json);

// The '#' lines at the top of a CSV, without the "# ".
std::vector<std::string> csv_comments(const std::filesystem::path& path);

// punch.csv: the columns time_s, gap_m, top_force_N, stress_Pa, solid_fraction, phase; H0 and
// the die area from run.json beside it (facts reference_gap_m, die_area_m2).
PunchCurve read_punch_curve(const std::filesystem::path& path);
// force.csv: deformation, approach_m, top_force_N, hertz_force_N (contacts when present); the
// particle kind, sub-sphere count and fills from run.json beside it (facts particle_kind,
// sub_spheres, fills).
PlateCurve read_plate_curve(const std::filesystem::path& path);

}  // namespace shapepress::analysis
