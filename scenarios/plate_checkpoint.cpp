#include "scenarios/plate_checkpoint.hpp"

#include <fmt/format.h>

#include <limits>
#include <mutex>
#include <string_view>
#include <utility>

#include "common/checkpoint.hpp"
#include "scenarios/plate_run.hpp"
#include "simulate/checkpoint.hpp"

namespace shapepress::scenarios {
namespace {

constexpr std::string_view plate_stage = "plate";

// One lock for the folder's files: the fills of an ensemble write them from their threads.
std::mutex& files_lock() {
  static std::mutex lock;
  return lock;
}

std::string prefix(int fill) {
  return fmt::format("fill{}", fill);
}

// A finished fill's record: fill<k>.json (not fill<k>_N.json, so that removing the fill's step
// checkpoints leaves it).
std::filesystem::path finished_file(const std::filesystem::path& folder, int fill) {
  return folder / (prefix(fill) + ".json");
}

// A row's fields by their checkpoint keys: one table writes and reads them.
constexpr std::pair<std::string_view, double PlateRow::*> row_numbers[] = {
    {"time", &PlateRow::time},
    {"deformation", &PlateRow::deformation},
    {"approach", &PlateRow::approach},
    {"top_force", &PlateRow::top_force},
    {"bottom_force", &PlateRow::bottom_force},
    {"hertz_force", &PlateRow::hertz_force},
    {"kinetic_energy", &PlateRow::kinetic_energy},
    {"work", &PlateRow::work},
    {"cpu_s", &PlateRow::cpu_seconds},
    {"wall_s", &PlateRow::wall_seconds},
    {"top_force_sd", &PlateRow::top_force_sd},
    {"top_force_min", &PlateRow::top_force_min},
    {"top_force_max", &PlateRow::top_force_max}};
constexpr std::pair<std::string_view, std::int64_t PlateRow::*> row_wholes[] = {
    {"contacts", &PlateRow::contacts}, {"intact_bonds", &PlateRow::intact_bonds}};
std::vector<CheckpointState> rows_state(const std::vector<PlateRow>& rows) {
  std::vector<CheckpointState> items(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    for (const auto& [key, field] : row_numbers)
      items[k].number(key, rows[k].*field);
    for (const auto& [key, field] : row_wholes)
      items[k].whole(key, rows[k].*field);
    add_work_count(items[k], rows[k].work_count);
  }
  return items;
}

std::vector<PlateRow> read_rows(const CheckpointFields& state) {
  std::vector<PlateRow> rows;
  for (const CheckpointFields& f : state.list("rows")) {
    PlateRow& r = rows.emplace_back();
    for (const auto& [key, field] : row_numbers)
      r.*field = f.number(key);
    for (const auto& [key, field] : row_wholes)
      r.*field = f.whole(key);
    r.work_count = read_work_count(f);
  }
  return rows;
}

std::size_t count(const CheckpointFields& state, std::string_view key) {
  return static_cast<std::size_t>(state.whole(key, 0, std::numeric_limits<std::int64_t>::max()));
}

}  // namespace

PlateCheckpoints::PlateCheckpoints(std::filesystem::path folder, CheckpointPolicy policy,
                                   Provenance provenance, bool final_snapshot)
    : folder_(std::move(folder)),
      policy_(policy),
      provenance_(std::move(provenance)),
      final_snapshot_(final_snapshot) {}

std::optional<PlateRunOutcome> PlateCheckpoints::finished(int fill) const {
  const std::lock_guard<std::mutex> lock(files_lock());
  const std::filesystem::path path = finished_file(folder_, fill);
  if (!std::filesystem::exists(path)) return std::nullopt;
  const CheckpointRecord record = read_checkpoint_record(path, plate_stage);
  const CheckpointFields state = record.state();
  PlateRunOutcome o;
  o.spheres = count(state, "spheres");
  o.bonds = count(state, "bonds");
  o.requested_spheres = count(state, "requested_spheres");
  o.sub_sphere_radius = state.number("sub_sphere_radius");
  o.time_step = state.number("time_step");
  o.description = state.text("description");
  o.rows = read_rows(state);
  return o;
}

void PlateCheckpoints::finish(int fill, const PlateRunOutcome& o, std::int64_t step) const {
  const std::lock_guard<std::mutex> lock(files_lock());
  if (fill == 0 && final_snapshot_) write_plate_snapshot(folder_, o, provenance_);
  write_checkpoint_record(
      finished_file(folder_, fill), plate_stage, step,
      CheckpointState()
          .whole("spheres", static_cast<std::int64_t>(o.spheres))
          .whole("bonds", static_cast<std::int64_t>(o.bonds))
          .whole("requested_spheres", static_cast<std::int64_t>(o.requested_spheres))
          .number("sub_sphere_radius", o.sub_sphere_radius)
          .number("time_step", o.time_step)
          .text("description", o.description)
          .list("rows", rows_state(o.rows)));
  simulate::remove_checkpoints(folder_, prefix(fill));
}

PlateHooks PlateCheckpoints::hooks(int fill) const {
  PlateHooks hooks;
  {
    const std::lock_guard<std::mutex> lock(files_lock());
    if (const auto latest = simulate::latest_checkpoint(folder_, prefix(fill))) {
      const CheckpointRecord record = read_checkpoint_record(latest->record, plate_stage);
      const CheckpointFields state = record.state();
      PlateProgress progress;
      progress.cpu_seconds = state.number("cpu_s");
      progress.wall_seconds = state.number("wall_s");
      progress.work_count = read_work_count(state);
      progress.rows = read_rows(state);
      hooks.resume = PlateResumePoint{read_snapshot(latest->snapshot), std::move(progress)};
    }
  }
  // Each fill keeps its own clock: the fills' checkpoints come at their own steps.
  auto clock = std::make_shared<CheckpointClock>(policy_);
  hooks.after_step = [this, fill, clock](const Engine& engine,
                                         const std::function<PlateProgress()>& progress) {
    if (!clock->due(engine.step_index())) return true;
    const PlateProgress p = progress();
    CheckpointState state;
    state.number("cpu_s", p.cpu_seconds).number("wall_s", p.wall_seconds);
    add_work_count(state, p.work_count).list("rows", rows_state(p.rows));
    {
      const std::lock_guard<std::mutex> lock(files_lock());
      simulate::write_checkpoint(folder_, engine, {}, provenance_, plate_stage, state,
                                 prefix(fill));
    }
    clock->taken();
    return SignalCheckpoints::received() == 0;
  };
  return hooks;
}

}  // namespace shapepress::scenarios
