#pragma once
#include "common/options.hpp"
#include "common/stage.hpp"

namespace shapepress::fem {

// shapepress fem-plate --config fem.toml --out DIR [--arc-elements N] [--ccx PROGRAM]
StageRunner setup_fem_plate_cli(CLI::App& app);
// Its config keys (fem_plate_config.hpp), for --help-config and docs/config-reference.md.
StageOptions fem_plate_options();

}  // namespace shapepress::fem
