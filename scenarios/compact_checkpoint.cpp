#include "scenarios/compact_checkpoint.hpp"

#include <fmt/format.h>

#include <chrono>
#include <limits>

#include "common/checkpoint.hpp"
#include "simulate/checkpoint.hpp"

namespace shapepress::scenarios {
namespace {

CheckpointState record_state(const PunchRecord& r) {
  CheckpointState s;
  s.whole("step", r.step)
      .number("time", r.time)
      .number("gap", r.gap)
      .number("strain", r.strain)
      .number("top_force", r.top_force)
      .number("bottom_force", r.bottom_force)
      .number("stress", r.stress)
      .number("solid_fraction", r.solid_fraction)
      .number("solid_fraction_spheres", r.solid_fraction_spheres)
      .whole("phase", static_cast<std::int64_t>(r.phase))
      .number("kinetic_energy", r.kinetic_energy)
      .number("punch_work", r.punch_work)
      .whole("sphere_contacts", r.sphere_contacts)
      .whole("wall_contacts", r.wall_contacts)
      .number("contacts_per_particle", r.contacts_per_particle)
      .whole("intact_bonds", r.intact_bonds);
  return s;
}

PunchRecord read_record(const CheckpointFields& f) {
  PunchRecord r;
  r.step = f.whole("step");
  r.time = f.number("time");
  r.gap = f.number("gap");
  r.strain = f.number("strain");
  r.top_force = f.number("top_force");
  r.bottom_force = f.number("bottom_force");
  r.stress = f.number("stress");
  r.solid_fraction = f.number("solid_fraction");
  r.solid_fraction_spheres = f.number("solid_fraction_spheres");
  r.phase = static_cast<PunchPhase>(f.whole("phase", 0, static_cast<int>(PunchPhase::relax)));
  r.kinetic_energy = f.number("kinetic_energy");
  r.punch_work = f.number("punch_work");
  r.sphere_contacts = f.whole("sphere_contacts");
  r.wall_contacts = f.whole("wall_contacts");
  r.contacts_per_particle = f.number("contacts_per_particle");
  r.intact_bonds = f.whole("intact_bonds");
  return r;
}

constexpr std::int64_t most = std::numeric_limits<std::int64_t>::max();

}  // namespace

void write_compact_checkpoint(const std::filesystem::path& out, const Engine& engine,
                              const ScenarioState& scenario, const Provenance& provenance,
                              const CheckpointHistory& history) {
  const double loop_seconds = history.compaction.loop_seconds +
                              std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                                            history.compaction.loop_started)
                                  .count();
  std::vector<CheckpointState> records, snapshots;
  records.reserve(history.compaction.records.size());
  for (const PunchRecord& r : history.compaction.records)
    records.push_back(record_state(r));
  for (const SnapshotIndexEntry& e : history.snapshots)
    snapshots.push_back(CheckpointState()
                            .text("file", e.file.generic_string())
                            .number("time", e.time)
                            .whole("spheres", static_cast<std::int64_t>(e.spheres))
                            .whole("walls", static_cast<std::int64_t>(e.walls))
                            .flag("stress", e.stress)
                            .whole("bonds", static_cast<std::int64_t>(e.bonds))
                            .whole("clumps", static_cast<std::int64_t>(e.clumps)));
  CheckpointState state;
  state.whole("steps", history.compaction.steps)
      .number("loop_s", loop_seconds)  // NaN: unknown (resumed from a run that did not say)
      .list("records", std::move(records))
      .list("snapshots", std::move(snapshots));
  const std::filesystem::path folder = out / std::string(checkpoint_folder);
  write_checkpoint(folder, engine, scenario, provenance, compact_stage, state);
  remove_checkpoints(folder, settle_checkpoint_prefix);
}

void write_settle_checkpoint(const std::filesystem::path& out, const Engine& engine,
                             const Provenance& provenance) {
  write_checkpoint(out / std::string(checkpoint_folder), engine, {}, provenance, compact_stage,
                   CheckpointState(), settle_checkpoint_prefix);
}

CheckpointHistory read_checkpoint_history(const std::filesystem::path& path) {
  const CheckpointRecord record = read_checkpoint_record(path, compact_stage);
  const CheckpointFields state = record.state();
  CheckpointHistory h;
  h.compaction.steps = state.whole("steps", 0, most);
  h.compaction.loop_seconds = state.number("loop_s");
  for (const CheckpointFields& r : state.list("records"))
    h.compaction.records.push_back(read_record(r));
  for (const CheckpointFields& e : state.list("snapshots")) {
    SnapshotIndexEntry entry;
    entry.file = e.text("file");
    entry.time = e.number("time");
    entry.spheres = static_cast<std::size_t>(e.whole("spheres", 0, most));
    entry.walls = static_cast<std::size_t>(e.whole("walls", 0, most));
    entry.stress = e.flag("stress");
    entry.bonds = static_cast<std::size_t>(e.whole("bonds", 0, most));
    entry.clumps = static_cast<std::size_t>(e.whole("clumps", 0, most));
    h.snapshots.push_back(entry);
  }
  return h;
}

}  // namespace shapepress::scenarios
