#pragma once
// The typed facts the scenario stages put into their run.json (common/run_metadata.hpp): what
// `report` and later stages read instead of the CSV comment lines. Kept out of the cli_*.cpp
// files so a stage's command line only adds the call.
#include <nlohmann/json.hpp>

#include "common/run_metadata.hpp"
#include "scenarios/compact.hpp"
#include "scenarios/config_io.hpp"
#include "scenarios/plate_run.hpp"
#include "simulate/timestep.hpp"

namespace shapepress::scenarios {

// One entry per configured interaction: {"first", "second", "normal_law"} (tangential:
// Mindlin with Coulomb friction for all of them, so not repeated).
nlohmann::json interaction_laws(const MaterialConfig& materials);

// The run's counted work (simulate/work_count.hpp): sphere_steps, contact_steps, bond_steps and
// their sum counted_cost, what `advise` picks by.
void add_work_facts(RunMetadata& meta, const WorkCount& work);

// compact: reference_gap_m (H0), die_area_m2, solid_volume_m3, strain_reference, the particle
// counts and kind, the laws, time_step_s (setup.time_step), steps and
// their work (add_work_facts).
void add_compaction_facts(RunMetadata& meta, const CompactConfig& config,
                          const CompactionSetup& setup, double reference_gap, const Engine& engine,
                          const CompactionSummary& summary);

// plate and calibrate: particle_kind (sphere, bms, cms), sub_spheres, fills, radius_m, the laws,
// time_step_s, the work (of the fills summed).
void add_plate_facts(RunMetadata& meta, const PlateConfig& config, PlateParticleKind kind,
                     const PlateRunOutcome& outcome);

}  // namespace shapepress::scenarios
