#pragma once
// Running CalculiX (`ccx`, Debian's calculix-ccx) as a child process on a deck in a folder, and
// reading what it printed: which increments converged and when, and the totals of *NODE PRINT.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace shapepress::fem {

struct ConvergedIncrement {
  int number = 0;            // CalculiX's increment count, from 1
  double step_time = 0.0;    // in [0, 1]: the fraction of the step's load
  double total_time = 0.0;   // over the steps, each of period 1: step n ends at n
  double cpu_seconds = 0.0;  // the child's user + system CPU when it converged
  double wall_seconds = 0.0;
};

struct CcxOutcome {
  int exit_status = 0;
  std::vector<ConvergedIncrement> increments;
  std::string error;         // the first "*ERROR" line CalculiX printed, empty if none
  double cpu_seconds = 0.0;  // the child's total user + system CPU
  double wall_seconds = 0.0;
  // The end of the last of `steps` steps was reached without an error.
  bool completed(int steps = 1) const;
};

// Runs `program -i job` in `folder` (job.inp there), its output in folder/job.log, OpenMP and
// SPOOLES threads limited to `threads`. `on_increment` sees each converged increment as it
// happens (progress). InputError (exit 2) naming the program when it cannot be started (not
// installed: Debian package calculix-ccx).
CcxOutcome run_ccx(const std::string& program, const std::filesystem::path& folder,
                   const std::string& job, int threads,
                   const std::function<void(const ConvergedIncrement&)>& on_increment = {});

struct NodeSetTotal {
  double step_time = 0.0;  // the total time CalculiX prints: step n of period 1 ends at n
  double fx = 0.0, fy = 0.0, fz = 0.0;
};
// The "total force (fx,fy,fz) for set NAME and time T" blocks of a .dat file, in order.
// InputError naming the file when it cannot be read or a block is malformed.
std::vector<NodeSetTotal> read_total_forces(const std::filesystem::path& dat,
                                            const std::string& set);

}  // namespace shapepress::fem
