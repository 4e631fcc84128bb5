#pragma once
// What every stage of the `shapepress` binary is (after COLMAP's table of stages):
// a name, a one-line summary, and a function that adds the stage's options to its CLI11
// subcommand and returns the runner that main() calls once the command line is parsed.
#include <functional>
#include <string>
#include <string_view>

#include "common/run_lock.hpp"

namespace CLI {
class App;
}

namespace shapepress {

struct StageOptions;   // common/options.hpp
class CommandOptions;  // common/command_options.hpp

// Global options, parsed by main() before any stage runs.
struct RunContext {
  std::string command_line;  // for provenance
  int threads = 0;           // 0: OpenMP's default (all cores)
  bool quiet = false;
};

// Returns the process exit code (0 ok; a stage may return 2 when, say, some inputs were skipped).
using StageRunner = std::function<int(const RunContext&)>;
using StageSetup = StageRunner (*)(CLI::App& subcommand);

struct Stage {
  std::string_view name;
  std::string_view summary;
  StageSetup setup;
  // The keys of the stage's config file, for `--help-config` and docs/config-reference.md; null
  // for a stage without one.
  StageOptions (*config_options)() = nullptr;
  // What the stage's --out (or --resume) names; main() locks it for the run (common/run_lock.hpp).
  RunOutput output = RunOutput::folder;
  // The stage's command-line options as one table, for docs/stages.md; null for a stage that
  // binds its options to CLI11 directly.
  CommandOptions (*command_options)() = nullptr;
};

}  // namespace shapepress
