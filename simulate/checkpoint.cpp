#include "simulate/checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <regex>
#include <vector>

#include "common/atomic_file.hpp"

namespace shapepress::simulate {

void write_checkpoint(const std::filesystem::path& folder, const Engine& engine,
                      const ScenarioState& scenario, const Provenance& provenance,
                      const std::string& history, std::string_view prefix, std::size_t keep) {
  const std::string stem = fmt::format("{}_{:010d}", prefix, engine.step_index());
  const std::string mine = std::string(prefix) + "_";
  write_snapshot(folder / (stem + ".h5"), engine, scenario, provenance);
  write_file_atomically(folder / (stem + ".history"), history);

  // The newest `keep` whole checkpoints stay; older ones, and snapshots whose history never
  // came (a kill between the two files), go.
  std::vector<CheckpointFiles> whole;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const std::filesystem::path p = entry.path();
    if (p.extension() == ".history" && p.filename().string().starts_with(mine) &&
        std::filesystem::exists(p.parent_path() / (p.stem().string() + ".h5")))
      whole.push_back({0, p.parent_path() / (p.stem().string() + ".h5"), p});
  }
  std::sort(whole.begin(), whole.end(), [](const auto& a, const auto& b) {
    return a.history.filename() > b.history.filename();
  });
  for (std::size_t k = keep; k < whole.size(); ++k) {
    std::filesystem::remove(whole[k].history, ec);
    std::filesystem::remove(whole[k].snapshot, ec);
  }
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const std::filesystem::path p = entry.path();
    if (p.extension() == ".h5" && p.filename().string().starts_with(mine) &&
        p.stem().string() < stem &&
        !std::filesystem::exists(p.parent_path() / (p.stem().string() + ".history")))
      std::filesystem::remove(p, ec);
  }
}

std::optional<CheckpointFiles> latest_checkpoint(const std::filesystem::path& folder,
                                                 std::string_view prefix) {
  const std::regex name(std::string(prefix) + R"(_(\d{10})\.history)");
  std::optional<CheckpointFiles> latest;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    std::smatch m;
    const std::string file = entry.path().filename().string();
    if (!std::regex_match(file, m, name)) continue;
    const std::filesystem::path snapshot =
        entry.path().parent_path() / (std::string(prefix) + "_" + m[1].str() + ".h5");
    if (!std::filesystem::exists(snapshot)) continue;
    const std::int64_t step = std::stoll(m[1].str());
    if (!latest || step > latest->step) latest = CheckpointFiles{step, snapshot, entry.path()};
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
