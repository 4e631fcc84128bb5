#include "scenarios/compact_setup.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "common/error.hpp"
#include "packing/bed_state.hpp"
#include "packing/clump_packing.hpp"
#include "packing/pack.hpp"

namespace shapepress::scenarios {
namespace {

double expected_speed(const CompactConfig& c, const SphereState& s) {
  double v =
      std::max({c.setup.program.speed, c.setup.program.unload_speed, c.setup.program.max_speed});
  for (std::size_t i = 0; i < s.size(); ++i)
    v = std::max(v,
                 std::sqrt(s.velocity.x[i] * s.velocity.x[i] + s.velocity.y[i] * s.velocity.y[i] +
                           s.velocity.z[i] * s.velocity.z[i]));
  const std::array<double, 3>& gravity = c.run.engine.gravity;
  const double g = std::hypot(gravity[0], gravity[1], gravity[2]);
  const double fall = std::isnan(c.punch) ? 0.0 : c.punch - c.bottom;
  return std::max(v, std::sqrt(2.0 * std::max(g, c.generate ? 9.81 : 0.0) * fall));
}

// The skin defaults to 0.1 of the smallest diameter.
EngineSettings settings_for(const CompactConfig& c, const SphereState& s, double dt) {
  const double d_min = 2.0 * *std::min_element(s.radius.begin(), s.radius.end());
  EngineSettings settings = c.run.engine_settings(dt, 0.1 * d_min);
  settings.bond_substeps = 1;  // the step chosen says how many (compaction_settings)
  return settings;
}

// The compaction's: with mass scaling s the bed's weight stays the true one (gravity / s), so a run
// at s is the unscaled run at v√s in a time stretched by √s, weight included (models.md, "Quasi-
// static compaction and mass scaling"); at s × g a soft bed sinks under s times its weight.
EngineSettings compaction_settings(const CompactConfig& c, const SphereState& s,
                                   const TimeStepChoice& step) {
  EngineSettings settings = settings_for(c, s, step.time_step);
  settings.bond_substeps = step.bond_substeps;
  for (double& g : settings.gravity)
    g /= c.density_scale;
  return settings;
}

// Plain spheres' volumes plus each clump's union volume (its sub-spheres overlap).
double solid_volume(const SphereState& s, const ClumpSet& clumps) {
  double volume = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (clumps.clump_of.empty() || clumps.clump_of[i] < 0)
      volume += s.radius[i] * s.radius[i] * s.radius[i];
  volume *= 4.0 / 3.0 * std::numbers::pi;
  for (double v : clumps.volume)
    volume += v;
  return volume;
}

// The particle material's density × run.density_scale (mass scaling).
MaterialConfig scaled_materials(const CompactConfig& c) {
  MaterialConfig m = c.materials;
  if (c.density_scale != 1.0)
    for (Material& material : m.materials)
      if (material.name == c.particle_material) material.density *= c.density_scale;
  return m;
}

// The bed's volumes: of its bodies in the bed (the solid fraction's), of their shapes (meshes)
// and of their sub-spheres; one number for a bed of spheres and clumps.
struct BedVolumes {
  double body = 0.0, shape = 0.0, spheres = 0.0;
  double mean_diameter =
      0.0;  // m, of the bodies' volume-equivalent diameters (the inertial number's)
};

// The volume the bed's solid fraction is stated by (punch.solid_fraction_volume).
double stated_solid_volume(const CompactConfig& c, const BedVolumes& volumes) {
  return c.setup.solid_fraction_volume == packing::SolidVolume::shape ? volumes.shape
                                                                      : volumes.body;
}

// The mean volume-equivalent diameter of the bed's bodies: spheres, and clumps by their volume.
double mean_diameter(const SphereState& s, const ClumpSet& clumps) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (clumps.clump_of.empty() || clumps.clump_of[i] < 0) sum += 2.0 * s.radius[i], ++count;
  for (double v : clumps.volume)
    sum += std::cbrt(6.0 * v / std::numbers::pi), ++count;
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

CompactionSetup compaction_setup(const CompactConfig& c, double reference_gap,
                                 const BedVolumes& volumes, const TimeStepChoice& time_step) {
  CompactionSetup setup = c.setup;
  setup.time_step = time_step;
  setup.solid_volume = stated_solid_volume(c, volumes);
  if (c.target_strain) setup.program.target_gap = reference_gap * (1.0 - *c.target_strain);
  if (c.target_solid_fraction)
    setup.program.target_gap = setup.solid_volume / (c.box_x * c.box_y * *c.target_solid_fraction);
  setup.body_volume = volumes.body;
  setup.shape_volume = volumes.shape;
  setup.sphere_volume = volumes.spheres;
  setup.inertial.diameter = volumes.mean_diameter;
  if (const Material* m = c.materials.find(c.particle_material))
    setup.inertial.density = m->density * c.density_scale;
  // Solid-fraction ceiling: D = V / (A H) reaches it at H = V / (A D_max).
  const double min_gap = setup.solid_volume / (c.box_x * c.box_y * setup.max_solid_fraction);
  setup.program.min_gap = min_gap;
  if (setup.program.target_gap && *setup.program.target_gap < min_gap) {
    setup.ceiling_limits_load = true;
    spdlog::warn(
        "punch: the target gap {:.6g} m (strain {:.4g} from H0 = {:.6g} m) would need solid "
        "fraction {:.3f}, above the ceiling punch.max_solid_fraction = {}: loading stops at gap "
        "{:.6g} m (strain {:.4g})",
        *setup.program.target_gap, 1.0 - *setup.program.target_gap / reference_gap, reference_gap,
        setup.solid_volume / (c.box_x * c.box_y * *setup.program.target_gap),
        setup.max_solid_fraction, min_gap, 1.0 - min_gap / reference_gap);
  }
  setup.die_area = c.box_x * c.box_y;
  if (setup.max_steps == 0 && !setup.program.target_gap &&
      setup.program.mode == PunchProgram::Mode::displacement)
    throw InputError("punch: give target_gap or target_strain, or run.steps to stop the run");
  return setup;
}

// A program with a relaxation starts in it, from the engine's time now.
void start_program(PreparedCompaction& out) {
  if (!(out.setup.program.relax_time > 0.0)) return;
  out.punch.phase = PunchPhase::relax;
  out.punch.phase_start = out.engine->time();
}

// H0 of the strain: the gap when loading starts, or where the bed would be at the reference
// solid fraction (the fill height is the caller's: it needs the pour).
double reference_gap(const CompactConfig& c, double start_gap, double solid_volume) {
  return c.setup.strain_reference == CompactionSetup::StrainReference::solid_fraction
             ? solid_volume / (c.box_x * c.box_y * c.setup.reference_solid_fraction)
             : start_gap;
}

// The [clumps] templates: a templates file's /cms groups (all, or the one named) or the one
// given inline.
std::vector<BodyTemplate> clump_templates(const ClumpsConfig& k) {
  if (!k.templates.empty())
    return k.template_name.empty()
               ? load_body_templates(k.templates, BodyKind::cms)
               : load_body_templates({k.templates}, {TemplateChoice{"cms/" + k.template_name}});
  BodyTemplate t;
  t.name = "clumps.spheres";
  t.kind = BodyKind::cms;
  for (std::size_t i = 0; i + 3 < k.spheres.size(); i += 4) {
    t.centres.push_back({k.spheres[i], k.spheres[i + 1], k.spheres[i + 2]});
    t.radii.push_back(k.spheres[i + 3]);
  }
  return {t};
}

}  // namespace

PreparedCompaction prepare_compaction(const CompactConfig& c, std::optional<SphereList> spheres,
                                      SettleCheckpoints settle_checkpoints) {
  if (std::isnan(c.punch))
    throw InputError(
        "box.punch: required for a bed that is not a packing made by `pack` (it sets where the "
        "punch starts)");
  const MaterialTable table = scaled_materials(c).table();
  const int particle = table.index_of(c.particle_material);
  const int wall = table.index_of(c.wall_material);
  const Box box{c.box_x, c.box_y};
  const bool generated = !spheres;
  if (generated && !c.generate && !c.clumps)
    throw InputError(
        "no packing: pass --packing FILE or add a [generate] (or [clumps]) table to the config");
  Pour request{box, generated ? c.generate : std::nullopt, std::nullopt,
               table.material(particle).density, particle};
  if (c.clumps) {
    ClumpInsertion& clumps = request.clumps.emplace();
    clumps.templates = clump_templates(*c.clumps);
    clumps.count = c.clumps->count;
    clumps.seed = c.clumps->seed;
    clumps.integration_cells = c.clumps->integration_cells;
    clumps.z_low = c.generate ? c.generate->z_low : c.bottom;
    clumps.z_high = c.generate ? c.generate->z_high : c.punch;
  }
  ClumpSet clumps;
  SphereState state = pour(request, spheres ? *spheres : SphereList{}, clumps);
  std::vector<PlaneWall> walls = {PlaneWall{c.bottom, 1, 0.0, wall},
                                  PlaneWall{c.punch, -1, 0.0, wall}};
  PreparedCompaction out;
  const TimeStepChoice step =
      select_time_step(state, table, {wall}, c.run.time_step, c.run.time_step_fraction,
                       expected_speed(c, state), BondSet{}, clumps);
  const double dt = step.time_step;
  if (generated && c.settle_time > 0.0) {
    TimedSettle request{box, walls, settings_for(c, state, dt), c.settle_time, c.settle_friction};
    std::optional<SphereState> settled =
        settle_for_time(std::move(state), clumps, c.materials.materials, c.materials.interactions,
                        request, std::move(settle_checkpoints));
    if (!settled) return {};
    state = std::move(*settled);
    walls[1].position = std::min(c.punch, bed_top(state, c.bottom));
  }
  for (std::size_t i = 0; i < state.size(); ++i)
    if (state.position.z[i] - state.radius[i] < c.bottom - 0.5 * state.radius[i] ||
        state.position.z[i] + state.radius[i] > walls[1].position + 0.5 * state.radius[i])
      throw InputError("packing: sphere " + std::to_string(i) +
                       " lies outside the space between box.bottom and box.punch");
  const EngineSettings settings = compaction_settings(c, state, step);
  out.engine =
      std::make_unique<Engine>(std::move(state), box, table, walls, settings, BondSet{}, clumps);
  // H0: the gap when loading starts, or the loose fill height (the insertion region's top, the
  // paper's "maximum initial height"), which strains like its 57 % need (docs/stages.md, H0).
  const double volume = solid_volume(out.engine->state(), out.engine->clumps());
  out.punch.reference_gap =
      c.setup.strain_reference == CompactionSetup::StrainReference::fill && c.generate
          ? c.generate->z_high - c.generate->z_low
          : reference_gap(c, walls[1].position - walls[0].position, volume);
  out.setup = compaction_setup(
      c, out.punch.reference_gap,
      {volume, volume, volume, mean_diameter(out.engine->state(), out.engine->clumps())}, step);
  start_program(out);
  return out;
}

PreparedCompaction prepare_compaction(const CompactConfig& c, const BodyPacking& packing) {
  if (c.generate || c.clumps)
    throw InputError(
        "packing: a packing made by `pack` is the whole bed; remove [generate] and "
        "[clumps] from the config");
  const auto differs = [](double a, double b) {
    return std::fabs(a - b) > 1e-9 * std::max(std::fabs(a), std::fabs(b)) + 1e-15;
  };
  if (differs(c.box_x, packing.box.length_x) || differs(c.box_y, packing.box.length_y) ||
      differs(c.bottom, packing.floor))
    throw InputError(fmt::format(
        "packing: the box x = {:.6g} m, y = {:.6g} m, bottom = {:.6g} m of the config is not the "
        "packing's ({:.6g}, {:.6g}, floor {:.6g} m): give the packing's die",
        c.box_x, c.box_y, c.bottom, packing.box.length_x, packing.box.length_y, packing.floor));
  double top = packing.floor;
  for (std::size_t i = 0; i < packing.particles.size(); ++i)
    top = std::max(top, packing.particles.z[i] + packing.particles.radius[i]);
  const double punch = std::isnan(c.punch) ? std::max(packing.top, top) : c.punch;
  if (punch < top)
    throw InputError(fmt::format(
        "box.punch = {:.6g} m is below the packing's highest particle top {:.6g} m", punch, top));
  const MaterialTable table = scaled_materials(c).table();
  const int particle = table.index_of(c.particle_material);
  const int wall = table.index_of(c.wall_material);
  BedRequest request;
  request.density = table.material(particle).density;
  request.material = particle;
  request.bond = c.bond;
  Bed bed = bed_from_packing(packing, request);
  std::vector<PlaneWall> walls = {PlaneWall{c.bottom, 1, 0.0, wall},
                                  PlaneWall{punch, -1, 0.0, wall}};
  PreparedCompaction out;
  const TimeStepChoice step =
      select_time_step(bed.state, table, {wall}, c.run.time_step, c.run.time_step_fraction,
                       expected_speed(c, bed.state), bed.bonds, bed.clumps,
                       c.run.engine.bond_substeps, c.run.bond_time_step_fraction, packing.box);
  const EngineSettings settings = compaction_settings(c, bed.state, step);
  out.engine = std::make_unique<Engine>(std::move(bed.state), packing.box, table, walls, settings,
                                        std::move(bed.bonds), std::move(bed.clumps));
  double diameters = 0.0;
  for (const PackedBody& b : packing.bodies)
    diameters += std::cbrt(6.0 * b.shape_volume / std::numbers::pi);
  const BedVolumes volumes{
      bed.body_volume, bed.shape_volume, bed.sphere_volume,
      packing.bodies.empty() ? 0.0 : diameters / static_cast<double>(packing.bodies.size())};
  out.punch.reference_gap = reference_gap(c, punch - c.bottom, stated_solid_volume(c, volumes));
  out.setup = compaction_setup(c, out.punch.reference_gap, volumes, step);
  start_program(out);
  return out;
}

PreparedCompaction resume_compaction(const CompactConfig& c, LoadedSnapshot snapshot) {
  const MaterialTable table = scaled_materials(c).table();
  PreparedCompaction out;
  std::vector<int> wall_materials;
  for (const PlaneWall& w : snapshot.checkpoint.walls)
    wall_materials.push_back(w.material);
  TimeStepChoice step = select_time_step(
      snapshot.state, table, wall_materials, c.run.time_step, c.run.time_step_fraction,
      expected_speed(c, snapshot.state), snapshot.checkpoint.bonds, snapshot.checkpoint.clumps,
      c.run.engine.bond_substeps, c.run.bond_time_step_fraction, snapshot.box);
  // The uninterrupted run's step, where the snapshot keeps it (compaction_scenario_state): the
  // bound just computed reads the bonds' lengths now, not at the start.
  for (const auto& [name, value] : snapshot.scenario) {
    if (name == "time_step_s") step.time_step = value;
    if (name == "rayleigh_time_s") step.rayleigh_time = value;
    if (name == "collision_time_s") step.collision_time = value;
    if (name == "collision_speed_m_per_s") step.collision_speed = value;
    if (name == "bond_period_s") step.bond_period = value;
    if (name == "bond_stability_step_s") step.bond_stability_step = value;
    if (name == "clump_period_s") step.clump_period = value;
    if (name == "bond_substeps") step.bond_substeps = static_cast<int>(value);
  }
  const EngineSettings settings = compaction_settings(c, snapshot.state, step);
  out.engine = std::make_unique<Engine>(std::move(snapshot.state), snapshot.box, table, settings,
                                        std::move(snapshot.checkpoint));
  out.punch = punch_state_from(snapshot.scenario);
  // A bed of bodies keeps its body, shape and sub-sphere volumes in the snapshot
  // (compaction_scenario_state); a bed of spheres and clumps has them in its state. A snapshot
  // from before body volumes has no bed_body_volume: its solid fraction was by shape volume.
  const double own = solid_volume(out.engine->state(), out.engine->clumps());
  BedVolumes volumes{own, own, own, mean_diameter(out.engine->state(), out.engine->clumps())};
  bool body_volume = false;
  for (const auto& [name, value] : snapshot.scenario) {
    if (name == "bed_body_volume") volumes.body = value, body_volume = true;
    if (name == "bed_shape_volume") volumes.shape = value;
    if (name == "bed_sphere_volume") volumes.spheres = value;
    if (name == "bed_mean_diameter") volumes.mean_diameter = value;
  }
  if (!body_volume) volumes.body = volumes.shape;
  out.setup = compaction_setup(c, out.punch.reference_gap, volumes, step);
  return out;
}

}  // namespace shapepress::scenarios
