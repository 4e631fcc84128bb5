#pragma once
#include "common/options.hpp"
#include "common/stage.hpp"

namespace shapepress::packing {

// shapepress pack [TEMPLATES.h5...] --config pack.toml --out packed.h5 [--seed N]
StageRunner setup_pack_cli(CLI::App& app);
// Its config keys (pack_config.hpp), for --help-config and docs/config-reference.md.
StageOptions pack_options();
// Its command-line options (docs/stages.md).
CommandOptions pack_command_options();

}  // namespace shapepress::packing
