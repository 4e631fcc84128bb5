#pragma once
#include "common/stage.hpp"

namespace shapepress::analysis {

// shapepress report RUN_DIR... --out REPORT_DIR [--poisson-ratio NU] [--heckel-window LO HI]
//                   [--kawakita-window LO HI]
StageRunner setup_report_cli(CLI::App& app);

}  // namespace shapepress::analysis
