#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include "common/atomic_file.hpp"
#include "common/config.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/run_metadata.hpp"
#include "fem/cli.hpp"
#include "fem/fem_plate.hpp"
#include "geometry/press_frame.hpp"

namespace shapepress::fem {
namespace {

struct FemPlateCli {
  std::string config;
  std::string out;
  std::string ccx = "ccx";
  std::string gmsh = "gmsh";
  int arc_elements = 0;
  int coarse_arc_elements = -1;
};

// The deformations the run's summary states the force and the mesh difference at.
const std::vector<double> summary_deformations = {0.05, 0.1, 0.2, 0.3, 0.4};
// The mesh difference is taken from here on. Below it the contact radius a = R √(Δ/2R) < 0.22 R
// spans only a few arc elements of the coarse mesh, and each node coming into contact steps the
// force by a few per cent (docs/models.md, "The finite-element reference"): that measures the
// contact's discretisation, which both meshes share, not the curve's convergence.
constexpr double convergence_from = 0.05;

// The columns of `plate`'s force.csv (scenarios/plate_run.hpp), so `report` reads both.
void write_force_csv(const std::filesystem::path& path, const FemPlateRun& run,
                     const FemPlateConfig& config, const PressedParticle* particle) {
  std::vector<std::string> columns = {"time_s",      "deformation",    "approach_m",
                                      "top_force_N", "bottom_force_N", "hertz_force_N",
                                      "contacts",    "intact_bonds",   "kinetic_energy_J",
                                      "work_J",      "cpu_s",          "wall_s"};
  if (config.unload) columns.push_back("step");
  CsvWriter csv(path, columns);
  if (particle == nullptr) {
    csv.comment(fmt::format(
        "shapepress fem-plate: {} sphere R = {:.6g} m, E = {:.6g} Pa, nu = {:.6g} between rigid "
        "plates (friction {:.3g}), CalculiX, {} axisymmetric CAX4 elements ({} per 45 deg of "
        "arc), {}",
        material_model_name(config.material), config.radius, config.youngs_modulus,
        config.poisson_ratio, config.friction, run.elements, run.arc_elements,
        config.nonlinear_geometry ? "nonlinear geometry" : "small-strain geometry"));
    csv.comment("particle = fem; static: time_s is the step's load fraction, kinetic_energy_J 0");
    csv.comment(
        fmt::format("polar radius c = {:.6g} m (the plates' axis); deformation = approach / (2c); "
                    "top_force_N = bottom_force_N (symmetry plane)",
                    config.pressed_radius()));
    csv.comment(
        fmt::format("hertz_force_N = (sqrt(2)/3) E* sqrt(Rp) approach^1.5, E* = E/(1-nu^2), "
                    "Rp = R^2/c = {:.6g} m (the pole's radius of curvature)",
                    config.pole_curvature_radius()));
  } else {
    csv.comment(fmt::format(
        "shapepress fem-plate: {} particle {} (E = {:.6g} Pa, nu = {:.6g}) pressed along its {} "
        "axis between rigid plates (friction {:.3g}), CalculiX, {} C3D10 tetrahedra ({:.4g} m at "
        "the plates), {}",
        material_model_name(config.material), config.mesh, config.youngs_modulus,
        config.poisson_ratio, press_axis_name(config.axis), config.friction, run.elements,
        run.element_size,
        config.nonlinear_geometry ? "nonlinear geometry" : "small-strain geometry"));
    csv.comment("particle = fem; static: time_s is the step's load fraction, kinetic_energy_J 0");
    csv.comment(fmt::format("height along the axis H = {:.6g} m; deformation = approach / H",
                            particle->height()));
    csv.comment(
        "hertz_force_N: Hertz's elliptical contact (Johnson 4.2) at each plate, the principal "
        "curvatures fitted to the surface there, the two contacts in series");
  }
  csv.comment("contacts: plates touching the particle; cpu_s, wall_s: CalculiX's when converged");
  if (config.plastic())
    csv.comment(fmt::format(
        "von Mises plasticity (CalculiX *PLASTIC): yield stress {:.6g} Pa, hardening modulus "
        "{:.6g} Pa (sigma = sigma_y + H eps_p)",
        *config.yield_stress, config.hardening_modulus));
  if (config.unload) {
    const UnloadingResult unloaded = unloading_result(run);
    csv.comment(
        "step: 1 loading (time_s 0 to 1), 2 unloading (time_s 1 to 2: the plates back to where "
        "they first touched)");
    csv.comment(fmt::format(
        "peak force {:.6g} N; the unloading force falls to zero at deformation {:.6g} (approach "
        "{:.6g} m, within the increment {:.3g}): the plastic deformation left",
        unloaded.peak_force, unloaded.residual_deformation, unloaded.residual_approach,
        unloaded.resolution));
  }
  for (const FemPlateRow& r : run.rows) {
    std::vector<double> values = {r.step_time + (r.step - 1),
                                  r.deformation,
                                  r.approach,
                                  r.top_force,
                                  r.bottom_force,
                                  r.hertz_force,
                                  r.force > 0.0 ? 2.0 : 0.0,
                                  0.0,
                                  0.0,
                                  r.work,
                                  r.cpu_seconds,
                                  r.wall_seconds};
    if (config.unload) values.push_back(r.step);
    csv.row(values);
  }
  csv.commit();
}

nlohmann::ordered_json by_deformation(const std::vector<std::pair<double, double>>& values) {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (const auto& [deformation, value] : values)
    out[fmt::format("{:g}", deformation)] =
        std::isfinite(value) ? nlohmann::ordered_json(value) : nlohmann::ordered_json();
  return out;
}

void add_run_facts(RunMetadata& meta, const FemPlateConfig& config, const FemPlateRun& run,
                   const PressedParticle* particle) {
  std::vector<std::pair<double, double>> forces;
  for (double d : summary_deformations)
    forces.emplace_back(d, force_at(run, d));
  double reached = 0.0;  // the loading step's last converged deformation
  for (const FemPlateRow& r : run.rows)
    if (r.step == 1) reached = r.deformation;
  meta.fact("particle_kind", "fem")
      .fact("sub_spheres", 1)  // one continuum body: `report` keeps it out of the BMS N study
      .fact("bonds", 0)
      .fact("fills", 1)
      .fact("model", particle == nullptr ? "axisymmetric" : "solid")
      .fact("radius_m", particle == nullptr ? config.radius : 0.5 * particle->height())
      .fact("polar_radius_m",
            particle == nullptr ? config.pressed_radius() : 0.5 * particle->height())
      .fact("max_deformation", config.max_deformation)
      .fact("material_model", material_model_name(config.material))
      .fact("nonlinear_geometry", config.nonlinear_geometry)
      .fact("friction", config.friction)
      .fact("elements", run.elements)
      .fact("nodes", run.nodes)
      .fact("arc_elements", run.arc_elements)
      .fact("rows", run.rows.size())
      .fact("completed", run.completed)
      .fact("deformation_reached", reached)
      .fact("force_N_at_deformation", by_deformation(forces))
      .fact("cpu_s", run.cpu_seconds)
      .fact("wall_s", run.wall_seconds);
  if (config.plastic())
    meta.fact("yield_stress_Pa", *config.yield_stress)
        .fact("hardening_modulus_Pa", config.hardening_modulus);
  if (config.unload) {
    const UnloadingResult unloaded = unloading_result(run);
    const auto finite_or_null = [](double v) {
      return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
    };
    meta.fact("unload", true)
        .fact("peak_force_N", unloaded.peak_force)
        .fact("residual_deformation", finite_or_null(unloaded.residual_deformation))
        .fact("residual_approach_m", finite_or_null(unloaded.residual_approach))
        .fact("residual_resolution", unloaded.resolution);
  }
  if (particle == nullptr) {
    meta.fact("pole_curvature_radius_m", config.pole_curvature_radius());
    return;
  }
  // The 3-2-1 anchors hold the particle at its centroid: a particle that is not symmetric about
  // its centre plane would move along the axis to balance its two contacts, and the anchors'
  // reaction is the difference of the two plates' forces instead (force_N is their mean).
  double imbalance = 0.0;
  for (const FemPlateRow& r : run.rows)
    if (r.force > 0.0)
      imbalance = std::max(imbalance, std::fabs(r.top_force - r.bottom_force) / r.force);
  const Eigen::Vector3d axis = particle->frame.row(2).transpose();
  meta.fact("mesh", config.mesh)
      .fact("mesh_unit_m", config.mesh_unit)
      .fact("axis", press_axis_name(config.axis))
      .fact("axis_direction", std::vector<double>{axis.x(), axis.y(), axis.z()})
      .fact("centroid_m", std::vector<double>{particle->centroid.x(), particle->centroid.y(),
                                              particle->centroid.z()})
      .fact("height_m", particle->height())
      .fact("volume_m3", particle->volume)
      .fact("element_type", "C3D10")
      .fact("element_size_m", run.element_size)
      .fact("plate_force_imbalance_max", imbalance);
}

int run(const FemPlateCli& cli, const RunContext& context) {
  RunMetadata meta("fem-plate", context.command_line);
  const ConfigTable root = ConfigTable::load_file(cli.config);
  meta.input("config", cli.config);
  FemPlateConfig config = read_fem_plate_config(root);
  root.check_unknown_keys();
  if (cli.arc_elements > 0) config.arc_elements = cli.arc_elements;
  if (cli.coarse_arc_elements >= 0) config.coarse_arc_elements = cli.coarse_arc_elements;
  config.check();
  const std::filesystem::path out(cli.out);
  ensure_output_folder(out);
  write_file_atomically(
      out / "effective.toml",
      fmt::format("# {}\n# the effective config of a fem-plate run\n", context.command_line) +
          fem_plate_config_toml(config));

  std::optional<PressedParticle> particle;
  if (config.solid())
    particle = pressed_particle(config.mesh, config.mesh_unit, config.axis, config.direction);
  const PressedParticle* solid = particle ? &*particle : nullptr;
  const std::string job = solid != nullptr ? "particle" : "sphere";
  const auto press = [&](int arc_elements, const std::string& job) {
    FemRunOptions options;
    options.ccx = cli.ccx;
    options.gmsh = cli.gmsh;
    options.threads = context.threads > 0 ? context.threads : 1;
    options.log = [](const std::string& line) { spdlog::info("{}", line); };
    // One line per converged increment: an increment takes seconds to minutes, so a line each is
    // the progress (ProgressReporter samples its clock every 64 updates, too rarely here).
    int increment = 0;
    options.progress = [&](double total_time) {
      if (context.quiet) return;
      if (total_time > 1.0 + 1e-6)
        spdlog::info(
            "fem-plate {}: increment {} converged, unloaded to deformation {:.4g} from {:.4g}", job,
            ++increment, (2.0 - total_time) * config.max_deformation, config.max_deformation);
      else
        spdlog::info("fem-plate {}: increment {} converged, deformation {:.4g} of {:.4g}", job,
                     ++increment, total_time * config.max_deformation, config.max_deformation);
    };
    return solid != nullptr ? run_solid_fem_plate(config, *solid, arc_elements, out, job, options)
                            : run_fem_plate(config, arc_elements, out, job, options);
  };

  const FemPlateRun fine = press(config.arc_elements, job);
  write_force_csv(out / "force.csv", fine, config, solid);
  meta.output("force.csv").output(job + ".inp").output(job + ".dat").output(job + ".frd");
  if (solid != nullptr) meta.output(job + ".msh");
  add_run_facts(meta, config, fine, solid);
  if (!fine.completed) {
    meta.fact("failure", fine.failure);
    meta.write(out / run_metadata_name);
    throw ComputationError(fmt::format(
        "CalculiX did not converge in increment {} (deformation {:.4g} reached of {:.4g}): {}; "
        "{} keeps the {} converged increment(s) (more fem.increments, a smaller "
        "fem.minimum_increment or a finer mesh may carry it further)",
        fine.rows.size(), fine.rows.back().deformation, config.max_deformation, fine.failure,
        (out / "force.csv").string(), fine.rows.size() - 1));
  }
  spdlog::info("fem-plate: {} elements, {:.3g} s CPU; force {:.4g} N at deformation {:.3g}",
               fine.elements, fine.cpu_seconds, fine.rows.back().force,
               fine.rows.back().deformation);
  if (config.unload) {
    const UnloadingResult unloaded = unloading_result(fine);
    spdlog::info(
        "fem-plate: peak force {:.4g} N; unloaded, the force falls to zero at deformation {:.4g} "
        "(within {:.2g}): the plastic deformation left",
        unloaded.peak_force, unloaded.residual_deformation, unloaded.resolution);
  }

  if (config.coarse_arc_elements > 0) {
    const FemPlateRun coarse = press(config.coarse_arc_elements, job + "-coarse");
    write_force_csv(out / "force_coarse.csv", coarse, config, solid);
    meta.output("force_coarse.csv").output(job + "-coarse.inp");
    if (!coarse.completed)
      throw ComputationError(
          fmt::format("the convergence check's coarse mesh ({} per 45°) stopped at deformation "
                      "{:.4g}: {} (the fine run's force.csv is complete)",
                      coarse.arc_elements, coarse.rows.back().deformation, coarse.failure));
    const MeshDifference d = mesh_difference(coarse, fine, convergence_from, summary_deformations);
    meta.fact("coarse_arc_elements", coarse.arc_elements)
        .fact("coarse_elements", coarse.elements)
        .fact("coarse_cpu_s", coarse.cpu_seconds)
        .fact("mesh_difference_from_deformation", convergence_from)
        .fact("mesh_difference_max", d.max_relative)
        .fact("mesh_difference_max_at_deformation", d.at_deformation_of_max)
        .fact("mesh_difference_at_deformation", by_deformation(d.at));
    spdlog::info(
        "fem-plate: mesh convergence: the {}-element mesh differs from the {}-element one by at "
        "most {:+.3g} % (at deformation {:.3g}, from {:g}); {:.3g} s CPU",
        coarse.elements, fine.elements, 100.0 * d.max_relative, d.at_deformation_of_max,
        convergence_from, coarse.cpu_seconds);
  }
  meta.write(out / run_metadata_name);
  return 0;
}

}  // namespace

StageRunner setup_fem_plate_cli(CLI::App& app) {
  auto cli = std::make_shared<FemPlateCli>();
  app.add_option("--config", cli->config,
                 "fem-plate config TOML ([sphere] or [particle], [plate], [fem])")
      ->required();
  app.add_option("--out", cli->out,
                 "output folder (force.csv, force_coarse.csv, the CalculiX decks and results)")
      ->required();
  app.add_option("--arc-elements", cli->arc_elements,
                 "elements per 45° of the sphere's outline (overrides fem.arc_elements)")
      ->check(CLI::Range(2, 400));
  app.add_option("--coarse-arc-elements", cli->coarse_arc_elements,
                 "the convergence check's coarse mesh (overrides fem.coarse_arc_elements; 0: "
                 "no check)")
      ->check(CLI::Range(0, 400));
  app.add_option("--ccx", cli->ccx, "the CalculiX program (Debian's calculix-ccx)")
      ->capture_default_str();
  app.add_option("--gmsh", cli->gmsh,
                 "the mesher of a [particle]'s volume (Debian's gmsh; run only for [particle])")
      ->capture_default_str();
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::fem
