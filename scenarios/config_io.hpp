#pragma once
// Config TOML → the engine's plain structs, for `plate` and `compact`. Keys (all quantities
// accept units, "100 MPa", "0.1 mm"):
//   [[material]]     name, youngs_modulus, poisson_ratio, density
//   [[interaction]]  first, second (material names), restitution, sliding_friction,
//                    rolling_friction = 0, effective_modulus, normal_law = "hertz" | … and the
//                    law's keys: read by the law (simulate/contact_law_config.hpp;
//                    normal_law_options() lists them with units, ranges and defaults)
//   [run]            time_step (fixed) | time_step_fraction = 0.2 (of the Rayleigh time),
//                    steps = 0 (0: until the punch program ends), record_every = 100,
//                    snapshot_every = 0, skin = 0.1 × smallest diameter, gravity = [0,0,0] m/s²,
//                    max_overlap_fraction = 0.5, local_damping = 0 (Cundall's α, [0, 1):
//                    for quasi-static loading; engine.hpp)
// compact only:
//   [box]            x, y (periodic lengths), bottom = 0, punch (initial punch height)
//   [particles]      material; [walls] material
//   [punch]          mode = "displacement" | "servo", speed, target_gap | target_strain,
//                    hold_time = 0, unload_speed = 0, target_stress, max_speed,
//                    strain_reference = "start" | "fill" (H0: the gap when loading starts, or
//                    the loose fill height = [generate] height), max_solid_fraction = 0.95
//   [generate]       (when no --packing) count, diameter_min, diameter_max, seed = 1,
//                    size_quantiles + size_quantile_levels (+ size_weighting = "volume" |
//                    "number"): a size distribution truncated to [diameter_min, diameter_max],
//                    height = box height (of the insertion region), settle_time = 0.2 s (settling
//                    under gravity, 9.81 m/s² down if [run] gravity is zero; then the punch is
//                    lowered onto the bed), settle_friction (μs = μr of every interaction
//                    while settling only)
//   [clumps]         count, seed = 1, integration_cells = 128, and either templates (a
//                    templates.h5; template = one /cms/<name>, default all in turn) or spheres
//                    = [x, y, z, r, …] (one template inline, metres): rigid CMS clumps inserted
//                    at random where they overlap nothing, in the [generate] region (else the
//                    box), of the particles' material
// plate only:
//   [sphere]         radius, material; [plate] material, speed, ramp = 0 (deformation over which
//                    the top plate speeds up from rest), final_speed = speed (reached at
//                    max_deformation, linearly in deformation after the ramp), symmetric = false,
//                    max_deformation = 0.01, records = 50
//   [bms]            (plate --particle bms) count = 545,
//                    lattice = "fcc" | "hcp" | "random" | "shell" | "carved", placement = "inside"
//                    | "centre", seed = 1, fills = 1 (the mean curve of fills of seeds seed, seed +
//                    1, …), bond_multiplier = 1.15 (m_b, Eq. 10), material = the sphere's (the
//                    sub-spheres' contact material)
//   [bond]           normal_stiffness, shear_stiffness (k̄n, k̄s, N/m^3) | modulus (Ē, Pa) with
//                    shear_ratio = 1 (k̄s/k̄n); radius_multiplier = 1 (λ̄),
//                    tensile_strength, shear_strength (Pa, default unbreakable),
//                    damping_ratio = 0, contact_when_bonded = true
//   [cms]            (plate --particle cms) count = 150 (plate --spheres), resolution = 64,
//                    min_radius_fraction = 0.02, match_volume = true, integration_cells = 128,
//                    material = the sphere's
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>
#include "scenarios/namespaces.hpp"

#include "common/config.hpp"
#include "packing/packing.hpp"
#include "scenarios/plate.hpp"
#include "scenarios/punch.hpp"
#include "simulate/bonds.hpp"
#include "simulate/materials.hpp"

namespace shapepress::scenarios {

struct MaterialConfig {
  std::vector<Material> materials;
  std::vector<Interaction> interactions;
  MaterialTable table() const { return MaterialTable(materials, interactions); }
};
// `normal_law` (plate --model), when given, replaces the normal law of every interaction.
MaterialConfig read_materials(const ConfigTable& root,
                              const std::optional<std::string>& normal_law = std::nullopt);

struct RunConfig {
  std::optional<double> time_step;
  double time_step_fraction = 0.2;
  std::int64_t steps = 0;
  std::int64_t record_every = 100;
  std::int64_t snapshot_every = 0;
  std::optional<double> skin;
  std::array<double, 3> gravity = {0.0, 0.0, 0.0};
  double max_overlap_fraction = 0.5;
  double local_damping = 0.0;  // α, EngineSettings::local_damping
};
RunConfig read_run(const ConfigTable& root);

// Rigid clumps (CMS particles) added to a compaction bed ([clumps]): from a templates file's
// /cms groups or one template given inline, inserted where they overlap nothing.
struct ClumpsConfig {
  std::int64_t count = 0;
  std::uint64_t seed = 1;
  std::string templates;        // templates.h5; empty: `spheres` holds the one template
  std::string template_name;    // one /cms/<name> of `templates`; empty: all, in turn
  std::vector<double> spheres;  // x, y, z, r per sub-sphere (m), body frame
  int integration_cells = 128;
};

struct CompactConfig {
  MaterialConfig materials;
  RunConfig run;
  double box_x = 0.0, box_y = 0.0, bottom = 0.0, punch = 0.0;
  std::string particle_material, wall_material;
  PunchProgram program;
  std::optional<double> target_strain;
  bool strain_from_fill = false;             // H0 = [generate] height instead of the starting gap
  double max_solid_fraction = 0.95;          // loading stops when the solid fraction passes it
  std::optional<InsertionRequest> generate;  // filled in from [generate] when present
  double settle_time = 0.2;
  // Sliding and rolling friction of every interaction while settling (a denser fill, as DEM
  // fills are usually made to reach a target density); absent: the interactions' own.
  std::optional<double> settle_friction;
  std::optional<ClumpsConfig> clumps;  // filled in from [clumps] when present
};
CompactConfig read_compact_config(const ConfigTable& root);

// A bonded multi-sphere particle filling the plate rig's sphere (plate --particle bms).
struct BmsConfig {
  int count = 545;
  // or "hcp", "random" (a dense random packing), "shell" (the same with a surface-conforming
  // outer layer), "carved" (cut out of a larger random packing; geometry/random_packing.hpp)
  std::string lattice = "fcc";
  std::string placement = "inside";
  std::uint64_t seed = 1;
  // Fills of seeds seed, seed + 1, … pressed alike, whose mean curve the run reports (with the
  // spread): one random fill's curve is one sample of the model, the plates meeting whichever
  // sub-spheres happen to sit at the poles (docs/models.md, "One fill is one sample").
  int fills = 1;
  double bond_multiplier = 1.15;
  std::string material;  // of the sub-spheres; empty: the sphere's
  BondParameters bond;
};

// A rigid clump of overlapping sub-spheres filling the plate rig's sphere (plate --particle cms),
// made by the CMS filler (geometry::fill_rigid) of the analytic sphere.
struct CmsConfig {
  int count = 150;                    // sub-spheres asked of the filler (plate --spheres)
  int resolution = 64;                // filler grid cells along the sphere's diameter
  double min_radius_fraction = 0.02;  // smallest sub-sphere / largest
  bool match_volume = true;           // grow the radii until the union has the sphere's volume
  int integration_cells = 128;        // voxels along the clump's longest side (mass, inertia)
  std::string material;               // of the sub-spheres; empty: the sphere's
};

struct PlateConfig {
  MaterialConfig materials;
  RunConfig run;
  PlateSetup setup;              // time_step left 0: chosen from run
  std::optional<BmsConfig> bms;  // when the config has [bms]
  std::optional<CmsConfig> cms;  // when the config has [cms]
};
// `normal_law` (plate --model) replaces the normal law of every interaction.
PlateConfig read_plate_config(const ConfigTable& root,
                              const std::optional<std::string>& normal_law = std::nullopt);
// The config as TOML that read_plate_config reads back to the same values (calibrate writes
// the fitted parameters this way, so a calibrated run is one config file).
std::string plate_config_toml(const PlateConfig& config);

}  // namespace shapepress::scenarios
