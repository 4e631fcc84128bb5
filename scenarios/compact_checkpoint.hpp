#pragma once
// Checkpoints of a compaction for `compact --resume` (docs/stages.md, "Checkpoints and
// --resume"): in OUT/checkpoints/, a snapshot step_N.h5 (the engine and the punch, as --restart
// reads it) and beside it the record step_N.json (common/checkpoint.hpp) of the
// CompactionHistory at that step (every punch.csv record with every bit, the steps taken and
// their work counts, the loop's wall seconds) and the snapshot index so far. resume.json
// (common/resume.hpp) says how the run was started, so --resume OUT needs nothing else.
#include <filesystem>
#include <vector>
#include "scenarios/namespaces.hpp"

#include "common/provenance.hpp"
#include "scenarios/compact.hpp"
#include "simulate/snapshot.hpp"

namespace shapepress::scenarios {

inline constexpr std::string_view checkpoint_folder = "checkpoints";
// The settle of a generated bed runs an engine of its own before the compaction's: its
// checkpoints are settle_N.h5 and settle_N.json (a record with an empty state), removed once the
// compaction has one.
inline constexpr std::string_view settle_checkpoint_prefix = "settle";

struct CheckpointHistory {
  CompactionHistory compaction;
  std::vector<SnapshotIndexEntry> snapshots;
};

inline constexpr std::string_view compact_stage = "compact";

// Writes OUT/checkpoints/step_N.h5 and step_N.json (simulate/checkpoint.hpp), the newest two
// kept.
void write_compact_checkpoint(const std::filesystem::path& out, const Engine& engine,
                              const ScenarioState& scenario, const Provenance& provenance,
                              const CheckpointHistory& history);
void write_settle_checkpoint(const std::filesystem::path& out, const Engine& engine,
                             const Provenance& provenance);
// InputError naming the file and the key when it is not a compaction's record. A history without
// records is one taken before loading began (the punch's relaxation, which is not recorded): the
// caller judges it against the snapshot's punch phase.
CheckpointHistory read_checkpoint_history(const std::filesystem::path& path);

}  // namespace shapepress::scenarios
