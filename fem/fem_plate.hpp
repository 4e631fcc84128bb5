#pragma once
// The plate test by the finite element method: mesh the sphere, write the deck, run CalculiX,
// read the plate's reaction per increment into the force–deformation curve (the same columns as
// `plate`'s force.csv), and compare two mesh resolutions.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "analysis/curves.hpp"
#include "fem/fem_plate_config.hpp"
#include "geometry/press_frame.hpp"

namespace shapepress::fem {

struct FemPlateRow {
  int step = 1;              // 1 loading, 2 unloading (config.unload)
  double step_time = 0.0;    // fraction of the step
  double deformation = 0.0;  // Δ/(2R), Δ/(2c) for a spheroid
  double approach = 0.0;     // Δ [m], both plates
  double force = 0.0;        // on the plates [N]: the mean of the two (3D) or either (symmetry)
  double top_force = 0.0, bottom_force = 0.0;  // each plate's [N]
  double hertz_force = 0.0;  // (√2/3) E* √R Δ^{3/2}, E* = E/(1 − ν²) (rigid plates), R at the pole;
                             // 3D: both contacts' elliptical Hertz in series
  double work = 0.0;         // ∫ F dΔ by the plates [J] (net: unloading gives some back)
  double cpu_seconds = 0.0;  // CalculiX's CPU when the increment converged
  double wall_seconds = 0.0;
};

struct FemPlateRun {
  int arc_elements = 0;
  double element_size = 0.0;  // 3D: at the plates [m]
  int elements = 0;           // of the particle
  int nodes = 0;
  std::vector<FemPlateRow> rows;  // converged increments only, from the undeformed state;
                                  // the unloading step's after the loading step's
  double cpu_seconds = 0.0;       // CalculiX's total
  double wall_seconds = 0.0;
  bool completed = false;
  std::string failure;  // why it stopped early: CalculiX's error line or its exit status
  std::filesystem::path deck;
};

// What the run's unloading (step 2) left, by the peak force (analysis::unloading_residual).
using UnloadingResult = analysis::UnloadingResidual;
UnloadingResult unloading_result(const FemPlateRun& run);

struct FemRunOptions {
  std::string ccx = "ccx";    // the CalculiX program
  std::string gmsh = "gmsh";  // the mesher (3D models)
  int threads = 1;
  std::function<void(const std::string&)> log;      // one-line notes
  std::function<void(double total_time)> progress;  // 0 to 1 loading, 1 to 2 unloading
};

// Runs `config` at `arc_elements` in `folder` as job `job` (job.inp, job.dat, job.frd, job.log
// kept there). A run that stops before the step's end returns completed = false with the rows
// that converged; the caller decides (fem-plate exits 1 after writing them).
FemPlateRun run_fem_plate(const FemPlateConfig& config, int arc_elements,
                          const std::filesystem::path& folder, const std::string& job,
                          const FemRunOptions& options);

// The same for `particle` as a 3D model of C3D10 tetrahedra (job.stl, job.geo, job.msh from Gmsh
// kept in `folder` too), pressed along the press frame's z.
FemPlateRun run_solid_fem_plate(const FemPlateConfig& config, const PressedParticle& particle,
                                int arc_elements, const std::filesystem::path& folder,
                                const std::string& job, const FemRunOptions& options);

// Hertz's force of the two plate contacts in series (stiffnesses F = k δ^{3/2} each) at total
// approach Δ: the contact forces are equal, so δ_top / δ_bottom = (k_bottom / k_top)^{2/3}.
double hertz_series_force(double k_top, double k_bottom, double approach);

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

// The loading curve's force at a deformation, linear between rows; NaN beyond its last row.
double force_at(const FemPlateRun& run, double deformation);

}  // namespace shapepress::fem
