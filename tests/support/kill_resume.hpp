#pragma once
// The kill test of `--resume` (docs/stages.md, "Checkpoints and --resume"): a run killed with
// SIGKILL at checkpoints the test chose and resumed each time, as a batch job killed by its node
// would be.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress::testing {

struct KilledRuns {
  // Per attempt, the step its run resumed from ("start": none, it began again).
  std::vector<std::string> resumed_from;
  bool finished = false;  // the last resume ended the run (exit 0)
  std::string output;     // of the last command
};

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

// Where a run writes its checkpoints and the steps at which the kill test kills it: an attempt
// is killed once a checkpoint of its run at `steps[k]` or later is out, never after a fraction
// of a measured wall time, so that the kills land at the same checkpoints on an idle machine and
// under load (a kill lands within one poll, 20 ms, of the checkpoint: the resumed attempt starts
// from that checkpoint or the next).
struct CheckpointKills {
  std::filesystem::path folder;
  // The start of a checkpoint record's name (an extended regular expression), before its step:
  // "step_" for step_0000001200.json, "fill[0-9]+_" for plate's fill2_0000001000.json.
  std::string prefix;
  std::vector<std::int64_t> steps;  // one kill an attempt, in increasing order
};

// `count` steps spread over (0, `total`): at 1/(count + 1), 2/(count + 1), … of it, each rounded
// down to a multiple of `every` (the run's checkpoint interval) and at least one interval.
inline std::vector<std::int64_t> spread_steps(std::int64_t total, std::int64_t every, int count) {
  std::vector<std::int64_t> steps;
  for (int k = 1; k <= count; ++k)
    steps.push_back(std::max(every, total * k / (count + 1) / every * every));
  return steps;
}

// The shell test "a checkpoint at `step` or later is out" (kills.folder, kills.prefix).
inline std::string checkpoint_reached(const CheckpointKills& kills, std::int64_t step) {
  std::string test = "ls ";
  test += shell_quoted(kills.folder);
  test += " 2>/dev/null | sed -n -E 's/^";
  test += kills.prefix;
  test += "0*([0-9]+)[.]json$/\\1/p' | awk -v t=";
  test += std::to_string(step);
  test += " '$1 + 0 >= t { f = 1 } END { exit !f }'";
  return test;
}

// Starts `start` (shapepress arguments) and kills it with SIGKILL at the first of `kills.steps`,
// then runs `resume` and kills it at the next, and so on, then runs `resume` to the end. An
// attempt that ends before its kill (exit 0) ends the run.
inline KilledRuns kill_at_checkpoints(const std::string& start, const std::string& resume,
                                      const CheckpointKills& kills) {
  KilledRuns runs;
  const std::regex resumed(R"(checkpoint at step (\d+))");
  const auto from = [&](const std::string& output) {
    std::smatch step;
    return std::regex_search(output, step, resumed) ? step[1].str() : std::string("start");
  };
  for (std::size_t attempt = 0; attempt < kills.steps.size() && !runs.finished; ++attempt) {
    std::string command = "(";
    command += SHAPEPRESS_BINARY;
    command += " ";
    command += attempt == 0 ? start : resume;
    command += " & pid=$!; while ! { ";
    command += checkpoint_reached(kills, kills.steps[attempt]);
    command += "; } && kill -0 $pid 2>/dev/null; do sleep 0.02; done; ";
    command += "kill -KILL $pid 2>/dev/null; wait $pid)";
    const CommandResult killed = run_command(command);
    runs.resumed_from.push_back(from(killed.output));
    std::printf("attempt %zu: killed at the checkpoint at step %lld (resumed from %s), exit %d\n",
                attempt + 1, static_cast<long long>(kills.steps[attempt]),
                runs.resumed_from.back().c_str(), killed.exit_code);
    runs.finished = killed.exit_code == 0;  // it ended before its kill: nothing left to resume
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
