#pragma once
#include "common/options.hpp"
#include "common/stage.hpp"
#include "scenarios/namespaces.hpp"

namespace shapepress::scenarios {

// shapepress plate --config plate.toml --out DIR
StageRunner setup_plate_cli(CLI::App& app);
// shapepress compact --config compact.toml [--packing FILE | --restart SNAPSHOT] --out DIR
StageRunner setup_compact_cli(CLI::App& app);
// shapepress advise --config plate.toml --counts 100,250,545 [--fractions 0.1,0.2] --out DIR
StageRunner setup_advise_cli(CLI::App& app);
// shapepress calibrate --config plate.toml --reference curve.csv [--fit ...] --out DIR
StageRunner setup_calibrate_cli(CLI::App& app);

// Their config keys (config_io.hpp), for --help-config and docs/config-reference.md.
StageOptions plate_options();
StageOptions calibrate_options();
StageOptions compact_options();
// The command-line options of the resumable ones (docs/stages.md).
CommandOptions plate_command_options();
CommandOptions calibrate_command_options();
CommandOptions compact_command_options();

}  // namespace shapepress::scenarios
