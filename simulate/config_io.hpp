#pragma once
// Config TOML → the engine's plain structs, for `plate` and `compact`. Keys (all quantities
// accept units, "100 MPa", "0.1 mm"):
//   [[material]]     name, youngs_modulus, poisson_ratio, density
//   [[interaction]]  first, second (material names), restitution, sliding_friction,
//                    rolling_friction = 0, normal_law = "hertz"
//   [run]            time_step (fixed) | time_step_fraction = 0.2 (of the Rayleigh time),
//                    steps = 0 (0: until the punch program ends), record_every = 100,
//                    snapshot_every = 0, skin = 0.1 × smallest diameter, gravity = [0,0,0] m/s²,
//                    max_overlap_fraction = 0.5
// compact only:
//   [box]            x, y (periodic lengths), bottom = 0, punch (initial punch height)
//   [particles]      material; [walls] material
//   [punch]          mode = "displacement" | "servo", speed, target_gap | target_strain,
//                    hold_time = 0, unload_speed = 0, target_stress, max_speed
//   [generate]       (when no --packing) count, diameter_min, diameter_max, seed = 1,
//                    height = box height (of the insertion region), settle_time = 0.2 s (settling
//                    under gravity, 9.81 m/s² down if [run] gravity is zero; then the punch is
//                    lowered onto the bed)
// plate only:
//   [sphere]         radius, material; [plate] material, speed, max_deformation = 0.01,
//                    records = 50
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/config.hpp"
#include "simulate/materials.hpp"
#include "simulate/packing.hpp"
#include "simulate/plate.hpp"
#include "simulate/punch.hpp"

namespace shapepress::simulate {

struct MaterialConfig {
  std::vector<Material> materials;
  std::vector<Interaction> interactions;
  MaterialTable table() const { return MaterialTable(materials, interactions); }
};
MaterialConfig read_materials(const ConfigTable& root);

struct RunConfig {
  std::optional<double> time_step;
  double time_step_fraction = 0.2;
  std::int64_t steps = 0;
  std::int64_t record_every = 100;
  std::int64_t snapshot_every = 0;
  std::optional<double> skin;
  std::array<double, 3> gravity = {0.0, 0.0, 0.0};
  double max_overlap_fraction = 0.5;
};
RunConfig read_run(const ConfigTable& root);

struct CompactConfig {
  MaterialConfig materials;
  RunConfig run;
  double box_x = 0.0, box_y = 0.0, bottom = 0.0, punch = 0.0;
  std::string particle_material, wall_material;
  PunchProgram program;
  std::optional<double> target_strain;
  std::optional<InsertionRequest> generate;  // filled in from [generate] when present
  double settle_time = 0.2;
};
CompactConfig read_compact_config(const ConfigTable& root);

struct PlateConfig {
  MaterialConfig materials;
  RunConfig run;
  PlateSetup setup;  // time_step left 0: chosen from run
};
PlateConfig read_plate_config(const ConfigTable& root);

}  // namespace shapepress::simulate
