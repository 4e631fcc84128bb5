#pragma once
// Checkpoints of a compaction for `compact --resume` (docs/stages.md, "Checkpoints and
// --resume"): in OUT/checkpoints/, a snapshot step_N.h5 (the engine and the punch, as --restart
// reads it) and beside it step_N.history, the CompactionHistory at that step (every punch.csv
// record at full precision, the steps taken) and the snapshot index so far. The history is
// written after the snapshot, each atomically, so a checkpoint whose history exists is whole.
// resume.json (common/resume.hpp) says how the run was started, so --resume OUT needs nothing
// else.
#include <filesystem>
#include <vector>
#include "scenarios/namespaces.hpp"

#include "common/provenance.hpp"
#include "scenarios/compact.hpp"
#include "simulate/snapshot.hpp"

namespace shapepress::scenarios {

inline constexpr std::string_view checkpoint_folder = "checkpoints";
// The settle of a generated bed runs an engine of its own before the compaction's: its
// checkpoints are settle_N.h5 and settle_N.history (no history but its name), removed once the
// compaction has one.
inline constexpr std::string_view settle_checkpoint_prefix = "settle";

struct CheckpointHistory {
  CompactionHistory compaction;
  std::vector<SnapshotIndexEntry> snapshots;
};

// Writes OUT/checkpoints/step_N.h5 and step_N.history (simulate/checkpoint.hpp), the newest two
// kept.
void write_compact_checkpoint(const std::filesystem::path& out, const Engine& engine,
                              const ScenarioState& scenario, const Provenance& provenance,
                              const CheckpointHistory& history);
void write_settle_checkpoint(const std::filesystem::path& out, const Engine& engine,
                             const Provenance& provenance);
// InputError naming the file when it is not a checkpoint history. A history without records is
// one taken before loading began (the punch's relaxation, which is not recorded): the caller
// judges it against the snapshot's punch phase.
CheckpointHistory read_checkpoint_history(const std::filesystem::path& path);

}  // namespace shapepress::scenarios
