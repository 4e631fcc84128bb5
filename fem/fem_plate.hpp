#pragma once
// The plate test by the finite element method: mesh the sphere, write the deck, run CalculiX,
// read the plate's reaction per increment into the force–deformation curve (the same columns as
// `plate`'s force.csv), and compare two mesh resolutions.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "fem/fem_plate_config.hpp"

namespace shapepress::fem {

struct FemPlateRow {
  double step_time = 0.0;    // fraction of the step
  double deformation = 0.0;  // Δ/(2R), Δ/(2c) for a spheroid
  double approach = 0.0;     // Δ [m], both plates
  double force = 0.0;        // on one plate [N] (the two are equal: symmetry)
  double hertz_force = 0.0;  // (√2/3) E* √R Δ^{3/2}, E* = E/(1 − ν²) (rigid plates), R at the pole
  double work = 0.0;         // ∫ F dΔ by the plates [J]
  double cpu_seconds = 0.0;  // CalculiX's CPU when the increment converged
  double wall_seconds = 0.0;
};

struct FemPlateRun {
  int arc_elements = 0;
  int elements = 0;  // of the sphere
  int nodes = 0;
  std::vector<FemPlateRow> rows;  // converged increments only, from the undeformed state
  double cpu_seconds = 0.0;       // CalculiX's total
  double wall_seconds = 0.0;
  bool completed = false;
  std::string failure;  // why it stopped early: CalculiX's error line or its exit status
  std::filesystem::path deck;
};

struct FemRunOptions {
  std::string ccx = "ccx";  // the CalculiX program
  int threads = 1;
  std::function<void(const std::string&)> log;  // one-line notes
  std::function<void(double step_time)> progress;
};

// Runs `config` at `arc_elements` in `folder` as job `job` (job.inp, job.dat, job.frd, job.log
// kept there). A run that stops before the step's end returns completed = false with the rows
// that converged; the caller decides (fem-plate exits 1 after writing them).
FemPlateRun run_fem_plate(const FemPlateConfig& config, int arc_elements,
                          const std::filesystem::path& folder, const std::string& job,
                          const FemRunOptions& options);

// The largest relative difference |F_coarse − F_fine| / F_fine over the coarse run's rows at
// deformation ≥ `from` (the fine curve interpolated linearly at them), and the same at given
// deformations (NaN where either run does not reach it).
struct MeshDifference {
  double max_relative = 0.0;
  double at_deformation_of_max = 0.0;
  std::vector<std::pair<double, double>> at;  // (deformation, relative difference)
};
MeshDifference mesh_difference(const FemPlateRun& coarse, const FemPlateRun& fine, double from,
                               const std::vector<double>& deformations);

// The curve's force at a deformation, linear between rows; NaN beyond the last row.
double force_at(const FemPlateRun& run, double deformation);

}  // namespace shapepress::fem
