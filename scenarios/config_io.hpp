#pragma once
// Config TOML → the scenarios' structs, for `plate` (and `calibrate`) and `compact`. Every
// section is an OptionTable (common/options.hpp): the same tables read the config, write the
// effective config back (effective.toml beside a run's outputs, calibrate's calibrated.toml) and
// document the keys (`shapepress STAGE --help-config`, docs/config-reference.md).
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>
#include "scenarios/namespaces.hpp"

#include "common/config.hpp"
#include "common/options.hpp"
#include "geometry/press_axis.hpp"
#include "packing/packing.hpp"
#include "scenarios/compact.hpp"
#include "scenarios/plate.hpp"
#include "scenarios/punch.hpp"
#include "simulate/bonds.hpp"
#include "simulate/engine.hpp"
#include "simulate/materials.hpp"

namespace shapepress::scenarios {

struct MaterialConfig {
  std::vector<Material> materials;
  std::vector<Interaction> interactions;
  MaterialTable table() const { return MaterialTable(materials, interactions); }
  // The [[material]] of that name; none: nullptr.
  const Material* find(const std::string& name) const {
    for (const Material& m : materials)
      if (m.name == name) return &m;
    return nullptr;
  }
};
// `normal_law` (plate --model), when given, replaces the normal law of every interaction.
MaterialConfig read_materials(const ConfigTable& root,
                              const std::optional<std::string>& normal_law = std::nullopt);

// [run]: the time step rule and the engine's settings as read. The engine's time step and, when
// the config gives none, its skin are chosen when the particles are known (engine_settings()).
struct RunSettings {
  std::optional<double> time_step;  // fixed; else time_step_fraction of the critical step
  double time_step_fraction = 0.2;
  // The bonds' bound as a fraction of their period bound; absent: time_step_fraction.
  std::optional<double> bond_time_step_fraction;
  std::optional<double> skin;  // Verlet skin; absent: the stage's default from the radii
  EngineSettings engine;       // gravity, max_overlap_fraction, local_damping
  EngineSettings engine_settings(double time_step, double default_skin) const;
};

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
  RunSettings run;
  double box_x = 0.0, box_y = 0.0, bottom = 0.0;
  // Where the punch starts; NaN when [box] gives none: then the top of a packing made by `pack`
  // (prepare_compaction refuses any other bed without it).
  double punch = std::numeric_limits<double>::quiet_NaN();
  // Mass scaling: every particle's density × this (the time step grows as its square root). Only
  // for quasi-static runs, whose curve must not move with it (docs/models.md, "Mass scaling").
  double density_scale = 1.0;
  // Checkpoints for `compact --resume` (docs/stages.md, "Checkpoints and --resume"): every this
  // many steps (0: none by steps) and every this many minutes of wall time (0: none by time).
  std::int64_t checkpoint_every = 0;
  double checkpoint_minutes = 10.0;
  std::string particle_material, wall_material;
  // The compaction as the config gives it ([punch], [run] steps, record_every, snapshot_every);
  // prepare_compaction completes it with what the bed decides (H0, solid volume, ceiling).
  CompactionSetup setup;
  std::optional<double> target_strain;
  std::optional<double> target_solid_fraction;  // [punch]: the endpoint by the bed's solid volume
  std::optional<InsertionRequest> generate;     // filled in from [generate] when present
  // [generate] height: the insertion region's top above box.bottom (generate->z_high); read
  // back from the effective config, the box height when the config gives none.
  std::optional<double> fill_height;
  double settle_time = 0.2;
  // Sliding and rolling friction of every interaction while settling (a denser fill, as DEM
  // fills are usually made to reach a target density); absent: the interactions' own.
  std::optional<double> settle_friction;
  std::optional<ClumpsConfig> clumps;  // filled in from [clumps] when present
  std::optional<BondParameters> bond;  // [bond]: the bonds of a packing's BMS bodies
};
CompactConfig read_compact_config(const ConfigTable& root);
// The config as TOML that read_compact_config reads back to the same values.
std::string compact_config_toml(const CompactConfig& config);
// The keys of a compact config, for --help-config and docs/config-reference.md.
StageOptions compact_config_options();

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
  // A template of `fill` instead of a fill of the sphere: /bms/<template_name> of this
  // templates.h5, pressed along a principal axis of its body frame or a direction given in the
  // frame of the mesh it was filled from (a fem-plate run's axis_direction). The rig's R is then
  // half its height along that axis.
  std::string templates;
  std::string template_name;  // empty: the file's only BMS template
  geometry::PressAxis axis = geometry::PressAxis::short_axis;
  std::array<double, 3> direction = {0.0, 0.0, 1.0};
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
  RunSettings run;
  PlateSetup setup;  // material indices resolved from the names below
  std::string sphere_material, plate_material;
  std::optional<BmsConfig> bms;  // when the config has [bms]
  std::optional<CmsConfig> cms;  // when the config has [cms]
  // Checkpoints for `plate --resume` (as CompactConfig's): every this many steps of a fill (0:
  // none by steps) and every this many minutes of wall time (0: none by time).
  std::int64_t checkpoint_every = 0;
  double checkpoint_minutes = 10.0;
};
// `normal_law` (plate --model) replaces the normal law of every interaction.
PlateConfig read_plate_config(const ConfigTable& root,
                              const std::optional<std::string>& normal_law = std::nullopt);
// The config as TOML that read_plate_config reads back to the same values (the effective config
// of a plate run; calibrate writes the fitted parameters this way, so a calibrated run is one
// config file).
std::string plate_config_toml(const PlateConfig& config);
// The keys of a plate (and calibrate) config.
StageOptions plate_config_options(std::string stage = "plate");

}  // namespace shapepress::scenarios
