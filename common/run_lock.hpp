#pragma once
// One run at a time in an output: two runs started into the same --out (or a --resume of a run
// still running) would interleave their files and delete each other's checkpoints and
// temporaries. The first to start holds a lock file there; the second is refused (exit 2) with
// the holder named. The lock is flock(2): the kernel drops it when its holder ends, so a crashed
// or killed run never leaves its folder locked (the file it leaves is inert).
#include <filesystem>
#include <string>
#include <string_view>

namespace shapepress {

// What a stage's --out names: a folder the run writes into (compact's run/), or a single file
// (pack's packed.h5, fill's templates.h5), locked by a hidden file beside it.
enum class RunOutput { folder, file };

// The lock file of an output: <folder>/.shapepress.lock, or .<name>.lock beside a file.
std::filesystem::path run_lock_path(const std::filesystem::path& output, RunOutput kind);

class RunFolderLock {
 public:
  // Creates the folder (of a file: its parent) when missing and locks it for this process.
  // InputError naming the output and the holder's pid, host, start time and command when another
  // process holds it, or naming the folder when it cannot be created. `command_line` is written
  // into the lock file for the next one to read.
  RunFolderLock(const std::filesystem::path& output, RunOutput kind, std::string_view command_line);
  RunFolderLock(const RunFolderLock&) = delete;
  RunFolderLock& operator=(const RunFolderLock&) = delete;
  // Removes the lock file, and the folders the lock created when the run left them empty (a run
  // refused for bad input leaves nothing behind).
  ~RunFolderLock();

 private:
  std::filesystem::path lock_;
  std::filesystem::path folder_;
  std::filesystem::path created_;  // the outermost folder this lock created; empty: none
  int descriptor_ = -1;
};

}  // namespace shapepress
