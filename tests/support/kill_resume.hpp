#pragma once
// The kill test of `--resume` (docs/stages.md, "Checkpoints and --resume"): a run killed with
// SIGKILL at seeded points and resumed each time, as a batch job killed by its node would be.
#include <chrono>
#include <cstdio>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include "tests/support/command.hpp"

namespace shapepress::testing {

struct KilledRuns {
  // Per attempt, the step its run resumed from ("start": none, it began again).
  std::vector<std::string> resumed_from;
  bool finished = false;  // the last resume ended the run (exit 0)
  std::string output;     // of the last command
};

// Seconds the command took, running it once to the end.
inline double timed_run(const std::string& arguments, CommandResult& result) {
  const auto t0 = std::chrono::steady_clock::now();
  result = run_shapepress(arguments);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Runs shapepress `arguments` in the background and sends it SIGTERM once a file matches the
// shell pattern `ready` (already quoted where it needs to be), or when the run has ended: the
// run's exit code and output. Polled every `poll` (a `sleep` argument, seconds).
// (Appended piece by piece: GCC 12 at -O3 warns falsely (-Wrestrict) on one long sum.)
inline CommandResult terminate_when(const std::string& arguments, const std::string& ready,
                                    const std::string& poll) {
  std::string command = "(";
  command += SHAPEPRESS_BINARY;
  command += " ";
  command += arguments;
  command += " & pid=$!; while ! ls ";
  command += ready;
  command += " >/dev/null 2>&1 && kill -0 $pid 2>/dev/null; do sleep ";
  command += poll;
  command += "; done; kill -TERM $pid; wait $pid)";
  return run_command(command);
}

// Starts `start` (shapepress arguments) and kills it with SIGKILL after a seeded fraction (0.4 to
// 0.9) of `seconds` (the uninterrupted run's wall time) times `first_share`, then `resume`
// likewise times `resumed_share` (a resumed attempt skips the set-up before its checkpoint),
// three kills in all, then runs `resume` to the end. The shares keep the kills inside the run
// on a machine whose load varies. With `ready` (a shell pattern, quoted where it needs to be)
// each attempt's time to its kill counts from when a file matches it (a checkpoint), so that a
// set-up slowed by the machine's load cannot take every kill.
inline KilledRuns kill_three_times_and_resume(const std::string& start, const std::string& resume,
                                              double seconds, double first_share,
                                              double resumed_share, unsigned seed,
                                              const std::string& ready = {}) {
  KilledRuns runs;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> fraction(0.4, 0.9);
  const std::regex resumed(R"(checkpoint at step (\d+))");
  const auto from = [&](const std::string& output) {
    std::smatch step;
    return std::regex_search(output, step, resumed) ? step[1].str() : std::string("start");
  };
  for (int attempt = 0; attempt < 3 && !runs.finished; ++attempt) {
    const double kill_after =
        fraction(random) * seconds * (attempt == 0 ? first_share : resumed_share);
    std::string command;
    if (ready.empty()) {
      command = "timeout -s KILL ";
      command += std::to_string(kill_after);
      command += " ";
      command += SHAPEPRESS_BINARY;
      command += " ";
      command += attempt == 0 ? start : resume;
    } else {
      command = "(";
      command += SHAPEPRESS_BINARY;
      command += " ";
      command += attempt == 0 ? start : resume;
      command += " & pid=$!; while ! ls ";
      command += ready;
      command += " >/dev/null 2>&1 && kill -0 $pid 2>/dev/null; do sleep 0.02; done; sleep ";
      command += std::to_string(kill_after);
      command += "; kill -KILL $pid 2>/dev/null; wait $pid)";
    }
    const CommandResult killed = run_command(command);
    runs.resumed_from.push_back(from(killed.output));
    std::printf("attempt %d: killed after %.2f s of %.2f s (resumed from %s), exit %d\n",
                attempt + 1, kill_after, seconds, runs.resumed_from.back().c_str(),
                killed.exit_code);
    runs.finished = killed.exit_code == 0;  // it outran its kill: nothing left to resume
    runs.output = killed.output;
  }
  if (!runs.finished) {
    const CommandResult last = run_shapepress(resume);
    runs.finished = last.exit_code == 0;
    runs.output = last.output;
    std::printf("last resume: from %s\n", from(last.output).c_str());
  }
  return runs;
}

}  // namespace shapepress::testing
