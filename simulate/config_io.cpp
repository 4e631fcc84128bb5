#include "simulate/config_io.hpp"

#include <cmath>

#include "common/error.hpp"

namespace shapepress::simulate {

MaterialConfig read_materials(const ConfigTable& root) {
  MaterialConfig out;
  for (const ConfigTable& t : root.tables("material")) {
    Material m;
    m.name = t.string("name");
    m.youngs_modulus = t.quantity("youngs_modulus", dim::pressure, std::nullopt, Range::positive());
    m.poisson_ratio = t.number("poisson_ratio", std::nullopt, Range{-1.0, 0.5, false, false});
    m.density = t.quantity("density", dim::density, 0.0, Range::non_negative());
    out.materials.push_back(m);
  }
  for (const ConfigTable& t : root.tables("interaction")) {
    Interaction in;
    in.first = t.string("first");
    in.second = t.string("second");
    in.restitution = t.number("restitution", std::nullopt, Range::open_closed(0.0, 1.0));
    in.sliding_friction = t.number("sliding_friction", std::nullopt, Range::non_negative());
    in.rolling_friction = t.number("rolling_friction", 0.0, Range::non_negative());
    in.normal_law = t.choice("normal_law", {"hertz", "multicontact"}, "hertz") == "multicontact"
                        ? NormalLaw::multicontact
                        : NormalLaw::hertz;
    // Paper Eq. 6 (models.md); given with normal_law = "hertz" they are an error (materials.cpp).
    const char* keys[] = {"plasticity_ratio", "loading_stiffness", "adhesion_stiffness",
                          "pull_off_force", "multicontact_prefactor"};
    bool any = false;
    for (const char* key : keys)
      any = any || t.has(key);
    if (any || in.normal_law == NormalLaw::multicontact) {
      MulticontactParameters m;
      m.plasticity_ratio = t.number("plasticity_ratio", 1.0, Range::open_closed(0.0, 1.0));
      if (t.has("loading_stiffness"))  // N/m^1.5: no unit suffix (not an integer dimension)
        m.loading_stiffness = t.number("loading_stiffness", std::nullopt, Range::positive());
      m.adhesion_stiffness = t.number("adhesion_stiffness", 0.0, Range::non_negative());
      m.pull_off_force =
          t.quantity("pull_off_force", dim::force, 0.0, Range{-HUGE_VAL, 0.0, true, true});
      m.prefactor = t.number("multicontact_prefactor", 0.0, Range::non_negative());
      in.multicontact = m;
    }
    out.interactions.push_back(in);
  }
  return out;
}

RunConfig read_run(const ConfigTable& root) {
  RunConfig run;
  if (!root.has("run")) return run;
  const ConfigTable t = root.table("run");
  if (t.has("time_step"))
    run.time_step = t.quantity("time_step", dim::time, std::nullopt, Range::positive());
  run.time_step_fraction = t.number("time_step_fraction", 0.2, Range::open_closed(0.0, 1.0));
  run.steps = t.integer("steps", 0, Range::non_negative());
  run.record_every = t.integer("record_every", 100, Range::at_least(1));
  run.snapshot_every = t.integer("snapshot_every", 0, Range::non_negative());
  if (t.has("skin"))
    run.skin = t.quantity("skin", dim::length, std::nullopt, Range::non_negative());
  if (t.has("gravity")) {
    const std::vector<double> g = t.numbers("gravity");
    if (g.size() != 3)
      throw InputError(root.source_name() + ": run.gravity must be [gx, gy, gz] in m/s^2");
    run.gravity = {g[0], g[1], g[2]};
  }
  run.max_overlap_fraction = t.number("max_overlap_fraction", 0.5, Range::open_closed(0.0, 1.0));
  return run;
}

namespace {

PunchProgram read_punch(const ConfigTable& t, std::optional<double>& target_strain) {
  PunchProgram p;
  const std::string mode = t.choice("mode", {"displacement", "servo"}, "displacement");
  p.hold_time = t.quantity("hold_time", dim::time, 0.0, Range::non_negative());
  p.unload_speed = t.quantity("unload_speed", dim::velocity, 0.0, Range::non_negative());
  if (mode == "servo") {
    p.mode = PunchProgram::Mode::servo;
    p.target_stress = t.quantity("target_stress", dim::pressure, std::nullopt, Range::positive());
    p.max_speed = t.quantity("max_speed", dim::velocity, std::nullopt, Range::positive());
    return p;
  }
  p.speed = t.quantity("speed", dim::velocity, std::nullopt, Range::positive());
  if (t.has("target_gap") && t.has("target_strain"))
    throw InputError(t.source_name() + ": give punch.target_gap or punch.target_strain, not both");
  if (t.has("target_gap"))
    p.target_gap = t.quantity("target_gap", dim::length, std::nullopt, Range::positive());
  if (t.has("target_strain"))
    target_strain = t.number("target_strain", std::nullopt, Range{0.0, 1.0, false, false});
  return p;
}

}  // namespace

CompactConfig read_compact_config(const ConfigTable& root) {
  CompactConfig c;
  c.materials = read_materials(root);
  c.run = read_run(root);
  const ConfigTable box = root.table("box");
  c.box_x = box.quantity("x", dim::length, std::nullopt, Range::positive());
  c.box_y = box.quantity("y", dim::length, std::nullopt, Range::positive());
  c.bottom = box.quantity("bottom", dim::length, 0.0);
  c.punch = box.quantity("punch", dim::length);
  if (!(c.punch > c.bottom))
    throw InputError(root.source_name() + ": box.punch must be above box.bottom");
  c.particle_material = root.table("particles").string("material");
  c.wall_material = root.table("walls").string("material");
  const ConfigTable punch = root.table("punch");
  c.program = read_punch(punch, c.target_strain);
  c.strain_from_fill = punch.choice("strain_reference", {"start", "fill"}, "start") == "fill";
  c.max_solid_fraction = punch.number("max_solid_fraction", 0.95, Range{0.0, 1.0, false, false});
  if (c.strain_from_fill && !root.has("generate"))
    throw InputError(root.source_name() +
                     ": punch.strain_reference = \"fill\" needs a [generate] table (the loose "
                     "fill height is generate.height)");
  if (root.has("generate")) {
    const ConfigTable g = root.table("generate");
    InsertionRequest r;
    r.count = g.integer("count", std::nullopt, Range::at_least(1));
    r.diameter_min = g.quantity("diameter_min", dim::length, std::nullopt, Range::positive());
    r.diameter_max = g.quantity("diameter_max", dim::length, r.diameter_min, Range::positive());
    if (g.has("size_quantiles")) {
      SizeQuantiles q;
      q.diameters = g.quantities("size_quantiles", dim::length, Range::positive());
      q.levels = g.numbers("size_quantile_levels", Range{0.0, 1.0, false, false});
      q.volume_weighted = g.choice("size_weighting", {"volume", "number"}, "volume") == "volume";
      try {
        q.check();
        size_table(q, r.diameter_min, r.diameter_max);
      } catch (const InputError& e) {
        throw InputError(root.source_name() + ": [generate] " + e.what());
      }
      r.sizes = q;
    }
    r.seed = static_cast<std::uint64_t>(g.integer("seed", 1, Range::non_negative()));
    r.z_low = c.bottom;
    const double height = g.quantity("height", dim::length, c.punch - c.bottom, Range::positive());
    if (height > c.punch - c.bottom)
      throw InputError(root.source_name() + ": generate.height is above box.punch");
    r.z_high = c.bottom + height;
    c.settle_time = g.quantity("settle_time", dim::time, 0.2, Range::non_negative());
    if (g.has("settle_friction"))
      c.settle_friction = g.number("settle_friction", std::nullopt, Range::non_negative());
    c.generate = r;
  }
  return c;
}

PlateConfig read_plate_config(const ConfigTable& root, std::optional<NormalLaw> normal_law) {
  PlateConfig c;
  c.materials = read_materials(root);
  if (normal_law)
    for (Interaction& in : c.materials.interactions)
      in.normal_law = *normal_law;
  c.run = read_run(root);
  const MaterialTable table = c.materials.table();
  const ConfigTable sphere = root.table("sphere");
  c.setup.radius = sphere.quantity("radius", dim::length, std::nullopt, Range::positive());
  c.setup.sphere_material = table.index_of(sphere.string("material"));
  const ConfigTable plate = root.table("plate");
  c.setup.plate_material = table.index_of(plate.string("material"));
  c.setup.speed = plate.quantity("speed", dim::velocity, std::nullopt, Range::positive());
  c.setup.max_deformation = plate.number("max_deformation", 0.01, Range{0.0, 0.5, false, false});
  c.setup.records = static_cast<int>(plate.integer("records", 50, Range::closed(1, 100000)));
  return c;
}

}  // namespace shapepress::simulate
