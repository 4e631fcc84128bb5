#include "fem/fem_plate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "analysis/sphere_plates.hpp"
#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "fem/calculix_deck.hpp"
#include "fem/calculix_process.hpp"
#include "fem/quarter_disc_mesh.hpp"
#include "fem/solid_deck.hpp"
#include "fem/tet_mesh.hpp"

namespace shapepress::fem {

namespace {

// CalculiX on the deck already written to run.deck: the outcome's times and failure into `run`.
CcxOutcome solve(FemPlateRun& run, const std::filesystem::path& folder, const std::string& job,
                 int steps, const FemRunOptions& options) {
  // Stale results of an earlier run in the same folder must not pass for this one's.
  std::filesystem::remove(folder / (job + ".dat"));
  const CcxOutcome outcome =
      run_ccx(options.ccx, folder, job, options.threads, [&](const ConvergedIncrement& done) {
        if (options.progress) options.progress(done.total_time);
      });
  run.cpu_seconds = outcome.cpu_seconds;
  run.wall_seconds = outcome.wall_seconds;
  run.completed = outcome.completed(steps);
  if (!run.completed)
    run.failure = !outcome.error.empty()
                      ? outcome.error
                      : fmt::format("CalculiX exited with status {} before the end of step {}",
                                    outcome.exit_status, steps);
  return outcome;
}

// One row per converged increment from the plates' reactions (`bottom` empty: the symmetric
// model's one plate), from the undeformed state. `height`: the particle's along the plates'
// axis; `force_factor`: the model's share of the whole (axisymmetric: 180); `hertz`: F(Δ).
void add_rows(FemPlateRun& run, const CcxOutcome& outcome, const std::vector<NodeSetTotal>& top,
              const std::vector<NodeSetTotal>& bottom, double max_deformation, double height,
              double force_factor, const std::function<double(double)>& hertz) {
  run.rows.push_back(FemPlateRow{});  // the undeformed state: nothing touches yet
  for (std::size_t i = 0; i < top.size(); ++i) {
    FemPlateRow row;
    // CalculiX prints the total time: the loading step runs from 0 to 1, the unloading step,
    // which takes the plates back linearly, from 1 to 2.
    const double total_time = top[i].step_time;
    row.step = total_time > 1.0 + 1e-6 ? 2 : 1;
    row.step_time = total_time - (row.step - 1);
    row.deformation = (row.step == 1 ? row.step_time : 1.0 - row.step_time) * max_deformation;
    row.approach = height * row.deformation;
    // The reaction of the supports, whichever way z points: the magnitude is the force.
    row.top_force = std::fabs(bottom.empty() ? top[i].fy : top[i].fz) * force_factor;
    row.bottom_force = i < bottom.size() ? std::fabs(bottom[i].fz) * force_factor : row.top_force;
    row.force = 0.5 * (row.top_force + row.bottom_force);
    row.hertz_force = hertz(row.approach);
    const FemPlateRow& previous = run.rows.back();
    row.work =
        previous.work + 0.5 * (row.force + previous.force) * (row.approach - previous.approach);
    for (const ConvergedIncrement& done : outcome.increments)
      // Both print 7 significant digits (the .dat 0.3333333E+00, the log 3.333333e-01).
      if (std::fabs(done.total_time - total_time) < 1e-6 * std::max(1.0, total_time)) {
        row.cpu_seconds = done.cpu_seconds;
        row.wall_seconds = done.wall_seconds;
      }
    run.rows.push_back(row);
  }
  if (run.completed && !run.rows.empty()) {
    run.rows.back().cpu_seconds = run.cpu_seconds;
    run.rows.back().wall_seconds = run.wall_seconds;
  }
}

std::vector<NodeSetTotal> totals_of(const std::filesystem::path& dat, const std::string& set) {
  return std::filesystem::exists(dat) ? read_total_forces(dat, set) : std::vector<NodeSetTotal>{};
}

}  // namespace

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
  if (options.log)
    options.log(
        fmt::format("fem-plate: {} CAX4 elements ({} per 45° of arc), {} nodes, {} "
                    "increments at most: {}",
                    run.elements, arc_elements, run.nodes, config.increments, run.deck.string()));
  const CcxOutcome outcome = solve(run, folder, job, config.unload ? 2 : 1, options);
  // Hertz at the pole: a sphere of the pole's radius of curvature (R itself for a sphere).
  const analysis::ElasticSphere sphere{config.pole_curvature_radius(), config.youngs_modulus,
                                       config.poisson_ratio};
  add_rows(run, outcome, totals_of(folder / (job + ".dat"), plate_node_set), {},
           config.max_deformation, 2.0 * config.pressed_radius(), axisymmetric_force_factor,
           [&](double approach) { return analysis::hertz_plate_force(sphere, approach); });
  return run;
}

double hertz_series_force(double k_top, double k_bottom, double approach) {
  if (approach <= 0.0) return 0.0;
  const double top_share = 1.0 / (1.0 + std::pow(k_top / k_bottom, 2.0 / 3.0));
  return k_top * std::pow(top_share * approach, 1.5);
}

FemPlateRun run_solid_fem_plate(const FemPlateConfig& config, const PressedParticle& particle,
                                int arc_elements, const std::filesystem::path& folder,
                                const std::string& job, const FemRunOptions& options) {
  // The element size where the plates touch: (π/4) R_c / n, n elements per 45° of the smaller
  // principal radius of curvature there (the axisymmetric model's arc element; R_c = R on a
  // sphere), R_c at most H/2 and at least H/10 (an edge or a tip). The fine band reaches past
  // the contact at the end of the step (each plate travels ε H/2) and two elements more; the
  // middle is meshed at up to four times that, at most H/6.
  const double height = particle.height();
  double curvature_radius = 0.5 * height;
  for (bool top : {true, false}) {
    const auto radii = contact_curvature_radii(particle.surface, top, 0.005 * height);
    curvature_radius = std::min(curvature_radius, radii[1]);
  }
  curvature_radius = std::max(curvature_radius, 0.1 * height);
  TetSizes sizes;
  sizes.at_plates = std::numbers::pi / 4.0 * curvature_radius / arc_elements;
  sizes.band = std::max(0.75 * config.max_deformation * height, 2.0 * sizes.at_plates);
  sizes.elsewhere = std::max(sizes.at_plates, std::min(4.0 * sizes.at_plates, height / 6.0));
  // The 3-2-1 anchors: the centroid, and points on the x and y axes half-way to the surface.
  double reach_x = 0.0, reach_y = 0.0;
  for (const geometry::Vec3& v : particle.surface.vertices) {
    if (std::fabs(v.y()) < 0.2 * height && std::fabs(v.z()) < 0.2 * height)
      reach_x = std::max(reach_x, v.x());
    if (std::fabs(v.x()) < 0.2 * height && std::fabs(v.z()) < 0.2 * height)
      reach_y = std::max(reach_y, v.y());
  }
  if (reach_x <= 0.0 || reach_y <= 0.0)
    throw ComputationError(
        "fem-plate: the particle's centroid axes x and y do not leave it near its centre plane "
        "(no anchor for its rigid-body motion)");
  const std::vector<geometry::Vec3> anchors = {geometry::Vec3::Zero(),
                                               geometry::Vec3(0.5 * reach_x, 0.0, 0.0),
                                               geometry::Vec3(0.0, 0.5 * reach_y, 0.0)};
  const double units_per_m = deck_units_per_m(height);
  const TetMesh mesh =
      tetrahedral_mesh(particle.surface, sizes, anchors, folder, job, options.gmsh, units_per_m);
  double lateral = 0.0;
  for (const geometry::Vec3& v : particle.surface.vertices)
    lateral = std::max({lateral, std::fabs(v.x()), std::fabs(v.y())});
  SolidPlates plates;
  plates.units_per_m = units_per_m;
  plates.top = particle.top;
  plates.bottom = particle.bottom;
  // The contact spreads and the particle bulges: twice its own lateral reach and its height.
  plates.half_width = 2.0 * std::max(lateral, 0.5 * height);
  plates.contact_size = sizes.at_plates;

  FemPlateRun run;
  run.arc_elements = arc_elements;
  run.element_size = sizes.at_plates;
  run.elements = static_cast<int>(mesh.elements.size());
  run.nodes = static_cast<int>(mesh.nodes.size());
  run.deck = folder / (job + ".inp");
  write_file_atomically(run.deck, solid_plate_deck(mesh, plates, config));
  if (options.log)
    options.log(fmt::format(
        "fem-plate: {} C3D10 elements ({:.3g} mm at the plates), {} nodes, {} "
        "increments at most: {}",
        run.elements, 1e3 * sizes.at_plates, run.nodes, config.increments, run.deck.string()));
  const CcxOutcome outcome = solve(run, folder, job, config.unload ? 2 : 1, options);
  // Hertz: each contact's principal curvatures from the surface within 0.5 % of the height.
  const double modulus =
      config.youngs_modulus / (1.0 - config.poisson_ratio * config.poisson_ratio);
  const auto stiffness = [&](bool top) {
    const auto r = contact_curvature_radii(particle.surface, top, 0.005 * height);
    return analysis::hertz_elliptic_contact_force(modulus, r[0], r[1], 1.0);
  };
  const double k_top = stiffness(true), k_bottom = stiffness(false);
  const std::filesystem::path dat = folder / (job + ".dat");
  add_rows(run, outcome, totals_of(dat, top_plate_node_set), totals_of(dat, bottom_plate_node_set),
           config.max_deformation, height, deck_force_in_newtons(units_per_m),
           [&](double approach) { return hertz_series_force(k_top, k_bottom, approach); });
  return run;
}

UnloadingResult unloading_result(const FemPlateRun& run) {
  std::vector<double> deformation, approach, force;
  std::size_t first_unloading = run.rows.size();
  for (std::size_t i = 0; i < run.rows.size(); ++i) {
    const FemPlateRow& r = run.rows[i];
    deformation.push_back(r.deformation), approach.push_back(r.approach), force.push_back(r.force);
    if (r.step == 2 && first_unloading == run.rows.size()) first_unloading = i;
  }
  return analysis::unloading_residual(deformation, approach, force, first_unloading);
}

double force_at(const FemPlateRun& run, double deformation) {
  const auto& rows = run.rows;
  for (std::size_t i = 1; i < rows.size() && rows[i].step == 1; ++i)
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
    if (row.step != 1 || row.deformation < from) continue;
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
