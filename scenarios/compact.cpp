#include "scenarios/compact.hpp"

#include <chrono>
#include <numbers>

namespace shapepress::scenarios {

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
  // setup.solid_volume counts each clump's union once (compact_setup.cpp).
  r.solid_fraction = setup.solid_volume / (setup.die_area * r.gap);
  r.phase = punch.phase;
  r.kinetic_energy = engine.energy().kinetic;
  r.sphere_contacts = engine.sphere_contacts();
  r.wall_contacts = engine.wall_contacts();
  const double n = static_cast<double>(engine.state().size());
  r.contacts_per_particle = n > 0 ? 2.0 * static_cast<double>(r.sphere_contacts) / n : 0.0;
  r.intact_bonds = engine.bonds().intact_count();
  return r;
}

CompactionSummary run_compaction(Engine& engine, const CompactionSetup& setup, PunchState& punch,
                                 const CompactionHooks& hooks) {
  CompactionSummary summary;
  const auto emit = [&](PunchRecord record) {
    summary.max_stress = std::max(summary.max_stress, record.stress);
    if (hooks.record) hooks.record(record);
    summary.last = record;
  };
  emit(punch_record(engine, setup, punch));
  const auto start = std::chrono::steady_clock::now();
  auto& walls = engine.walls();
  while (punch.phase != PunchPhase::done &&
         (setup.max_steps <= 0 || engine.step_index() < setup.max_steps)) {
    const double gap = walls[setup.punch_wall].position - walls[setup.bottom_wall].position;
    const double stress = engine.wall_load(setup.punch_wall) / setup.die_area;
    walls[setup.punch_wall].velocity =
        punch_velocity(setup.program, punch, engine.time(), gap, stress);
    engine.step();
    ++summary.steps;
    const std::int64_t step = engine.step_index();
    if (setup.record_every > 0 && step % setup.record_every == 0)
      emit(punch_record(engine, setup, punch));
    if (setup.snapshot_every > 0 && step % setup.snapshot_every == 0 && hooks.snapshot)
      hooks.snapshot(engine, punch);
    if (hooks.progress) hooks.progress(step);
  }
  summary.loop_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (summary.last.step != engine.step_index()) emit(punch_record(engine, setup, punch));
  return summary;
}

}  // namespace shapepress::scenarios
