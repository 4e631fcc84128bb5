#include "simulate/checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "common/atomic_file.hpp"

namespace shapepress::simulate {

void write_checkpoint(const std::filesystem::path& folder, const Engine& engine,
                      const ScenarioState& scenario, const Provenance& provenance,
                      std::string_view stage, const CheckpointState& state, std::string_view prefix,
                      std::size_t keep) {
  const std::string stem = fmt::format("{}_{:010d}", prefix, engine.step_index());
  const std::string mine = std::string(prefix) + "_";
  write_snapshot(folder / (stem + ".h5"), engine, scenario, provenance);
  write_checkpoint_record(checkpoint_record_path(folder, prefix, engine.step_index()), stage,
                          engine.step_index(), state);

  // The newest `keep` whole checkpoints stay; older ones, and snapshots whose record never
  // came (a kill between the two files), go.
  std::vector<CheckpointFiles> whole;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const std::filesystem::path p = entry.path();
    if (p.extension() == ".json" && p.filename().string().starts_with(mine) &&
        std::filesystem::exists(p.parent_path() / (p.stem().string() + ".h5")))
      whole.push_back({0, p.parent_path() / (p.stem().string() + ".h5"), p});
  }
  std::sort(whole.begin(), whole.end(),
            [](const auto& a, const auto& b) { return a.record.filename() > b.record.filename(); });
  for (std::size_t k = keep; k < whole.size(); ++k) {
    std::filesystem::remove(whole[k].record, ec);
    std::filesystem::remove(whole[k].snapshot, ec);
  }
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const std::filesystem::path p = entry.path();
    if (p.extension() == ".h5" && p.filename().string().starts_with(mine) &&
        p.stem().string() < stem &&
        !std::filesystem::exists(p.parent_path() / (p.stem().string() + ".json")))
      std::filesystem::remove(p, ec);
  }
}

std::optional<CheckpointFiles> latest_checkpoint(const std::filesystem::path& folder,
                                                 std::string_view prefix) {
  std::optional<CheckpointFiles> latest;
  for (const auto& [step, record] : checkpoint_records(folder, prefix)) {
    const std::filesystem::path snapshot = record.parent_path() / (record.stem().string() + ".h5");
    if (std::filesystem::exists(snapshot)) latest = CheckpointFiles{step, snapshot, record};
  }
  return latest;
}

void remove_checkpoints(const std::filesystem::path& folder, std::string_view prefix) {
  const std::string mine = std::string(prefix) + "_";
  std::error_code ec;
  std::vector<std::filesystem::path> doomed;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec))
    if (entry.path().filename().string().starts_with(mine)) doomed.push_back(entry.path());
  for (const std::filesystem::path& p : doomed)
    std::filesystem::remove(p, ec);
}

}  // namespace shapepress::simulate
