#include "simulate/plate_run.hpp"

#include <cmath>

#include <fmt/format.h>

#include "common/csv.hpp"
#include "simulate/bms_particle.hpp"
#include "simulate/engine.hpp"
#include "simulate/timestep.hpp"

namespace shapepress::simulate {

PlateRunOutcome run_plate_config(const PlateConfig& config, bool bonded,
                                 const std::function<void(const std::string&)>& log) {
  const MaterialTable table = config.materials.table();
  PlateSetup setup = config.setup;
  PlateParticle particle;
  PlateRunOutcome outcome;
  if (bonded) {
    BmsParticleInfo info;
    particle = bms_sphere(table, setup.radius, *config.bms, "BMS sphere", &info);
    outcome.sub_sphere_radius = info.sub_sphere_radius;
    outcome.description =
        fmt::format("BMS sphere R = {:.6g} m, {} sub-spheres of r = {:.6g} m, {} bonds",
                    setup.radius, info.spheres, info.sub_sphere_radius, info.bonds);
  } else {
    particle.spheres.add_sphere(0.0, 0.0, setup.radius, setup.radius,
                                table.material(setup.sphere_material).density,
                                setup.sphere_material);
    outcome.description = fmt::format("Hertz sphere R = {:.6g} m", setup.radius);
  }
  outcome.spheres = particle.spheres.size();
  outcome.bonds = particle.bonds.size();
  const TimeStepChoice dt =
      select_time_step(particle.spheres, table, {setup.plate_material}, config.run.time_step,
                       config.run.time_step_fraction, setup.speed, particle.bonds);
  setup.time_step = dt.time_step;
  outcome.time_step = dt.time_step;
  if (log) {
    log("plate: " + outcome.description);
    log(fmt::format("plate: time step {:.3g} s ({:.3g} of the Rayleigh time{})", dt.time_step,
                    dt.time_step / dt.rayleigh_time,
                    std::isfinite(dt.bond_period) ? fmt::format(", {:.3g} of the bond period bound",
                                                                dt.time_step / dt.bond_period)
                                                  : std::string()));
  }
  int recorded = 0;
  outcome.rows =
      run_plate(table, setup, std::move(particle), [&](const PlateRow&, const Engine& engine) {
        if (++recorded == setup.records) outcome.final_snapshot = std::make_shared<Engine>(engine);
      });
  return outcome;
}

void write_force_csv(const std::filesystem::path& path, const PlateRunOutcome& outcome,
                     const PlateConfig& config, bool bonded) {
  CsvWriter csv(path, {"time_s", "deformation", "approach_m", "top_force_N", "bottom_force_N",
                       "hertz_force_N", "contacts", "intact_bonds", "kinetic_energy_J", "work_J",
                       "cpu_s", "wall_s"});
  csv.comment(fmt::format("shapepress plate: {}, top plate at constant speed {:.6g} m/s",
                          outcome.description, config.setup.speed));
  csv.comment(fmt::format("particle = {}; sub_spheres = {}; bonds = {}; time_step_s = {:.6g}",
                          bonded ? "bms" : "sphere", outcome.spheres, outcome.bonds,
                          outcome.time_step));
  csv.comment(
      "deformation = approach / (2R); approach counted from the first touch of both plates");
  csv.comment("hertz_force_N = (sqrt(2)/3) E* sqrt(R) approach^1.5 (models.md), E* sphere-plate");
  csv.comment("work_J: done by the plates; kinetic_energy_J: of all (sub-)spheres");
  const MaterialTable table = config.materials.table();
  const PairConstants& contact =
      table.pair(config.setup.sphere_material, config.setup.plate_material);
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
  for (const PlateRow& r : outcome.rows)
    csv.row({r.time, r.deformation, r.approach, r.top_force, r.bottom_force, r.hertz_force,
             static_cast<double>(r.contacts), static_cast<double>(r.intact_bonds), r.kinetic_energy,
             r.work, r.cpu_seconds, r.wall_seconds});
  csv.commit();
}

}  // namespace shapepress::simulate
