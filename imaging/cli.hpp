#pragma once
#include "common/stage.hpp"

namespace shapepress::imaging {

// shapepress shape-stats IMAGES... --out DIR
StageRunner setup_shape_stats_cli(CLI::App& app);
// shapepress synth-images --out DIR
StageRunner setup_synth_images_cli(CLI::App& app);

}  // namespace shapepress::imaging
