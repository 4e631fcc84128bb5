#include "scenarios/compact.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>

namespace shapepress::scenarios {

ScenarioState compaction_scenario_state(const PunchState& punch, const CompactionSetup& setup) {
  ScenarioState state = punch_scenario_state(punch);
  state.emplace_back("bed_body_volume", setup.body_volume);
  state.emplace_back("bed_shape_volume", setup.shape_volume);
  state.emplace_back("bed_sphere_volume", setup.sphere_volume);
  state.emplace_back("bed_mean_diameter", setup.inertial.diameter);
  const TimeStepChoice& t = setup.time_step;
  state.emplace_back("time_step_s", t.time_step);
  state.emplace_back("rayleigh_time_s", t.rayleigh_time);
  state.emplace_back("collision_time_s", t.collision_time);
  state.emplace_back("collision_speed_m_per_s", t.collision_speed);
  state.emplace_back("bond_period_s", t.bond_period);
  state.emplace_back("bond_stability_step_s", t.bond_stability_step);
  state.emplace_back("clump_period_s", t.clump_period);
  state.emplace_back("bond_substeps", t.bond_substeps);
  return state;
}

std::string strain_reference_name(CompactionSetup::StrainReference reference) {
  switch (reference) {
    case CompactionSetup::StrainReference::fill:
      return "fill";
    case CompactionSetup::StrainReference::solid_fraction:
      return "solid_fraction";
    case CompactionSetup::StrainReference::start:
      break;
  }
  return "start";
}

std::string strain_reference_comment(const CompactionSetup& setup) {
  switch (setup.strain_reference) {
    case CompactionSetup::StrainReference::fill:
      return "H0 is the loose fill height (generate.height, punch.strain_reference = fill)";
    case CompactionSetup::StrainReference::solid_fraction:
      return fmt::format(
          "H0 is the gap at which the bed's solid fraction would be {} (punch.strain_reference "
          "= solid_fraction): strain = 1 - {} / solid_fraction",
          setup.reference_solid_fraction, setup.reference_solid_fraction);
    case CompactionSetup::StrainReference::start:
      break;
  }
  return "H0 is the gap when loading starts (punch.strain_reference = start)";
}

std::vector<std::string> punch_csv_columns() {
  return {"time_s",
          "step",
          "gap_m",
          "strain",
          "top_force_N",
          "bottom_force_N",
          "stress_Pa",
          "solid_fraction",
          "phase",
          "kinetic_energy_J",
          "contacts",
          "wall_contacts",
          "contacts_per_particle",
          "intact_bonds",
          "solid_fraction_spheres",
          "punch_work_J",
          "solid_fraction_shape"};
}

std::vector<double> punch_csv_row(const PunchRecord& r) {
  return {r.time,
          static_cast<double>(r.step),
          r.gap,
          r.strain,
          r.top_force,
          r.bottom_force,
          r.stress,
          r.solid_fraction,
          static_cast<double>(r.phase),
          r.kinetic_energy,
          static_cast<double>(r.sphere_contacts),
          static_cast<double>(r.wall_contacts),
          r.contacts_per_particle,
          static_cast<double>(r.intact_bonds),
          r.solid_fraction_spheres,
          r.punch_work,
          r.solid_fraction_shape};
}

PunchRecord punch_record(const Engine& engine, const CompactionSetup& setup,
                         const PunchState& punch) {
  const auto& walls = engine.walls();
  PunchRecord r;
  r.step = engine.step_index();
  r.time = engine.time();
  r.gap = walls[setup.punch_wall].position - walls[setup.bottom_wall].position;
  r.strain = (punch.reference_gap - r.gap) / punch.reference_gap;
  r.top_force = engine.wall_load(setup.punch_wall);
  r.bottom_force = engine.wall_load(setup.bottom_wall);
  r.stress = r.top_force / setup.die_area;
  r.solid_fraction = setup.solid_volume / (setup.die_area * r.gap);
  r.solid_fraction_spheres = setup.sphere_volume / (setup.die_area * r.gap);
  r.solid_fraction_shape = setup.shape_volume / (setup.die_area * r.gap);
  r.phase = punch.phase;
  r.kinetic_energy = engine.energy().kinetic;
  r.punch_work = punch.work;
  r.sphere_contacts = engine.sphere_contacts();
  r.wall_contacts = engine.wall_contacts();
  const double n = static_cast<double>(engine.state().size());
  r.contacts_per_particle = n > 0 ? 2.0 * static_cast<double>(r.sphere_contacts) / n : 0.0;
  r.intact_bonds = engine.bonds().intact_count();
  return r;
}

QuasiStaticCheck quasi_static_check(const std::vector<PunchRecord>& records,
                                    const InertialScale& scale) {
  QuasiStaticCheck check;
  double peak = 0.0, unload_work = 0.0;
  for (std::size_t k = 0; k < records.size(); ++k) {
    const PunchRecord& r = records[k];
    if (r.phase == PunchPhase::load) peak = std::max(peak, r.stress);
    if (r.phase == PunchPhase::unload && unload_work == 0.0)
      unload_work = k > 0 ? records[k - 1].punch_work : r.punch_work;
  }
  double imbalance_sum[2] = {0.0, 0.0};
  for (std::size_t k = 1; k < records.size(); ++k) {
    const PunchRecord& r = records[k];
    const bool loading = r.phase == PunchPhase::load;
    if ((!loading && r.phase != PunchPhase::unload) || !(peak > 0.0) || r.stress < 0.1 * peak)
      continue;
    const double work = loading ? r.punch_work : unload_work;
    if (!(work > 0.0)) continue;
    PhaseQuasiStatic& phase = loading ? check : check.unload;
    ++phase.records;
    phase.max_kinetic_to_work = std::max(phase.max_kinetic_to_work, r.kinetic_energy / work);
    const double imbalance = std::fabs(r.top_force - r.bottom_force) / r.top_force;
    imbalance_sum[loading ? 0 : 1] += imbalance;
    phase.max_force_imbalance = std::max(phase.max_force_imbalance, imbalance);
    const PunchRecord& before = records[k - 1];
    const double dt = r.time - before.time;
    if (scale.diameter > 0.0 && scale.density > 0.0 && dt > 0.0) {
      const double strain_rate = std::fabs(r.gap - before.gap) / dt / r.gap;
      phase.max_inertial_number =
          std::max(phase.max_inertial_number,
                   strain_rate * scale.diameter * std::sqrt(scale.density / r.stress));
    }
  }
  if (check.records > 0)
    check.mean_force_imbalance = imbalance_sum[0] / static_cast<double>(check.records);
  if (check.unload.records > 0)
    check.unload.mean_force_imbalance =
        imbalance_sum[1] / static_cast<double>(check.unload.records);
  return check;
}

CompactionSummary run_compaction(Engine& engine, const CompactionSetup& setup, PunchState& punch,
                                 const CompactionHooks& hooks, CompactionHistory history) {
  CompactionSummary summary;
  const auto emit = [&](PunchRecord record) {
    // The engine checks every check_every steps; a short run (advise's coarse rungs) can blow up
    // between two checks and record non-finite rows. Checked at every record, a run that
    // diverged stops with its named cause (exit 1) instead, as plate's rows are.
    engine.check_divergence();
    if (hooks.record) hooks.record(record);
    history.records.push_back(record);
  };
  // A resumed run's first record is the checkpoint's; recomputed here it would miss the contact
  // counts, which only a force evaluation sets. The relaxation before loading is not recorded:
  // the first record is where loading starts.
  const auto relaxing = [&] { return punch.phase == PunchPhase::relax; };
  if (history.records.empty() && !relaxing()) emit(punch_record(engine, setup, punch));
  const auto start = std::chrono::steady_clock::now();
  const double seconds_before = history.loop_seconds;
  history.loop_started = start;
  auto& walls = engine.walls();
  while (punch.phase != PunchPhase::done &&
         (setup.max_steps <= 0 || engine.step_index() < setup.max_steps)) {
    const double gap = walls[setup.punch_wall].position - walls[setup.bottom_wall].position;
    const double stress = engine.wall_load(setup.punch_wall) / setup.die_area;
    const double velocity = punch_velocity(setup.program, punch, engine.time(), gap, stress);
    if (history.records.empty() && !relaxing()) emit(punch_record(engine, setup, punch));
    walls[setup.punch_wall].velocity = velocity;
    engine.step();
    // The punch moves down at -velocity against the bed's load on it.
    punch.work -= engine.wall_load(setup.punch_wall) * velocity * engine.settings().time_step;
    ++history.steps;
    history.work_count += step_work(engine);
    ++summary.loop_steps;
    const std::int64_t step = engine.step_index();
    if (setup.record_every > 0 && step % setup.record_every == 0 && !relaxing())
      emit(punch_record(engine, setup, punch));
    if (setup.snapshot_every > 0 && step % setup.snapshot_every == 0 && hooks.snapshot)
      hooks.snapshot(engine, punch);
    if (hooks.progress) hooks.progress(step);
    if (hooks.after_step && !hooks.after_step(engine, punch, history)) {
      summary.interrupted = true;
      break;
    }
  }
  summary.loop_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!summary.interrupted &&
      (history.records.empty() || history.records.back().step != engine.step_index()))
    emit(punch_record(engine, setup, punch));
  for (const PunchRecord& r : history.records)
    summary.max_stress = std::max(summary.max_stress, r.stress);
  if (!history.records.empty()) {
    summary.first = history.records.front();
    summary.last = history.records.back();
  }
  summary.steps = history.steps;
  summary.work_count = history.work_count;
  summary.total_loop_seconds = seconds_before + summary.loop_seconds;
  summary.quasi_static = quasi_static_check(history.records, setup.inertial);
  return summary;
}

}  // namespace shapepress::scenarios
