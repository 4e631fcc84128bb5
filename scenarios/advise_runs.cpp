#include "scenarios/advise_runs.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <fstream>

#include "analysis/plot.hpp"
#include "common/error.hpp"

namespace shapepress::scenarios {

namespace fs = std::filesystem;

ChildEnd run_process(const std::vector<std::string>& args, const fs::path& log) {
  return run_child({args, "a step of advise", "", {}, {}, log});
}

std::string error_line(const fs::path& log, const std::string& stage) {
  std::ifstream in(log);
  std::string line, last;
  const std::string marks[] = {stage + ": error: ", stage + ": failed: "};
  while (std::getline(in, line))
    for (const std::string& mark : marks)
      if (const auto at = line.find(mark); at != std::string::npos)
        last = line.substr(at + mark.size());
  return last;
}

std::string divergence_cause(const std::string& message) {
  if (message.find("non-finite") != std::string::npos) return "non-finite";
  if (message.find("bonded spheres") != std::string::npos) return "bond overlap";
  if (message.find("energy") != std::string::npos) return "energy";
  if (message.find("overlap") != std::string::npos) return "overlap";
  return "failed";
}

std::optional<nlohmann::json> finished_record(const fs::path& path, const nlohmann::json& key,
                                              bool resume) {
  if (!fs::exists(path)) return std::nullopt;
  std::ifstream in(path);
  nlohmann::json record = nlohmann::json::parse(in, nullptr, false);
  if (record.is_discarded() || !record.contains("key") || !record.contains("exit_code"))
    throw InputError(fmt::format("{}: not a record of advise; remove the folder", path.string()));
  if (record["key"] != key)
    throw InputError(
        fmt::format("{} holds a step of another advise ({} against {}): use another --out",
                    path.string(), record["key"].dump(), key.dump()));
  if (!resume)
    throw InputError(
        fmt::format("{} holds finished steps of an earlier advise: --resume reuses them",
                    path.parent_path().string()));
  return record;
}

std::string this_binary() {
  return fs::read_symlink("/proc/self/exe").string();
}

std::int64_t counted_cost(const std::filesystem::path& folder, std::string_view stage) {
  const RunRecord run = RunRecord::read(folder / run_metadata_name, stage);
  return run.has("counted_cost") ? run.integer("counted_cost") : -1;
}

void write_advice(const analysis::Advice& advice, const std::filesystem::path& out,
                  RunMetadata& meta) {
  analysis::write_advice_csv(out / "advice.csv", advice);
  meta.output("advice.csv");
  if (!analysis::find_gnuplot().empty()) {
    analysis::plot_chart(analysis::speed_accuracy_chart(advice), out / "speed_accuracy");
    analysis::plot_chart(analysis::stability_map_chart(advice), out / "stability_map");
    meta.output("speed_accuracy.svg").output("stability_map.svg");
  } else {
    spdlog::warn("advise: gnuplot not on PATH: no charts (advice.csv has the numbers)");
  }
}

}  // namespace shapepress::scenarios
