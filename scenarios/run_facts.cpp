#include "scenarios/run_facts.hpp"

#include <cmath>
#include <variant>

#include "simulate/contact_law_config.hpp"
#include "simulate/engine.hpp"
#include "simulate/multicontact_law.hpp"

namespace shapepress::scenarios {
nlohmann::json interaction_laws(const MaterialConfig& materials) {
  nlohmann::json laws = nlohmann::json::array();
  for (const Interaction& in : materials.interactions) {
    nlohmann::json law = {
        {"first", in.first}, {"second", in.second}, {"normal_law", normal_law_name(in.normal_law)}};
    // A stated k1 replaces Hertz's 4/3 E* √R*: a calibrated run says which one it ran with.
    if (const auto* multicontact = std::get_if<simulate::MulticontactLaw>(&in.normal_law))
      if (multicontact->parameters.loading_stiffness)
        law["loading_stiffness_N_per_m1_5"] = *multicontact->parameters.loading_stiffness;
    laws.push_back(std::move(law));
  }
  return laws;
}

void add_compaction_facts(RunMetadata& meta, const CompactConfig& config,
                          const CompactionSetup& setup, double reference_gap,
                          const TimeStepChoice& time_step, const Engine& engine,
                          const CompactionSummary& summary) {
  const std::size_t clumps = engine.clumps().size(), bonds = engine.bonds().size();
  meta.fact("reference_gap_m", reference_gap)
      .fact("die_area_m2", setup.die_area)
      .fact("solid_volume_m3", setup.solid_volume)
      .fact("sphere_volume_m3", setup.sphere_volume)
      .fact("density_scale", config.density_scale)
      .fact("quasi_static", summary.quasi_static.quasi_static())
      .fact("max_kinetic_to_work", summary.quasi_static.max_kinetic_to_work)
      .fact("mean_force_imbalance", summary.quasi_static.mean_force_imbalance)
      .fact("max_force_imbalance", summary.quasi_static.max_force_imbalance)
      .fact("quasi_static_records", summary.quasi_static.records)
      .fact("strain_reference", setup.strain_from_fill ? "fill" : "start")
      .fact("max_solid_fraction", setup.max_solid_fraction)
      .fact("ceiling_limits_load", setup.ceiling_limits_load)
      // A bed of rigid clumps is CMS, of bonded spheres BMS; otherwise plain spheres.
      .fact("particle_kind", clumps > 0  ? "cms"
                             : bonds > 0 ? "bms"
                                         : "sphere")
      .fact("spheres", engine.state().size())
      .fact("clumps", clumps)
      .fact("bonds", bonds)
      .fact("particle_material", config.particle_material)
      .fact("wall_material", config.wall_material)
      .fact("laws", interaction_laws(config.materials))
      .fact("time_step_s", time_step.time_step)
      .fact("rayleigh_time_s", time_step.rayleigh_time)
      .fact("steps", summary.steps)
      .fact("final_step", engine.step_index())
      .fact("record_every", setup.record_every);
  // The stepping loop's wall seconds, a resumed run's whole; absent when a checkpoint older than
  // this fact did not keep the part before it.
  if (std::isfinite(summary.total_loop_seconds)) meta.fact("loop_s", summary.total_loop_seconds);
  if (setup.program.min_gap) meta.fact("min_gap_m", *setup.program.min_gap);
  if (setup.program.target_gap) meta.fact("target_gap_m", *setup.program.target_gap);
  if (config.generate) meta.fact("seed", config.generate->seed);
}

void add_plate_facts(RunMetadata& meta, const PlateConfig& config, PlateParticleKind kind,
                     const PlateRunOutcome& outcome) {
  const PlateSetup& setup = config.setup;
  const MaterialTable table = config.materials.table();
  meta.fact("particle_kind", particle_name(kind))
      // 1 for the single sphere: the count a convergence study orders runs by.
      .fact("sub_spheres", outcome.spheres)
      .fact("bonds", outcome.bonds)
      .fact("fills", outcome.fills())
      .fact("radius_m", setup.radius)
      .fact("max_deformation", setup.max_deformation)
      .fact("approach_speed_m_per_s", setup.speed)
      .fact("normal_law",
            normal_law_names().at(table.pair(setup.sphere_material, setup.plate_material).law))
      .fact("laws", interaction_laws(config.materials))
      .fact("time_step_s", outcome.time_step)
      .fact("rows", outcome.rows.size());
  if (kind != PlateParticleKind::sphere)
    meta.fact("sub_sphere_radius_m", outcome.sub_sphere_radius);
  if (kind == PlateParticleKind::cms) meta.fact("requested_spheres", outcome.requested_spheres);
  if (kind == PlateParticleKind::bms && config.bms)
    meta.fact("seed", config.bms->seed).fact("lattice", config.bms->lattice);
}

}  // namespace shapepress::scenarios
