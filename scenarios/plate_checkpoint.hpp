#pragma once
// Checkpoints of `plate` for `plate --resume` (docs/stages.md, "plate", "Checkpoints and
// --resume"), in OUT/checkpoints/. A run is fills 0 … K − 1 of an ensemble ([bms] fills = K; one
// run is fill 0 of 1), each with its own files:
// - fill<k>_<step>.h5 and .json: the unfinished fill's engine, rows and work count so far, every
//   run.checkpoint_every steps, every run.checkpoint_minutes and on SIGINT/SIGTERM (the newest
//   two kept, simulate/checkpoint.hpp);
// - fill<k>.json: a finished fill's rows and facts, with every bit, which a resumed ensemble
//   reuses instead of running the fill again;
// - final.h5 and final.xdmf: the first fill's last state, for --snapshot, moved beside force.csv
//   when the run ends.
// The fills run side by side on the threads: every file of this folder is written and read under
// one lock (HDF5 1.10 as Debian builds it is not thread-safe). The .json files are checkpoint
// records of the stage "plate" (common/checkpoint.hpp).
#include <filesystem>
#include <optional>
#include "scenarios/namespaces.hpp"

#include "common/provenance.hpp"
#include "common/resume.hpp"
#include "scenarios/plate.hpp"

namespace shapepress::scenarios {

struct PlateRunOutcome;

class PlateCheckpoints {
 public:
  // `final_snapshot`: keep the first fill's last state (plate --snapshot).
  PlateCheckpoints(std::filesystem::path folder, CheckpointPolicy policy, Provenance provenance,
                   bool final_snapshot);

  const std::filesystem::path& folder() const { return folder_; }
  // Fill k's outcome when it finished in an earlier attempt (its rows and particle facts; no
  // engine).
  std::optional<PlateRunOutcome> finished(int fill) const;
  // Writes fill<k>.json (and for fill 0, final.h5 + final.xdmf when asked) and removes the fill's
  // step checkpoints; `step`: the fill's last.
  void finish(int fill, const PlateRunOutcome& outcome, std::int64_t step) const;
  // Where an unfinished fill k resumes from (its newest checkpoint), and the hook that writes its
  // checkpoints while it runs and stops it on a signal.
  PlateHooks hooks(int fill) const;

 private:
  std::filesystem::path folder_;
  CheckpointPolicy policy_;
  Provenance provenance_;
  bool final_snapshot_;
};

}  // namespace shapepress::scenarios
