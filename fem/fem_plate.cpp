#include "fem/fem_plate.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "analysis/sphere_plates.hpp"
#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "fem/calculix_deck.hpp"
#include "fem/calculix_process.hpp"
#include "fem/quarter_disc_mesh.hpp"

namespace shapepress::fem {

FemPlateRun run_fem_plate(const FemPlateConfig& config, int arc_elements,
                          const std::filesystem::path& folder, const std::string& job,
                          const FemRunOptions& options) {
  FemPlateConfig at_resolution = config;
  at_resolution.arc_elements = arc_elements;
  const QuarterDiscMesh mesh = stretched_to_spheroid(quarter_disc_mesh(config.radius, arc_elements),
                                                     config.pressed_radius());
  FemPlateRun run;
  run.arc_elements = arc_elements;
  run.elements = static_cast<int>(mesh.quads.size());
  run.nodes = static_cast<int>(mesh.nodes.size());
  run.deck = folder / (job + ".inp");
  write_file_atomically(run.deck, plate_deck(mesh, at_resolution));
  // Stale results of an earlier run in the same folder must not pass for this one's.
  std::filesystem::remove(folder / (job + ".dat"));
  if (options.log)
    options.log(
        fmt::format("fem-plate: {} CAX4 elements ({} per 45° of arc), {} nodes, {} "
                    "increments at most: {}",
                    run.elements, arc_elements, run.nodes, config.increments, run.deck.string()));
  const CcxOutcome outcome =
      run_ccx(options.ccx, folder, job, options.threads, [&](const ConvergedIncrement& done) {
        if (options.progress) options.progress(done.step_time);
      });
  run.cpu_seconds = outcome.cpu_seconds;
  run.wall_seconds = outcome.wall_seconds;
  run.completed = outcome.completed();
  if (!run.completed)
    run.failure = !outcome.error.empty()
                      ? outcome.error
                      : fmt::format("CalculiX exited with status {} before the end of the step",
                                    outcome.exit_status);

  const std::vector<NodeSetTotal> totals =
      std::filesystem::exists(folder / (job + ".dat"))
          ? read_total_forces(folder / (job + ".dat"), plate_node_set)
          : std::vector<NodeSetTotal>{};
  // Hertz at the pole: a sphere of the pole's radius of curvature (R itself for a sphere).
  const analysis::ElasticSphere sphere{config.pole_curvature_radius(), config.youngs_modulus,
                                       config.poisson_ratio};
  run.rows.push_back(FemPlateRow{});  // the undeformed state: nothing touches yet
  for (const NodeSetTotal& total : totals) {
    FemPlateRow row;
    row.step_time = total.step_time;
    row.deformation = total.step_time * config.max_deformation;
    row.approach = 2.0 * config.pressed_radius() * row.deformation;
    // The plate is pushed down (−z): its reaction is +z on the plate, i.e. fy > 0 resists;
    // CalculiX prints the reaction the supports exert, which points up at the top plate.
    row.force = std::fabs(total.fy) * axisymmetric_force_factor;
    row.hertz_force = analysis::hertz_plate_force(sphere, row.approach);
    const FemPlateRow& previous = run.rows.back();
    row.work =
        previous.work + 0.5 * (row.force + previous.force) * (row.approach - previous.approach);
    for (const ConvergedIncrement& done : outcome.increments)
      // Both print 7 significant digits (the .dat 0.3333333E+00, the log 3.333333e-01).
      if (std::fabs(done.step_time - total.step_time) < 1e-6 * std::max(1.0, total.step_time)) {
        row.cpu_seconds = done.cpu_seconds;
        row.wall_seconds = done.wall_seconds;
      }
    run.rows.push_back(row);
  }
  if (run.completed && !run.rows.empty()) {
    run.rows.back().cpu_seconds = run.cpu_seconds;
    run.rows.back().wall_seconds = run.wall_seconds;
  }
  return run;
}

double force_at(const FemPlateRun& run, double deformation) {
  const auto& rows = run.rows;
  for (std::size_t i = 1; i < rows.size(); ++i)
    if (deformation <= rows[i].deformation + 1e-12) {
      const FemPlateRow& a = rows[i - 1];
      const FemPlateRow& b = rows[i];
      const double w = (deformation - a.deformation) / (b.deformation - a.deformation);
      return a.force + std::clamp(w, 0.0, 1.0) * (b.force - a.force);
    }
  return std::numeric_limits<double>::quiet_NaN();
}

MeshDifference mesh_difference(const FemPlateRun& coarse, const FemPlateRun& fine, double from,
                               const std::vector<double>& deformations) {
  MeshDifference d;
  const auto relative = [&](double deformation) {
    const double reference = force_at(fine, deformation);
    return (force_at(coarse, deformation) - reference) / reference;
  };
  for (const FemPlateRow& row : coarse.rows) {
    if (row.deformation < from) continue;
    const double r = relative(row.deformation);
    if (std::isfinite(r) && std::fabs(r) > std::fabs(d.max_relative)) {
      d.max_relative = r;
      d.at_deformation_of_max = row.deformation;
    }
  }
  for (double deformation : deformations)
    d.at.emplace_back(deformation, relative(deformation));
  return d;
}

}  // namespace shapepress::fem
