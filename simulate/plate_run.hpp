#pragma once
// A plate run from a config: the particle (one sphere or a BMS agglomerate), the time step
// (Rayleigh time and, with bonds, the bonded network's period), the run. Shared by `plate` and
// `calibrate`, which runs it many times with different bond parameters.
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "simulate/config_io.hpp"
#include "simulate/plate.hpp"

namespace shapepress::simulate {

class Engine;

struct PlateRunOutcome {
  std::vector<PlateRow> rows;
  std::string description;  // "BMS sphere R = … m, 545 sub-spheres of r = … m, 2900 bonds"
  std::size_t spheres = 0;
  std::size_t bonds = 0;
  double sub_sphere_radius = 0.0;
  double time_step = 0.0;
  std::shared_ptr<const Engine> final_snapshot;  // the engine at the last row
};

// `log` (optional) receives one-line notes (time step, particle); bonded: --particle bms.
PlateRunOutcome run_plate_config(const PlateConfig& config, bool bonded,
                                 const std::function<void(const std::string&)>& log = {});

// force.csv (atomically): time_s, deformation, approach_m, top_force_N, bottom_force_N,
// hertz_force_N, contacts, intact_bonds, kinetic_energy_J, work_J, cpu_s, wall_s; comment lines
// say what was pressed (report reads "sub_spheres = N").
void write_force_csv(const std::filesystem::path& path, const PlateRunOutcome& outcome,
                     const PlateConfig& config, bool bonded);

}  // namespace shapepress::simulate
