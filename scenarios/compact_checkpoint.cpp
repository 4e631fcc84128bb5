#include "scenarios/compact_checkpoint.hpp"

#include <fmt/format.h>

#include <chrono>
#include <limits>
#include <string_view>
#include <utility>

#include "common/checkpoint.hpp"
#include "simulate/checkpoint.hpp"

namespace shapepress::scenarios {
namespace {

// A punch record's fields by their checkpoint keys: one table writes and reads them.
constexpr std::pair<std::string_view, std::int64_t PunchRecord::*> record_wholes[] = {
    {"step", &PunchRecord::step},
    {"sphere_contacts", &PunchRecord::sphere_contacts},
    {"wall_contacts", &PunchRecord::wall_contacts},
    {"intact_bonds", &PunchRecord::intact_bonds}};
constexpr std::pair<std::string_view, double PunchRecord::*> record_numbers[] = {
    {"time", &PunchRecord::time},
    {"gap", &PunchRecord::gap},
    {"strain", &PunchRecord::strain},
    {"top_force", &PunchRecord::top_force},
    {"bottom_force", &PunchRecord::bottom_force},
    {"stress", &PunchRecord::stress},
    {"solid_fraction", &PunchRecord::solid_fraction},
    {"solid_fraction_spheres", &PunchRecord::solid_fraction_spheres},
    {"kinetic_energy", &PunchRecord::kinetic_energy},
    {"punch_work", &PunchRecord::punch_work},
    {"contacts_per_particle", &PunchRecord::contacts_per_particle}};

CheckpointState record_state(const PunchRecord& r) {
  CheckpointState s;
  for (const auto& [key, field] : record_wholes)
    s.whole(key, r.*field);
  for (const auto& [key, field] : record_numbers)
    s.number(key, r.*field);
  s.whole("phase", static_cast<std::int64_t>(r.phase));
  return s;
}

// (solid_fraction_shape follows from the gap: the caller sets it.)
PunchRecord read_record(const CheckpointFields& f) {
  PunchRecord r;
  for (const auto& [key, field] : record_wholes)
    r.*field = f.whole(key);
  for (const auto& [key, field] : record_numbers)
    r.*field = f.number(key);
  r.phase = static_cast<PunchPhase>(f.whole("phase", 0, static_cast<int>(PunchPhase::relax)));
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
  state.whole("steps", history.compaction.steps);
  add_work_count(state, history.compaction.work_count)
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
  h.compaction.work_count = read_work_count(state);
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
