#include "pipelines/stages.hpp"

#include <vector>

// Each stage library declares its setup function in its cli.hpp.

namespace shapepress {

std::span<const Stage> registered_stages() {
  // One line per stage, in the order of the data walk (DESIGN.md).
  static const std::vector<Stage> stages = {
  };
  return stages;
}

}  // namespace shapepress
