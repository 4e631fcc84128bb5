#pragma once
// How `shapepress advise` runs its ladder (issue 21, point 2): every rung, and every bed a
// compaction ladder fills and packs, is a shapepress process of its own in its own folder, so a
// run that diverges ends with its own exit code and named cause, and a killed advise leaves
// every finished step reusable. A folder counts as done when its record (written last,
// atomically) names the same key: the inputs' content and the rung's settings.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/advise.hpp"
#include "common/child_process.hpp"
#include "common/run_metadata.hpp"

namespace shapepress::scenarios {

// Runs `args` (argv[0] the binary) with stdout and stderr into `log`.
ChildEnd run_process(const std::vector<std::string>& args, const std::filesystem::path& log);

// The message of a failed run: the last "shapepress STAGE: error: …" (exit 2) or
// "…: failed: …" (exit 1) line main() printed into `log`.
std::string error_line(const std::filesystem::path& log, const std::string& stage);

// The named cause of a run's divergence message (simulate/diagnostics.cpp words them).
std::string divergence_cause(const std::string& message);

// A finished run's counted cost: the counted_cost of its run.json in `folder`, made by `stage`
// (scenarios/run_facts.hpp); -1 (unknown) when that run.json does not state one (a run from
// before the count). InputError naming the file when it is not that stage's run.json.
std::int64_t counted_cost(const std::filesystem::path& folder, std::string_view stage);

// The record of a finished step whose key is `key` (nothing when `record` does not exist).
// InputError when it holds another step (another config or settings), or when it is finished and
// `resume` is not set: finished work is neither silently reused nor overwritten.
std::optional<nlohmann::json> finished_record(const std::filesystem::path& record,
                                              const nlohmann::json& key, bool resume);

// The shapepress binary running now, to start the steps with.
std::string this_binary();

// advice.csv, and the speed–accuracy chart and stability map when gnuplot is there, into `out`,
// each named in `meta`.
void write_advice(const analysis::Advice& advice, const std::filesystem::path& out,
                  RunMetadata& meta);

}  // namespace shapepress::scenarios
