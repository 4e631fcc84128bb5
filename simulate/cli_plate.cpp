#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>

#include "common/config.hpp"
#include "common/csv.hpp"
#include "simulate/cli.hpp"
#include "simulate/config_io.hpp"
#include "simulate/engine.hpp"
#include "simulate/timestep.hpp"

namespace shapepress::simulate {
namespace {

struct PlateCli {
  std::string config;
  std::string out;
};

int run(const PlateCli& cli) {
  const ConfigTable root = ConfigTable::load_file(cli.config);
  PlateConfig config = read_plate_config(root);
  root.check_unknown_keys();
  const MaterialTable table = config.materials.table();
  PlateSetup setup = config.setup;
  SphereState probe;
  probe.add_sphere(0, 0, 0, setup.radius, table.material(setup.sphere_material).density,
                   setup.sphere_material);
  const TimeStepChoice dt =
      select_time_step(probe, table, {setup.plate_material}, config.run.time_step,
                       config.run.time_step_fraction, setup.speed);
  setup.time_step = dt.time_step;
  spdlog::info("plate: time step {:.3g} s ({:.3g} of the Rayleigh time)", dt.time_step,
               dt.time_step / dt.rayleigh_time);
  const std::vector<PlateRow> rows = run_plate(table, setup);
  const std::filesystem::path out(cli.out);
  std::filesystem::create_directories(out);
  CsvWriter csv(out / "force.csv", {"time_s", "deformation", "approach_m", "top_force_N",
                                    "bottom_force_N", "hertz_force_N"});
  csv.comment("shapepress plate: one sphere between two plates, top plate at constant speed");
  csv.comment("hertz_force_N = (sqrt(2)/3) E* sqrt(R) approach^1.5 (models.md), E* sphere-plate");
  for (const PlateRow& r : rows)
    csv.row({r.time, r.deformation, r.approach, r.top_force, r.bottom_force, r.hertz_force});
  csv.commit();
  spdlog::info("plate: {} rows in {}", rows.size(), (out / "force.csv").string());
  return 0;
}

}  // namespace

StageRunner setup_plate_cli(CLI::App& app) {
  auto cli = std::make_shared<PlateCli>();
  app.add_option("--config", cli->config, "plate config TOML (materials, sphere, plate)")
      ->required();
  app.add_option("--out", cli->out, "output folder (force.csv)")->required();
  return [cli](const RunContext&) { return run(*cli); };
}

}  // namespace shapepress::simulate
