#include <fmt/format.h>
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
  std::string model;  // empty: each interaction's normal_law
};

int run(const PlateCli& cli) {
  const ConfigTable root = ConfigTable::load_file(cli.config);
  std::optional<NormalLaw> model;  // --model overrides normal_law of every interaction
  if (!cli.model.empty())
    model = cli.model == "multicontact" ? NormalLaw::multicontact : NormalLaw::hertz;
  PlateConfig config = read_plate_config(root, model);
  root.check_unknown_keys();
  const MaterialTable table = config.materials.table();
  const PairConstants& contact =
      table.pair(config.setup.sphere_material, config.setup.plate_material);
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
  csv.comment(contact.normal_law == NormalLaw::multicontact
                  ? fmt::format("normal law: multicontact (Eq. 6), lambda_p = {:.6g}, k1 = {}, "
                                "kc = {:.6g}, F0 = {:.6g} N, beta nu pi = {:.6g}",
                                1.0 / contact.unloading_factor,
                                contact.loading_stiffness > 0.0
                                    ? fmt::format("{:.6g} N/m^1.5", contact.loading_stiffness)
                                    : std::string("4/3 E* sqrt(R*)"),
                                contact.adhesion_stiffness, contact.pull_off_force,
                                contact.multicontact_factor)
                  : std::string("normal law: hertz"));
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
  app.add_option("--model", cli->model,
                 "normal law of every interaction, overriding the config's normal_law "
                 "(multicontact: paper Eq. 6 with the interaction's parameters)")
      ->check(CLI::IsMember({"hertz", "multicontact"}));
  return [cli](const RunContext&) { return run(*cli); };
}

}  // namespace shapepress::simulate
