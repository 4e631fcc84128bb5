#pragma once
// Running another program as a child process: the finite element solver and the mesher of
// fem-plate, and the shapepress processes `advise` runs its ladder with. One place starts a child
// (posix_spawn: safe from a multi-threaded parent), waits for it through the signals a run notes
// for its checkpoints (every wait is retried on EINTR, or the child would be left a zombie and
// its output lost), and words its failures, naming the program and how it ended.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace shapepress {

struct ChildCommand {
  std::vector<std::string> arguments;    // arguments[0]: the program, looked up on PATH
  std::string role;                      // what errors call it: "the mesher"
  std::string install_hint;              // said when the program is not found
  std::filesystem::path folder;          // the child's working folder; empty: ours
  std::vector<std::string> environment;  // "NAME=value", set over our environment
  std::filesystem::path log;             // the child's stdout and stderr
};

struct ChildEnd {
  int exit_code = 0;         // the child's exit status, or 128 + the signal that ended it
  int signal = 0;            // the signal that ended it, 0 when it exited
  double cpu_seconds = 0.0;  // user + system CPU of the child and its threads
  double wall_seconds = 0.0;
  // "exit status 3" or "signal 9 (Killed)".
  std::string how() const;
};

// A line the child printed, as it prints it, with the child's pid (its CPU time so far is in
// /proc) and the wall time since the start.
using ChildLine = std::function<void(const std::string& line, int pid, double wall_seconds)>;

// Runs `command` to its end. With `on_line`, the output is read line by line as the child prints
// it (and copied into the log); without, it goes straight to the log. InputError naming the role
// and the program when it cannot be started (with the install hint when it is not found);
// ComputationError when the child cannot be waited for.
ChildEnd run_child(const ChildCommand& command, const ChildLine& on_line = {});

}  // namespace shapepress
