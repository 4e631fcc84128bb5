#include "scenarios/run_facts.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

#include "simulate/contact_law_config.hpp"
#include "simulate/engine.hpp"
#include "simulate/multicontact_law.hpp"

namespace shapepress::scenarios {
// Which bound set a run's step: the Rayleigh time of its smallest sphere at its stiffest
// contact, the bonded network's period, or the rigid clumps' rocking.
// With bond sub-steps the bonds bound each sub-step, and the step only through all of them.
std::string time_step_bound(const TimeStepChoice& t) {
  const double bonds = t.bond_substeps * t.bond_period;
  const double bound = std::min({t.rayleigh_time, bonds, t.clump_period});
  if (t.rayleigh_time == bound) return "rayleigh";
  return bonds == bound ? "bonds" : "clumps";
}

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

void add_work_facts(RunMetadata& meta, const WorkCount& work) {
  for (const auto& [key, field] : work_count_fields)
    meta.fact(std::string(key), work.*field);
  meta.fact("counted_cost", work.total());
}

void add_compaction_facts(RunMetadata& meta, const CompactConfig& config,
                          const CompactionSetup& setup, double reference_gap, const Engine& engine,
                          const CompactionSummary& summary) {
  const TimeStepChoice& time_step = setup.time_step;
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
      .fact("max_inertial_number", summary.quasi_static.max_inertial_number)
      .fact("unload_records", summary.quasi_static.unload.records)
      .fact("unload_max_kinetic_to_work", summary.quasi_static.unload.max_kinetic_to_work)
      .fact("unload_mean_force_imbalance", summary.quasi_static.unload.mean_force_imbalance)
      .fact("unload_max_inertial_number", summary.quasi_static.unload.max_inertial_number)
      .fact("unload_quasi_static",
            summary.quasi_static.unload.records == 0 || summary.quasi_static.unload.quasi_static())
      .fact("inertial_diameter_m", setup.inertial.diameter)
      .fact("inertial_density_kg_per_m3", setup.inertial.density)
      .fact("body_volume_m3", setup.body_volume)
      .fact("solid_fraction_volume", packing::solid_volume_name(setup.solid_fraction_volume))
      .fact("shape_volume_m3", setup.shape_volume)
      .fact("relax_time_s", setup.program.relax_time)
      .fact("release_time_s", setup.program.release_time)
      .fact("strain_reference", strain_reference_name(setup.strain_reference))
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
      .fact("time_step_bound", time_step_bound(time_step))
      .fact("bond_substeps", time_step.bond_substeps)
      .fact("steps", summary.steps)
      .fact("final_step", engine.step_index())
      .fact("record_every", setup.record_every);
  add_work_facts(meta, summary.work_count);
  // The stepping loop's wall seconds, a resumed run's whole; absent when a checkpoint older than
  // this fact did not keep the part before it.
  if (std::isfinite(summary.total_loop_seconds)) meta.fact("loop_s", summary.total_loop_seconds);
  if (std::isfinite(time_step.bond_period)) meta.fact("bond_period_s", time_step.bond_period);
  if (std::isfinite(time_step.bond_stability_step))
    meta.fact("bond_stability_step_s", time_step.bond_stability_step);
  if (std::isfinite(time_step.clump_period)) meta.fact("clump_period_s", time_step.clump_period);
  if (setup.strain_reference == CompactionSetup::StrainReference::solid_fraction)
    meta.fact("reference_solid_fraction", setup.reference_solid_fraction);
  // Where loading starts, after the relaxation: the bed's pre-stress and motion then.
  meta.fact("start_top_force_N", summary.first.top_force)
      .fact("start_bottom_force_N", summary.first.bottom_force)
      .fact("start_kinetic_energy_J", summary.first.kinetic_energy);
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
      // Particles one on another; sub_spheres and bonds count one of them.
      .fact("stack", setup.stack)
      .fact("max_deformation", setup.max_deformation)
      .fact("approach_speed_m_per_s", setup.speed)
      .fact("normal_law",
            normal_law_names().at(table.pair(setup.sphere_material, setup.plate_material).law))
      .fact("laws", interaction_laws(config.materials))
      .fact("time_step_s", outcome.time_step)
      .fact("rows", outcome.rows.size());
  add_work_facts(meta, outcome.work_count());
  if (kind != PlateParticleKind::sphere)
    meta.fact("sub_sphere_radius_m", outcome.sub_sphere_radius);
  if (kind == PlateParticleKind::cms) meta.fact("requested_spheres", outcome.requested_spheres);
  if (kind == PlateParticleKind::bms && config.bms)
    meta.fact("seed", config.bms->seed).fact("lattice", config.bms->lattice);
  if (setup.unload) {
    const PlateUnloading unloaded = plate_unloading(outcome.rows, setup.records);
    const auto finite_or_null = [](double v) {
      return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
    };
    meta.fact("unload", true)
        .fact("peak_force_N", unloaded.peak_force)
        .fact("residual_deformation", finite_or_null(unloaded.residual_deformation))
        .fact("residual_approach_m", finite_or_null(unloaded.residual_approach));
  }
}

}  // namespace shapepress::scenarios
