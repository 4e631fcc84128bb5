#include "app/stages.hpp"

#include <vector>

#include "analysis/cli.hpp"
#include "fem/cli.hpp"
#include "geometry/cli.hpp"
#include "imaging/cli.hpp"
#include "packing/cli.hpp"
#include "scenarios/cli.hpp"

// Each stage library declares its setup function in its cli.hpp.

namespace shapepress {

std::span<const Stage> registered_stages() {
  // One line per stage, in the order of the data walk (docs/architecture.md).
  static const std::vector<Stage> stages = {
      Stage{"shape-stats", "measure particles in images", imaging::setup_shape_stats_cli},
      Stage{"synth-images", "render SEM-like images of known particles",
            imaging::setup_synth_images_cli},
      Stage{"generate", "make 3D particles from shape statistics", geometry::setup_generate_cli,
            geometry::generate_options, RunOutput::folder, geometry::generate_command_options},
      Stage{"describe", "3D descriptors of meshes (L, I, S, sphericity, projected ASR)",
            geometry::setup_describe_cli, nullptr, RunOutput::file},
      Stage{"fill", "fill particle meshes with sub-spheres (BMS, CMS)", geometry::setup_fill_cli,
            nullptr, RunOutput::file},
      Stage{"plate",
            "one particle between two plates (the validation rig): a Hertz sphere, a BMS "
            "agglomerate or a CMS clump",
            scenarios::setup_plate_cli, scenarios::plate_options, RunOutput::folder,
            scenarios::plate_command_options},
      Stage{"fem-plate",
            "one elastic particle (a sphere, a spheroid or a closed mesh) between rigid plates "
            "by FEM (CalculiX)",
            fem::setup_fem_plate_cli, fem::fem_plate_options},
      Stage{"advise",
            "the cheapest sub-sphere count and time step within a tolerance of the finest "
            "(a ladder of plate runs, or of compactions of a bed; the stability map)",
            scenarios::setup_advise_cli},
      Stage{"calibrate",
            "fit contact or bond parameters so a plate or compaction run matches a curve",
            scenarios::setup_calibrate_cli, scenarios::calibrate_options, RunOutput::folder,
            scenarios::calibrate_command_options},
      Stage{"pack", "pack bodies (spheres, BMS, CMS) into a die: settle and pre-compress",
            packing::setup_pack_cli, packing::pack_options, RunOutput::file,
            packing::pack_command_options},
      Stage{"compact",
            "press a bed (pack's bodies, spheres, or poured from the config) with a punch program",
            scenarios::setup_compact_cli, scenarios::compact_options, RunOutput::folder,
            scenarios::compact_command_options},
      Stage{"report", "charts, metrics.json and report.html of compaction and plate runs",
            analysis::setup_report_cli},
      Stage{"help-config", "the config keys of every stage (--markdown: docs/config-reference.md)",
            setup_help_config_cli},
      Stage{"help-options",
            "docs/stages.md with the option tables of the stages that have one, as generated",
            setup_help_options_cli},
  };
  return stages;
}

}  // namespace shapepress
