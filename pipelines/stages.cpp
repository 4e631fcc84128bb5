#include "pipelines/stages.hpp"

#include <vector>

#include "imaging/cli.hpp"
#include "simulate/cli.hpp"

// Each stage library declares its setup function in its cli.hpp.

namespace shapepress {

std::span<const Stage> registered_stages() {
  // One line per stage, in the order of the data walk (DESIGN.md).
  static const std::vector<Stage> stages = {
      Stage{"shape-stats", "measure particles in images", imaging::setup_shape_stats_cli},
      Stage{"synth-images", "render SEM-like images of known particles", imaging::setup_synth_images_cli},
      Stage{"plate", "one sphere between two plates (validation rig)", simulate::setup_plate_cli},
      Stage{"compact", "compact a sphere packing with a punch program", simulate::setup_compact_cli},
  };
  return stages;
}

}  // namespace shapepress
