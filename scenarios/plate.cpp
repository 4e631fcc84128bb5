#include "scenarios/plate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <numbers>

#include <omp.h>

#include "common/error.hpp"
#include "simulate/engine.hpp"

namespace shapepress::scenarios {

namespace {

// CPU seconds of the process (all its threads), or, inside a parallel region (plate_run.cpp runs
// the fills of an ensemble side by side, one thread each), of the calling thread alone: there the
// process's clock would count the other fills too.
double cpu_seconds_of_this_run() {
  if (!omp_in_parallel()) return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

double hertz_plate_force(double effective_modulus, double radius, double approach) {
  return std::sqrt(2.0) / 3.0 * effective_modulus * std::sqrt(radius) * approach *
         std::sqrt(approach);
}

double hertz_stack_force(double plate_modulus, double pair_modulus, double radius, int stack,
                         double approach) {
  // δ = c F^{2/3} at each contact, c = (9 / (16 E*² R*))^{1/3}.
  const auto compliance = [](double modulus, double r_star) {
    return std::cbrt(9.0 / (16.0 * modulus * modulus * r_star));
  };
  const double total = 2.0 * compliance(plate_modulus, radius) +
                       (stack - 1) * compliance(pair_modulus, 0.5 * radius);
  const double ratio = std::max(approach, 0.0) / total;
  return ratio * std::sqrt(ratio);
}

double smallest_radius(const SphereState& spheres) {
  double r_min = spheres.radius.empty() ? 0.0 : spheres.radius[0];
  for (double r : spheres.radius)
    r_min = std::min(r_min, r);
  return r_min;
}

std::vector<PlateRow> run_plate(const MaterialTable& materials, const PlateSetup& setup,
                                const EngineSettings& engine) {
  if (!(setup.radius > 0.0)) throw InputError("plate: sphere radius must be > 0");
  PlateParticle particle;
  particle.spheres.add_sphere(0.0, 0.0, setup.radius, setup.radius,
                              materials.material(setup.sphere_material).density,
                              setup.sphere_material);
  particle.spheres = stacked(particle.spheres, setup.stack, setup.radius);
  return run_plate(materials, setup, engine, std::move(particle));
}

VerticalExtent vertical_extent(const SphereState& s) {
  double low = s.position.z[0] - s.radius[0], high = s.position.z[0] + s.radius[0];
  for (std::size_t i = 0; i < s.size(); ++i) {
    low = std::min(low, s.position.z[i] - s.radius[i]);
    high = std::max(high, s.position.z[i] + s.radius[i]);
  }
  return {low, high};
}

SphereState stacked(const SphereState& one, int stack, double body_radius) {
  if (stack <= 1) return one;
  // The lowest offset at which the copy rests on the one below: over every pair of sub-spheres
  // (i of the lower, j of the upper) closer sideways than ri + rj, the rise that makes them just
  // touch. A particle that is not flat at its ends touches its neighbour at one point, as two
  // particles of a bed first do, not across their extreme heights.
  double rise = 0.0;
  for (std::size_t i = 0; i < one.size(); ++i)
    for (std::size_t j = 0; j < one.size(); ++j) {
      const double dx = one.position.x[j] - one.position.x[i];
      const double dy = one.position.y[j] - one.position.y[i];
      const double reach = one.radius[i] + one.radius[j];
      const double sideways = dx * dx + dy * dy;
      if (sideways >= reach * reach) continue;
      rise = std::max(rise,
                      one.position.z[i] - one.position.z[j] + std::sqrt(reach * reach - sideways));
    }
  SphereState out;
  for (int k = 0; k < stack; ++k)
    for (std::size_t i = 0; i < one.size(); ++i) {
      const double volume = 4.0 / 3.0 * std::numbers::pi * std::pow(one.radius[i], 3);
      out.add_sphere(one.position.x[i], one.position.y[i], one.position.z[i] + k * rise,
                     one.radius[i], one.mass[i] / volume, one.material[i]);
      out.body.back() = k;
      out.body_radius.back() = body_radius;
    }
  return out;
}

namespace {

void check_plate_setup(const PlateSetup& setup) {
  if (!(setup.radius > 0.0)) throw InputError("plate: sphere radius must be > 0");
  if (!(setup.speed > 0.0)) throw InputError("plate: speed must be > 0");
  if (!(setup.max_deformation > 0.0 && setup.max_deformation < 0.5))
    throw InputError("plate: max_deformation must be in (0, 0.5)");
  if (setup.records < 1) throw InputError("plate: records must be >= 1");
  if (setup.stack < 1) throw InputError("plate: stack must be >= 1");
  if (!(setup.ramp >= 0.0 && setup.ramp < setup.max_deformation))
    throw InputError("plate: ramp must be in [0, max_deformation)");
}

// The plates' closing speed at time t and approach: a sin² ramp up to setup.speed over the
// first setup.ramp of deformation (it covers approach speed t_ramp / 2, the mean of sin² being
// 1/2), then linear in the deformation to final_speed at max_deformation.
struct PlateSpeed {
  const PlateSetup& setup;
  double diameter = setup.diameter();
  double ramp_time = 2.0 * setup.ramp * setup.diameter() / setup.speed;
  double final_speed = setup.final_speed > 0.0 ? setup.final_speed : setup.speed;

  double operator()(double t, double approach) const {
    if (t < ramp_time) {
      const double s = std::sin(0.5 * std::numbers::pi * t / ramp_time);
      return setup.speed * s * s;
    }
    return after_ramp(approach);
  }
  // Unloading, `t` after the turn: the loading's speed at the same approach, from rest over the
  // same sin² ramp.
  double unloading(double t, double approach) const {
    const double s = t < ramp_time ? std::sin(0.5 * std::numbers::pi * t / ramp_time) : 1.0;
    return s * s * after_ramp(approach);
  }
  double after_ramp(double approach) const {
    const double rise = setup.max_deformation - setup.ramp;
    const double along = rise > 0.0 ? (approach / diameter - setup.ramp) / rise : 0.0;
    return setup.speed + (final_speed - setup.speed) * std::clamp(along, 0.0, 1.0);
  }
};

// A row of the force curve at the engine's state: forces on both plates beside Hertz's at the
// same approach (e_star of sphere and plate), contacts, bonds, energy and work.
PlateRow plate_row(const Engine& engine, const PlateSetup& setup, double approach, double e_star,
                   double pair_modulus) {
  PlateRow r;
  r.time = engine.time();
  r.approach = approach;
  r.deformation = approach / setup.diameter();
  r.top_force = engine.wall_load(1);
  r.bottom_force = engine.wall_load(0);
  r.hertz_force = setup.stack == 1 ? hertz_plate_force(e_star, setup.radius, approach)
                                   : hertz_stack_force(e_star, pair_modulus, setup.radius,
                                                       setup.stack, approach);
  r.contacts = engine.sphere_contacts() + engine.wall_contacts();
  r.intact_bonds = engine.bonds().intact_count();
  r.kinetic_energy = engine.energy().kinetic;
  r.work = engine.work_in();
  return r;
}

}  // namespace

PlateUnloading plate_unloading(const std::vector<PlateRow>& rows, int records) {
  std::vector<double> deformation, approach, force;
  for (const PlateRow& r : rows)
    deformation.push_back(r.deformation), approach.push_back(r.approach),
        force.push_back(r.top_force);
  return analysis::unloading_residual(deformation, approach, force,
                                      static_cast<std::size_t>(records));
}

std::vector<PlateRow> run_plate(const MaterialTable& materials, const PlateSetup& setup,
                                const EngineSettings& engine_settings, PlateParticle particle,
                                const std::function<void(const PlateRow&, const Engine&)>& row,
                                PlateHooks hooks) {
  check_plate_setup(setup);
  SphereState& s = particle.spheres;
  if (s.size() == 0) throw InputError("plate: no sphere to press");
  // Plates touch the particle's lowest and highest points: a BMS agglomerate is a little
  // shorter than the sphere it fills. The approach counts from that first touch; the deformation
  // is the approach over the diameter 2R of the sphere the particle stands for (paper §3.1,
  // δ/2R), so every particle's curve lies on the axis of the Hertz and Tatara curves.
  const auto [low, high] = vertical_extent(s);
  const double gap0 = high - low;
  const PlateSpeed plate_speed{setup};
  const double top_share = setup.symmetric ? 0.5 : 1.0;
  std::vector<PlaneWall> walls = {
      PlaneWall{low, 1, (1.0 - top_share) * plate_speed(0.0, 0.0), setup.plate_material},
      PlaneWall{high, -1, -top_share * plate_speed(0.0, 0.0), setup.plate_material}};
  EngineSettings settings = engine_settings;
  settings.check_every = 1000;
  // A resumed run takes the engine as it was saved; the particle made again gives gap0, where
  // the approach counts from.
  Engine engine = hooks.resume
                      ? Engine(std::move(hooks.resume->snapshot.state), hooks.resume->snapshot.box,
                               materials, settings, std::move(hooks.resume->snapshot.checkpoint))
                      : Engine(std::move(s), Box{}, materials, std::move(walls), settings,
                               std::move(particle.bonds), std::move(particle.clumps));
  const double e_star =
      materials.pair(setup.sphere_material, setup.plate_material).effective_modulus;
  const double pair_modulus =
      materials.pair(setup.sphere_material, setup.sphere_material).effective_modulus;
  const double final_approach = setup.max_deformation * plate_speed.diameter;
  if (final_approach >= 0.9 * gap0)
    throw InputError(
        "plate: max_deformation leaves the plates less than 10 % of the particle's "
        "height apart");
  PlateProgress before;
  if (hooks.resume) before = std::move(hooks.resume->progress);
  std::vector<PlateRow> rows = std::move(before.rows);
  WorkCount work_count = before.work_count;
  const double cpu_start = cpu_seconds_of_this_run() - before.cpu_seconds;
  const auto wall_start = std::chrono::steady_clock::now();
  const auto wall_seconds = [&] {
    return before.wall_seconds +
           std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  const std::function<PlateProgress()> progress = [&] {
    return PlateProgress{rows, cpu_seconds_of_this_run() - cpu_start, wall_seconds(), work_count};
  };
  int next = static_cast<int>(rows.size()) + 1;
  // Of the walls' positions (the first touch: gap0).
  double approach = gap0 - (engine.walls()[1].position - engine.walls()[0].position);
  const int total = setup.total_records();
  while (next <= total) {
    // The speed at the step's midpoint: the wall moves by it over the step. Unloading (rows past
    // `records`) it is negative, from the turn at the loading's last row.
    const double mid = engine.time() + 0.5 * settings.time_step;
    const bool unloading = next > setup.records;
    const double speed =
        unloading ? -plate_speed.unloading(
                        mid - rows[static_cast<std::size_t>(setup.records) - 1].time, approach)
                  : plate_speed(mid, approach);
    engine.walls()[0].velocity = (1.0 - top_share) * speed;
    engine.walls()[1].velocity = -top_share * speed;
    engine.step();
    work_count += step_work(engine);
    approach = gap0 - (engine.walls()[1].position - engine.walls()[0].position);
    const bool due = unloading ? approach <= final_approach * (total - next) / setup.records
                               : approach >= final_approach * next / setup.records;
    if (due) {
      // The engine checks every check_every steps; a coarse step can blow up and fill the rows
      // after with NaN before the next check (a 40-row clump run at 1.0 of the critical step
      // takes ~260 steps). Checked again at every row, a run that diverged stops with its
      // named cause (exit 1) and never writes a non-finite curve.
      engine.check_divergence();
      PlateRow r = plate_row(engine, setup, approach, e_star, pair_modulus);
      r.cpu_seconds = cpu_seconds_of_this_run() - cpu_start;
      r.wall_seconds = wall_seconds();
      r.work_count = work_count;
      if (row) row(r, engine);
      rows.push_back(r);
      ++next;
    }
    if (hooks.after_step && !hooks.after_step(engine, progress)) break;
  }
  return rows;
}

}  // namespace shapepress::scenarios
