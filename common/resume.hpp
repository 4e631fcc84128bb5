#pragma once
// What every resumable stage shares (docs/stages.md, "Checkpoints and --resume"): when a
// checkpoint is due (every N steps, every T minutes of wall time, or on SIGINT/SIGTERM), the
// record of how a run was started that `--resume` runs again, and the cleanup of the temporaries
// a killed run left. What a checkpoint holds is the stage's (simulate/checkpoint.hpp writes the
// engine's half).
#include <chrono>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <map>
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
// run.json, `run_metadata` here, is written and the checkpoints' `resume_record` is gone), so
// there is nothing left to resume; logs that for `stage` and returns true.
bool finished_before_resume(std::string_view stage, const std::string& run,
                            const std::filesystem::path& resume_record,
                            const std::filesystem::path& run_metadata);

// The checkpoint folder of a run: when the run ends by an exception (bad input found while
// reading, a divergence) before its first checkpoint, the folder goes with it, so that a failed
// run leaves no file behind; with a checkpoint it stays for --resume.
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

// A double as a hexadecimal float and back: a checkpoint's text must give back every bit.
std::string exact_text(double value);
// InputError naming `file` when `token` is not a number (a damaged checkpoint).
double parse_exact(const std::string& token, const std::filesystem::path& file);

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
