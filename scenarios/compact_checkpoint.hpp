#pragma once
// Checkpoints of a compaction for `compact --resume` (docs/stages.md, "Checkpoints and
// --resume"): in OUT/checkpoints/, a snapshot step_N.h5 (the engine and the punch, as --restart
// reads it) and beside it step_N.history, the CompactionHistory at that step (every punch.csv
// record at full precision, the steps taken) and the snapshot index so far. The history is
// written after the snapshot, each atomically, so a checkpoint whose history exists is whole.
// resume.json says how the run was started, so --resume OUT needs nothing else.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>
#include "scenarios/namespaces.hpp"

#include "scenarios/compact.hpp"
#include "simulate/snapshot.hpp"

namespace shapepress::scenarios {

inline constexpr std::string_view checkpoint_folder = "checkpoints";

// How a compaction was started: what --resume runs again (before the first checkpoint) or
// continues.
struct CompactInvocation {
  std::string command_line;
  std::filesystem::path working_directory;  // relative paths below are from here
  std::string config, packing, restart;
  std::int64_t steps = -1;  // --steps; < 0: the config's
  std::string config_sha256;
};
void write_invocation(const std::filesystem::path& out, const CompactInvocation& invocation);
// InputError naming the folder when it holds no compaction that can be resumed.
CompactInvocation read_invocation(const std::filesystem::path& out);

struct CheckpointHistory {
  CompactionHistory compaction;
  std::vector<SnapshotIndexEntry> snapshots;
};

struct CheckpointFiles {
  std::int64_t step = 0;
  std::filesystem::path snapshot, history;
};

// Writes step_N.h5 then step_N.history, and removes all but the newest `keep` checkpoints.
void write_checkpoint(const std::filesystem::path& out, const Engine& engine,
                      const ScenarioState& scenario, const Provenance& provenance,
                      const CheckpointHistory& history, std::size_t keep = 2);
// The newest whole checkpoint, none when the run was killed before its first.
std::optional<CheckpointFiles> latest_checkpoint(const std::filesystem::path& out);
// InputError naming the file when it is not a checkpoint history.
CheckpointHistory read_checkpoint_history(const std::filesystem::path& path);

// Removes the ".name.tmp.PID" files a killed run left in `folder` (common/atomic_file.hpp).
void remove_stale_temporaries(const std::filesystem::path& folder);

}  // namespace shapepress::scenarios
