#include "common/logging.hpp"

#include <string>

#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>

#include "common/error.hpp"

namespace shapepress {

void configure_logging(std::string_view level, bool quiet) {
  spdlog::level::level_enum parsed = spdlog::level::from_str(std::string(level));
  if (parsed == spdlog::level::off && level != "off")
    throw InputError(
        fmt::format("--log-level: '{}' is not one of trace, debug, info, warn, "
                    "error, off",
                    level));
  auto logger = spdlog::stderr_color_mt("shapepress");
  logger->set_pattern("[%H:%M:%S] %^%l%$ %v");
  logger->set_level(quiet ? spdlog::level::err : parsed);
  spdlog::set_default_logger(logger);
}

}  // namespace shapepress
