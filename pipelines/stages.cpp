#include "pipelines/stages.hpp"

#include <array>

// Each stage library declares its setup function in its cli.hpp.

namespace shapepress {

std::span<const Stage> registered_stages() {
  static constexpr std::array<Stage, 0> stages = {
  };
  return stages;
}

}  // namespace shapepress
