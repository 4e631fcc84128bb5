#pragma once
// The geometry stages of the `shapepress` binary: generate, describe, fill.
#include "common/options.hpp"
#include "common/stage.hpp"

namespace shapepress::geometry {

StageRunner setup_generate_cli(CLI::App& app);
StageRunner setup_describe_cli(CLI::App& app);
StageRunner setup_fill_cli(CLI::App& app);
// The keys of generate's --targets TOML.
StageOptions generate_options();
// generate's command-line options (docs/stages.md).
CommandOptions generate_command_options();

}  // namespace shapepress::geometry
