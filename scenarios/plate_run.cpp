#include "scenarios/plate_run.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>
#include <omp.h>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/job_pool.hpp"
#include "scenarios/bms_particle.hpp"
#include "scenarios/cms_particle.hpp"
#include "scenarios/plate_checkpoint.hpp"
#include "simulate/contact_law_config.hpp"
#include "simulate/engine.hpp"
#include "simulate/snapshot.hpp"
#include "simulate/timestep.hpp"

namespace shapepress::scenarios {

namespace {

// The clump's contact period bound (timestep.hpp) at the end of the compression, when each plate
// has passed Δ/2 into the clump (it stays centred between them) and touches the most
// sub-spheres, deepest: the stiffest state of the run.
void tighten_for_plates(TimeStepChoice& dt, const PlateParticle& particle,
                        const MaterialTable& table, const PlateSetup& setup,
                        const RunSettings& run) {
  const SphereState& s = particle.spheres;
  const auto [low, high] = vertical_extent(s);
  const double half = 0.5 * setup.max_deformation * 2.0 * setup.radius;
  std::vector<double> overlap(s.size(), 0.0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double top = std::max(0.0, s.position.z[i] + s.radius[i] - (high - half));
    const double bottom = std::max(0.0, low + half - (s.position.z[i] - s.radius[i]));
    // One sub-sphere under both plates: the stiffnesses (∝ √δ) add.
    overlap[i] = std::pow(std::sqrt(top) + std::sqrt(bottom), 2);
  }
  const double period =
      clump_contact_period(particle.clumps, s, table, {setup.plate_material}, overlap);
  dt.clump_period = std::min(dt.clump_period, period);
  if (run.time_step) {
    if (*run.time_step > dt.clump_period / std::numbers::pi)
      throw InputError(fmt::format(
          "time_step {:.3g} s is above the stability limit {:.3g} s of the clump on the plates "
          "at {:.3g} deformation (contact period bound {:.3g} s): lower time_step",
          *run.time_step, dt.clump_period / std::numbers::pi, setup.max_deformation,
          dt.clump_period));
    return;
  }
  dt.time_step = std::min(dt.time_step, run.time_step_fraction * dt.clump_period);
}

}  // namespace

TimeStepChoice plate_time_step(const PlateParticle& particle, const MaterialTable& table,
                               const PlateSetup& setup, const RunSettings& run) {
  // The collision check takes the plates' speed when they first touch (`speed`, or rest with a
  // ramp), not final_speed: what the plates meet later they press at a speed that rises slowly,
  // they do not strike it (the one Hertz sphere, at 0.2 of its Rayleigh time, would be refused:
  // fewer than 10 steps per collision at 1.6 m/s).
  TimeStepChoice dt = select_time_step(
      particle.spheres, table, {setup.plate_material}, run.time_step, run.time_step_fraction,
      setup.speed, particle.bonds, particle.clumps, 1, run.bond_time_step_fraction);
  if (!particle.clumps.empty()) tighten_for_plates(dt, particle, table, setup, run);
  return dt;
}

namespace {

// The fills' mean curve, row by row: every fill records its rows at the same approaches
// (plate.hpp), so row j of each is the same point of the loading to within one step's travel.
// CPU seconds and work counts add up; wall seconds add up over the `threads` that ran the fills
// side by side.
PlateRunOutcome mean_of_fills(std::vector<PlateRunOutcome> fills, int threads) {
  const auto k = static_cast<double>(fills.size());
  double bonds = 0.0, radius = 0.0;
  for (const PlateRunOutcome& fill : fills) {
    bonds += static_cast<double>(fill.bonds) / k;
    radius += fill.sub_sphere_radius / k;
  }
  PlateRunOutcome mean = std::move(fills.front());
  mean.fill_rows.push_back(mean.rows);
  for (std::size_t f = 1; f < fills.size(); ++f)
    mean.fill_rows.push_back(std::move(fills[f].rows));
  mean.bonds = static_cast<std::size_t>(std::llround(bonds));
  mean.sub_sphere_radius = radius;
  for (std::size_t j = 0; j < mean.rows.size(); ++j) {
    PlateRow r;
    double contacts = 0.0, intact = 0.0, square = 0.0;
    r.top_force_min = r.top_force_max = mean.fill_rows[0][j].top_force;
    for (const std::vector<PlateRow>& rows : mean.fill_rows) {
      const PlateRow& q = rows.at(j);
      r.time += q.time / k;
      r.deformation += q.deformation / k;
      r.approach += q.approach / k;
      r.top_force += q.top_force / k;
      r.bottom_force += q.bottom_force / k;
      r.hertz_force += q.hertz_force / k;
      contacts += static_cast<double>(q.contacts) / k;
      intact += static_cast<double>(q.intact_bonds) / k;
      r.kinetic_energy += q.kinetic_energy / k;
      r.work += q.work / k;
      r.cpu_seconds += q.cpu_seconds;  // the ensemble's cost
      r.work_count += q.work_count;
      r.wall_seconds += q.wall_seconds / threads;
      r.top_force_min = std::min(r.top_force_min, q.top_force);
      r.top_force_max = std::max(r.top_force_max, q.top_force);
    }
    for (const std::vector<PlateRow>& rows : mean.fill_rows)
      square += std::pow(rows[j].top_force - r.top_force, 2);
    r.top_force_sd = std::sqrt(square / (k - 1.0));
    r.contacts = std::llround(contacts);
    r.intact_bonds = std::llround(intact);
    mean.rows[j] = r;
  }
  return mean;
}

// [bms] fills > 1: the fills side by side, one thread each; their order in the mean is the
// seeds', so the result does not depend on which thread ran which.
PlateRunOutcome run_one(const PlateConfig& config, PlateParticleKind kind,
                        const std::function<void(const std::string&)>& log, BmsFillCache* cache,
                        const PlateCheckpoints* checkpoints, int fill);

PlateRunOutcome run_fills(const PlateConfig& config,
                          const std::function<void(const std::string&)>& log, BmsFillCache* cache,
                          const PlateCheckpoints* checkpoints) {
  const int count = config.bms->fills;
  std::vector<PlateRunOutcome> fills(static_cast<std::size_t>(count));
  const int threads = std::min(count, omp_get_max_threads());
  run_jobs(fills.size(), threads, [&](std::size_t f) {
    if (threads > 1) omp_set_num_threads(1);  // each fill's engine on one thread: the same bits
    PlateConfig one = config;
    one.bms->fills = 1;
    one.bms->seed = config.bms->seed + f;
    fills[f] = run_one(one, PlateParticleKind::bms, log, cache, checkpoints, static_cast<int>(f));
  });
  for (const PlateRunOutcome& fill : fills)
    if (fill.interrupted) return fill;
  PlateRunOutcome mean = mean_of_fills(std::move(fills), threads);
  mean.description = fmt::format(
      "BMS sphere R = {:.6g} m, {} sub-spheres of r = {:.6g} m and {} bonds on average; mean of {} "
      "fills, seeds {} to {}",
      config.setup.radius, mean.spheres, mean.sub_sphere_radius, mean.bonds, count,
      config.bms->seed, config.bms->seed + static_cast<std::uint64_t>(count) - 1);
  if (log) log("plate: " + mean.description);
  return mean;
}

}  // namespace

const char* particle_name(PlateParticleKind kind) {
  switch (kind) {
    case PlateParticleKind::bms:
      return "bms";
    case PlateParticleKind::cms:
      return "cms";
    default:
      return "sphere";
  }
}

PlateRunOutcome run_plate_config(const PlateConfig& config, PlateParticleKind kind,
                                 const std::function<void(const std::string&)>& log,
                                 BmsFillCache* cache, const PlateCheckpoints* checkpoints) {
  if (kind == PlateParticleKind::bms && config.bms && config.bms->fills > 1)
    return run_fills(config, log, cache, checkpoints);
  return run_one(config, kind, log, cache, checkpoints, 0);
}

namespace {

using RunLog = std::function<void(const std::string&)>;

// A fill that an interrupted run finished (its rows, reused), or that a signal stops before it
// starts (nothing of it to keep); none when the fill is to run.
std::optional<PlateRunOutcome> finished_or_stopped(const PlateCheckpoints* checkpoints, int fill,
                                                   const RunLog& notes) {
  if (!checkpoints) return std::nullopt;
  if (std::optional<PlateRunOutcome> done = checkpoints->finished(fill)) {
    if (notes) notes(fmt::format("plate: fill {} finished before: its rows reused", fill));
    return done;
  }
  if (SignalCheckpoints::received() != 0) {
    PlateRunOutcome stopped;
    stopped.interrupted = true;
    return stopped;
  }
  return std::nullopt;
}

// The CMS sphere: one rigid clump of overlapping sub-spheres. A rigid clump cannot flatten: at
// the end each plate has passed Δ/2 into the clump, deeper into its small outer sub-spheres
// than their radius. That is the method's failure the study shows (paper §3.3), not a
// divergence: the overlap check widens to cover it.
PlateParticle cms_plate_particle(const PlateConfig& config, const MaterialTable& table,
                                 const RunLog& log, PlateRunOutcome& outcome,
                                 double& overlap_fraction) {
  const PlateSetup& setup = config.setup;
  CmsConfig cms = config.cms.value_or(CmsConfig{});
  if (cms.material.empty()) cms.material = table.material(setup.sphere_material).name;
  CmsParticleInfo info;
  PlateParticle particle = cms_sphere(table, setup.radius, cms, "CMS sphere", &info);
  outcome.requested_spheres = static_cast<std::size_t>(cms.count);
  outcome.sub_sphere_radius = info.max_radius;
  outcome.description = fmt::format(
      "CMS sphere R = {:.6g} m, one rigid clump of {} overlapping sub-spheres (asked {}) of r "
      "= {:.6g}…{:.6g} m, union volume {:.6g} m^3 ({:.4g} of the sphere's)",
      setup.radius, info.spheres, cms.count, info.min_radius, info.max_radius, info.volume,
      info.volume / (4.0 / 3.0 * std::numbers::pi * std::pow(setup.radius, 3)));
  if (info.spheres != static_cast<std::size_t>(cms.count) && log)
    log(fmt::format("plate: the CMS filler gave {} sub-spheres for the {} asked", info.spheres,
                    cms.count));
  const double r_min = smallest_radius(particle.spheres);
  const double deepest = 0.5 * setup.max_deformation * 2.0 * setup.radius;
  const double fraction = 1.0 + 2.0 * deepest / r_min;
  if (fraction > overlap_fraction) {
    overlap_fraction = fraction;
    if (log)
      log(
          fmt::format("plate: overlap check widened to {:.3g} sub-sphere radii (the plates "
                      "pass {:.3g} m into a rigid clump whose smallest sub-sphere has r = "
                      "{:.3g} m)",
                      fraction, deepest, r_min));
  }
  return particle;
}

// The BMS sphere (or template): sub-spheres joined by bonds.
PlateParticle bms_plate_particle(const PlateConfig& config, const MaterialTable& table,
                                 BmsFillCache* cache, PlateRunOutcome& outcome) {
  const PlateSetup& setup = config.setup;
  BmsParticleInfo info;
  PlateParticle particle = bms_particle(table, setup.radius, *config.bms,
                                        fmt::format("BMS sphere (seed {})", config.bms->seed),
                                        &info, cache, setup.stack);
  outcome.sub_sphere_radius = info.sub_sphere_radius;
  outcome.description =
      config.bms->templates.empty()
          ? fmt::format("BMS sphere R = {:.6g} m, {} sub-spheres of r = {:.6g} m, {} bonds",
                        setup.radius, info.spheres, info.sub_sphere_radius, info.bonds)
          : fmt::format(
                "BMS template {}{} along its {} axis, height 2R = {:.6g} m, {} "
                "sub-spheres of mean r = {:.6g} m, {} bonds",
                config.bms->templates,
                config.bms->template_name.empty() ? "" : " /bms/" + config.bms->template_name,
                geometry::press_axis_name(config.bms->axis), 2.0 * setup.radius, info.spheres,
                info.sub_sphere_radius, info.bonds);
  return particle;
}

PlateParticle hertz_plate_particle(const PlateConfig& config, const MaterialTable& table,
                                   PlateRunOutcome& outcome) {
  const PlateSetup& setup = config.setup;
  PlateParticle particle;
  particle.spheres.add_sphere(0.0, 0.0, setup.radius, setup.radius,
                              table.material(setup.sphere_material).density, setup.sphere_material);
  particle.spheres = stacked(particle.spheres, setup.stack, setup.radius);
  outcome.description = fmt::format("Hertz sphere R = {:.6g} m", setup.radius);
  return particle;
}

// The step against the bounds that chose it: the Rayleigh time, and the bond period or the
// clump's contact period where one applies.
std::string time_step_note(const TimeStepChoice& dt) {
  return fmt::format(
      "plate: time step {:.3g} s ({:.3g} of the Rayleigh time{})", dt.time_step,
      dt.time_step / dt.rayleigh_time,
      std::isfinite(dt.bond_period)
          ? fmt::format(", {:.3g} of the bond period bound", dt.time_step / dt.bond_period)
      : std::isfinite(dt.clump_period) ? fmt::format(", {:.3g} of the clump's contact period bound",
                                                     dt.time_step / dt.clump_period)
                                       : std::string());
}

// One run, fill `fill` of an ensemble (0 of 1 alone). Every fill logs what it resumes; only the
// first what it presses and with which step (the others' are the same but for the seed).
PlateRunOutcome run_one(const PlateConfig& config, PlateParticleKind kind, const RunLog& notes,
                        BmsFillCache* cache, const PlateCheckpoints* checkpoints, int fill) {
  const RunLog log = fill == 0 ? notes : RunLog{};
  if (std::optional<PlateRunOutcome> ended = finished_or_stopped(checkpoints, fill, notes))
    return std::move(*ended);
  PlateHooks hooks;
  if (checkpoints) {
    hooks = checkpoints->hooks(fill);
    if (hooks.resume && notes)
      notes(fmt::format("plate: fill {} resumes from its checkpoint at step {}", fill,
                        hooks.resume->snapshot.checkpoint.step));
  }
  const MaterialTable table = config.materials.table();
  const PlateSetup& setup = config.setup;
  double overlap_fraction = config.run.engine.max_overlap_fraction;
  PlateRunOutcome outcome;
  if (kind == PlateParticleKind::cms && setup.stack > 1)
    throw InputError(fmt::format(
        "plate.stack = {}: a stack of rigid clumps is not supported (sphere and bms are)",
        setup.stack));
  PlateParticle particle = kind == PlateParticleKind::cms
                               ? cms_plate_particle(config, table, log, outcome, overlap_fraction)
                           : kind == PlateParticleKind::bms
                               ? bms_plate_particle(config, table, cache, outcome)
                               : hertz_plate_particle(config, table, outcome);
  // Per particle: a stack's copies are the same particle.
  outcome.spheres = particle.spheres.size() / static_cast<std::size_t>(setup.stack);
  outcome.bonds = particle.bonds.size() / static_cast<std::size_t>(setup.stack);
  if (setup.stack > 1)
    outcome.description += fmt::format(", {} of them one on another", setup.stack);
  const TimeStepChoice dt = plate_time_step(particle, table, setup, config.run);
  EngineSettings engine =
      config.run.engine_settings(dt.time_step, 0.1 * smallest_radius(particle.spheres));
  engine.max_overlap_fraction = overlap_fraction;
  outcome.time_step = dt.time_step;
  if (log) {
    log("plate: " + outcome.description);
    log(time_step_note(dt));
  }
  int recorded = hooks.resume ? static_cast<int>(hooks.resume->progress.rows.size()) : 0;
  std::int64_t last_step = 0;
  outcome.rows = run_plate(
      table, setup, engine, std::move(particle),
      [&](const PlateRow&, const Engine& e) {
        last_step = e.step_index();
        if (++recorded == setup.total_records())
          outcome.final_snapshot = std::make_shared<Engine>(e);
      },
      std::move(hooks));
  if (outcome.rows.size() < static_cast<std::size_t>(setup.total_records())) {
    outcome.interrupted = true;
    return outcome;
  }
  if (checkpoints) checkpoints->finish(fill, outcome, last_step);
  return outcome;
}

}  // namespace

void write_plate_snapshot(const std::filesystem::path& folder, const PlateRunOutcome& outcome,
                          const Provenance& provenance) {
  if (!outcome.final_snapshot) return;
  const Engine& e = *outcome.final_snapshot;
  write_snapshot(folder / "final.h5", e, ScenarioState{}, provenance);
  write_xdmf(folder / "final.xdmf",
             {{"final.h5", e.time(), e.state().size(), e.walls().size(),
               e.computes_particle_stress(), e.bonds().size(), e.clumps().size()}});
}

void write_force_csv(const std::filesystem::path& path, const PlateRunOutcome& outcome,
                     const PlateConfig& config, PlateParticleKind kind) {
  std::vector<std::string> columns = {"time_s",      "deformation",    "approach_m",
                                      "top_force_N", "bottom_force_N", "hertz_force_N",
                                      "contacts",    "intact_bonds",   "kinetic_energy_J",
                                      "work_J",      "cpu_s",          "wall_s"};
  const bool ensemble = outcome.fills() > 1;
  if (ensemble)
    columns.insert(columns.end(), {"top_force_sd_N", "top_force_min_N", "top_force_max_N"});
  const PlateSetup& setup = config.setup;
  if (setup.unload) columns.push_back("step");
  CsvWriter csv(path, columns);
  csv.comment(fmt::format(
      "shapepress plate: {}; approach speed {:.6g} m/s{}{}{}", outcome.description, setup.speed,
      setup.ramp > 0.0 ? fmt::format(" after a sin^2 ramp over {:.6g} deformation", setup.ramp)
                       : std::string(),
      setup.final_speed > 0.0
          ? fmt::format(", rising linearly to {:.6g} m/s at the end", setup.final_speed)
          : std::string(),
      setup.symmetric ? ", both plates at half of it" : ", top plate only"));
  csv.comment(fmt::format("particle = {}; sub_spheres = {}; bonds = {}; time_step_s = {:.6g}",
                          particle_name(kind), outcome.spheres, outcome.bonds, outcome.time_step));
  if (kind == PlateParticleKind::cms)
    csv.comment(fmt::format(
        "requested_spheres = {}; contacts counts sub-sphere-plate contacts (one rigid clump)",
        outcome.requested_spheres));
  csv.comment(
      "deformation = approach / (2R); approach counted from the first touch of both plates");
  csv.comment("hertz_force_N = (sqrt(2)/3) E* sqrt(R) approach^1.5 (models.md), E* sphere-plate");
  csv.comment("work_J: done by the plates; kinetic_energy_J: of all (sub-)spheres");
  const MaterialTable table = config.materials.table();
  const PairConstants& contact =
      table.pair(config.setup.sphere_material, config.setup.plate_material);
  csv.comment("normal law: " + describe_normal_law(contact));
  if (ensemble)
    csv.comment(fmt::format(
        "fills = {}: every column is the fills' mean (cpu_s their sum, wall_s their sum over "
        "the threads that ran them side by side); "
        "top_force_sd_N is the fills' sample standard deviation, the standard error of the "
        "mean is it / sqrt({})",
        outcome.fills(), outcome.fills()));
  if (setup.unload) {
    const PlateUnloading unloaded = plate_unloading(outcome.rows, setup.records);
    csv.comment(fmt::format(
        "step: 1 loading, 2 unloading (the plates back to where they first touched); peak top "
        "force {:.6g} N, which falls to zero on unloading at deformation {:.6g} (approach {:.6g} "
        "m): the deformation kept",
        unloaded.peak_force, unloaded.residual_deformation, unloaded.residual_approach));
  }
  for (std::size_t k = 0; k < outcome.rows.size(); ++k) {
    const PlateRow& r = outcome.rows[k];
    std::vector<double> cells = {r.time,
                                 r.deformation,
                                 r.approach,
                                 r.top_force,
                                 r.bottom_force,
                                 r.hertz_force,
                                 static_cast<double>(r.contacts),
                                 static_cast<double>(r.intact_bonds),
                                 r.kinetic_energy,
                                 r.work,
                                 r.cpu_seconds,
                                 r.wall_seconds};
    if (ensemble) cells.insert(cells.end(), {r.top_force_sd, r.top_force_min, r.top_force_max});
    if (setup.unload) cells.push_back(k < static_cast<std::size_t>(setup.records) ? 1.0 : 2.0);
    csv.row(cells);
  }
  csv.commit();
}

}  // namespace shapepress::scenarios
