#pragma once
// What every resumable stage shares (docs/stages.md, "Checkpoints and --resume"): when a
// checkpoint is due (every N steps, every T minutes of wall time, or on SIGINT/SIGTERM), the
// record of how a run was started that `--resume` runs again, the cleanup of the temporaries a
// killed run left; and ResumableRun, the one way a long stage runs with all of these. What a
// checkpoint holds is the stage's, in the one format of common/checkpoint.hpp (simulate/
// checkpoint.hpp pairs it with the engine's snapshot).
#include <chrono>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace shapepress {

// The config keys run.checkpoint_every and run.checkpoint_minutes of a resumable stage.
struct CheckpointPolicy {
  std::int64_t every_steps = 0;  // 0: none by steps
  double minutes = 10.0;         // of wall time; 0: none by time
};

// SIGINT and SIGTERM noted instead of ending the process while a run steps, so that it writes a
// checkpoint and exits with 128 + the signal; a second signal ends it at once. Restores the
// previous handlers when destroyed.
class SignalCheckpoints {
 public:
  SignalCheckpoints();
  SignalCheckpoints(const SignalCheckpoints&) = delete;
  SignalCheckpoints& operator=(const SignalCheckpoints&) = delete;
  ~SignalCheckpoints();
  // The signal received, 0 before one.
  static int received();

 private:
  void (*interrupt_)(int);
  void (*terminate_)(int);
};

// Decides after each step whether a checkpoint is due.
class CheckpointClock {
 public:
  explicit CheckpointClock(CheckpointPolicy policy);
  // A signal was received, `step` is a multiple of every_steps, or `minutes` passed since the
  // last checkpoint (or the start).
  bool due(std::int64_t step) const;
  void taken();

 private:
  CheckpointPolicy policy_;
  std::chrono::steady_clock::time_point last_;
};

// A file besides the config that a resumed run must find unchanged (calibrate's reference).
struct RecordedInput {
  std::string role;  // the option naming it
  std::string file;
  std::string sha256;
};

// How a run was started: what --resume runs again (before the first checkpoint) or continues.
// `arguments` are the stage's own (option name → values, common/command_options.hpp), relative
// paths in them from working_directory.
struct RunInvocation {
  std::string command_line;
  std::filesystem::path working_directory;
  std::string config;  // the config file, whose SHA-256 must not change before a resume
  std::string config_sha256;
  std::map<std::string, std::vector<std::string>> arguments;
  std::vector<RecordedInput> inputs;
};
void write_invocation(const std::filesystem::path& path, const RunInvocation& invocation);
// Reads the record of `run` (the stage's --out) from `path`, makes its working folder current
// and checks that its config is unchanged. InputError naming `run` when there is nothing to
// resume, the folder is gone, or the config changed.
RunInvocation resume_invocation(const std::filesystem::path& path, const std::string& run);

// --resume OUT of a run killed between its last output and its exit: the run is whole (its
// run.json, `run_metadata` here, is written and the checkpoint folder's resume.json is gone), so
// there is nothing left to resume; logs that for `stage`, removes what a kill during the final
// removal left of `checkpoints` (never an output) and returns true.
bool finished_before_resume(std::string_view stage, const std::string& run,
                            const std::filesystem::path& checkpoints,
                            const std::filesystem::path& run_metadata);

// The checkpoint folder of a run: when the run ends by an exception (bad input found while
// reading, a divergence) before its first checkpoint record, the folder goes with it, so that a
// failed run leaves no file behind; with a record it stays for --resume.
class CheckpointFolderGuard {
 public:
  explicit CheckpointFolderGuard(std::filesystem::path folder);
  CheckpointFolderGuard(const CheckpointFolderGuard&) = delete;
  CheckpointFolderGuard& operator=(const CheckpointFolderGuard&) = delete;
  ~CheckpointFolderGuard();

 private:
  std::filesystem::path folder_;
  int exceptions_;
};

// What every resumable stage (pack, compact, plate, generate) does around its stepping loop, in
// this order:
//   if (finished_before_resume(...)) return 0;      // --resume of a whole run: exit 0
//   ResumableRun run(stage, out, folder, policy);
//   run.start(resumed, invocation);                 // once its inputs are accepted
//   ... the loop, after each step: if (!run.after_step(step, write)) break;
//   if (stopped) return run.stopped(step);          // 128 + the signal, after a checkpoint
//   ... the outputs, then run.finish();             // the checkpoints have done their work
// The records it writes are common/checkpoint.hpp's.
class ResumableRun {
 public:
  // `output`: what --resume names (a folder, or pack's file); `folder`: its checkpoints.
  ResumableRun(std::string stage, std::filesystem::path output, std::filesystem::path folder,
               CheckpointPolicy policy);

  // On --resume (`resumed`) the temporaries a killed attempt left in the folder go. A run
  // without a record to continue from (a fresh one, or one killed before its first checkpoint)
  // starts from nothing: the folder is emptied and `invocation` recorded in its resume.json (a
  // fresh start must not be resumed from another run's checkpoints). From here a run that ends
  // by an exception before its first record leaves no folder, and SIGINT and SIGTERM are noted
  // instead of ending the process. Returns whether the folder holds records to continue from.
  bool start(bool resumed, const RunInvocation& invocation);
  // After a step: calls `write` (the stage's checkpoint) when one is due by steps, wall time or
  // a signal; false when a signal was received, so that the loop stops after its checkpoint.
  bool after_step(std::int64_t step, const std::function<void()>& write);
  // The exit of a run stopped by a signal (after its checkpoint): logs how to continue and
  // returns 128 + the signal (130 for SIGINT, 143 for SIGTERM). `step`: where it stopped.
  int stopped(std::optional<std::int64_t> step = std::nullopt) const;
  // The run is whole, its outputs written: the checkpoint folder goes.
  void finish() const;

  const std::filesystem::path& folder() const { return folder_; }
  // For a stage whose items run side by side, each with a clock of its own (plate's fills).
  const CheckpointPolicy& policy() const { return policy_; }

 private:
  std::string stage_;
  std::filesystem::path output_, folder_;
  CheckpointPolicy policy_;
  CheckpointClock clock_;
  std::optional<CheckpointFolderGuard> guard_;
  std::optional<SignalCheckpoints> signals_;
};

// A double as a hexadecimal float (every bit back): how resume.json records a number option.
std::string exact_text(double value);

// A whole number in [least, most] of a resume record's argument `name` (std::stoi's exceptions
// would end the run as a failed computation): InputError naming `record`, the argument and the
// text when it is not one (a damaged record).
std::int64_t parse_whole(const std::string& token, std::string_view name,
                         const std::filesystem::path& record, std::int64_t least,
                         std::int64_t most);
// The same for an unsigned 64-bit value (a seed).
std::uint64_t parse_unsigned(const std::string& token, std::string_view name,
                             const std::filesystem::path& record);

// Removes the ".name.tmp.PID" files a killed run left in `folder` (common/atomic_file.hpp), only
// those whose name starts with `prefix` when given (a folder other runs write to as well).
void remove_stale_temporaries(const std::filesystem::path& folder, const std::string& prefix = {});

}  // namespace shapepress
