#pragma once
// The files of a checkpoint for --resume (docs/stages.md, "Checkpoints and --resume"): in a
// checkpoint folder, a snapshot step_N.h5 (the engine and the scenario's state, as a restart
// reads it) and beside it step_N.json, the stage's record of what it has done so far (the one
// format, common/checkpoint.hpp). The record is written after the snapshot, each atomically, so
// a checkpoint whose record exists is whole. The newest `keep` whole checkpoints stay.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "common/checkpoint.hpp"
#include "simulate/snapshot.hpp"

namespace shapepress::simulate {

struct CheckpointFiles {
  std::int64_t step = 0;
  std::filesystem::path snapshot, record;
};

// Writes <prefix>_N.h5 then the record <prefix>_N.json of `stage` with `state` into `folder` (N
// the engine's step index), and
// removes all but the newest `keep` whole checkpoints of that prefix and any snapshot left
// without its history. A stage whose phases run engines of their own (compact's settle, then
// its compaction, each from step 0) gives each phase its prefix.
void write_checkpoint(const std::filesystem::path& folder, const Engine& engine,
                      const ScenarioState& scenario, const Provenance& provenance,
                      std::string_view stage, const CheckpointState& state,
                      std::string_view prefix = "step", std::size_t keep = 2);

// The newest whole checkpoint of `prefix` in `folder`, none when the run was killed before its
// first.
std::optional<CheckpointFiles> latest_checkpoint(const std::filesystem::path& folder,
                                                 std::string_view prefix = "step");

// Removes every checkpoint of `prefix` from `folder` (a phase whose successor has one).
void remove_checkpoints(const std::filesystem::path& folder, std::string_view prefix);

}  // namespace shapepress::simulate
