#pragma once
// The table of stages the `shapepress` binary offers. A stage is listed only when it is real.
#include <span>

#include "common/stage.hpp"

namespace shapepress {

std::span<const Stage> registered_stages();

}  // namespace shapepress
