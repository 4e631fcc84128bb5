#pragma once
// Log lines go to stderr through spdlog; results go to files, never to the log.
#include <string_view>

#include <spdlog/spdlog.h>

namespace shapepress {

// `level` is one of trace, debug, info, warn, error, off; `quiet` keeps only errors.
// InputError naming the value if the level is unknown.
void configure_logging(std::string_view level, bool quiet);

}  // namespace shapepress
