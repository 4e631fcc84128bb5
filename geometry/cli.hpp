#pragma once
// The geometry stages of the `shapepress` binary: generate, describe, fill.
#include "common/stage.hpp"

namespace shapepress::geometry {

StageRunner setup_generate_cli(CLI::App& app);
StageRunner setup_describe_cli(CLI::App& app);
StageRunner setup_fill_cli(CLI::App& app);

}  // namespace shapepress::geometry
