#include "scenarios/config_io.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "common/error.hpp"
#include "geometry/sphere_fill.hpp"
#include "simulate/contact_law_config.hpp"

namespace shapepress::scenarios {

MaterialConfig read_materials(const ConfigTable& root,
                              const std::optional<std::string>& normal_law) {
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
    if (t.has("effective_modulus"))
      in.effective_modulus =
          t.quantity("effective_modulus", dim::pressure, std::nullopt, Range::positive());
    in.normal_law = read_normal_law(t, "interaction " + in.first + "–" + in.second, normal_law);
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
  run.local_damping = t.number("local_damping", 0.0, Range{0.0, 1.0, true, false});
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
  if (root.has("clumps")) {
    const ConfigTable t = root.table("clumps");
    ClumpsConfig k;
    k.count = t.integer("count", std::nullopt, Range::at_least(1));
    k.seed = static_cast<std::uint64_t>(t.integer("seed", 1, Range::non_negative()));
    k.integration_cells =
        static_cast<int>(t.integer("integration_cells", 128, Range::closed(8, 1024)));
    if (t.has("templates") == t.has("spheres"))
      throw InputError(root.source_name() +
                       ": [clumps] needs templates (a templates file) or spheres (x, y, z, r per "
                       "sub-sphere), one of the two");
    if (t.has("templates")) {
      k.templates = t.string("templates");
      k.template_name = t.string("template", "");
    } else {
      k.spheres = t.numbers("spheres");
      if (k.spheres.empty() || k.spheres.size() % 4 != 0)
        throw InputError(root.source_name() +
                         ": clumps.spheres must hold x, y, z, r (metres) per sub-sphere");
    }
    c.clumps = k;
  }
  return c;
}

PlateConfig read_plate_config(const ConfigTable& root,
                              const std::optional<std::string>& normal_law) {
  PlateConfig c;
  c.materials = read_materials(root, normal_law);
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
  c.setup.ramp = plate.number("ramp", 0.0, Range{0.0, c.setup.max_deformation, true, false});
  c.setup.symmetric = plate.boolean("symmetric", false);
  if (plate.has("final_speed"))
    c.setup.final_speed =
        plate.quantity("final_speed", dim::velocity, std::nullopt, Range::positive());
  c.setup.max_overlap_fraction = c.run.max_overlap_fraction;
  c.setup.local_damping = c.run.local_damping;
  if (root.has("bms")) {
    const ConfigTable t = root.table("bms");
    BmsConfig b;
    b.count = static_cast<int>(t.integer("count", 545, Range::closed(1, 1000000)));
    b.lattice = t.choice("lattice",
                         std::vector<std::string>(std::begin(geometry::lattice_names),
                                                  std::end(geometry::lattice_names)),
                         "fcc");
    b.placement = t.choice("placement", {"inside", "centre"}, "inside");
    b.seed = static_cast<std::uint64_t>(t.integer("seed", 1, Range::non_negative()));
    b.fills = static_cast<int>(t.integer("fills", 1, Range::closed(1, 1000)));
    // m_b <= 1 is refused by create_bonds with the reason; read it unchecked here.
    b.bond_multiplier = t.number("bond_multiplier", 1.15);
    b.material = t.has("material") ? t.string("material") : sphere.string("material");
    table.index_of(b.material);
    const ConfigTable k = root.table("bond");
    BondParameters& p = b.bond;
    // Signs are checked by BondParameters::check() so that every cause reads the same way.
    if (k.has("modulus")) {
      if (k.has("normal_stiffness") || k.has("shear_stiffness"))
        throw InputError(root.source_name() +
                         ": bond: give modulus (with shear_ratio) or normal_stiffness and "
                         "shear_stiffness, not both");
      p.modulus = k.quantity("modulus", dim::pressure);
      p.shear_ratio = k.number("shear_ratio", 1.0);
    } else {
      p.normal_stiffness = k.quantity("normal_stiffness", dim::stiffness_per_area);
      p.shear_stiffness = k.quantity("shear_stiffness", dim::stiffness_per_area);
    }
    p.radius_multiplier = k.number("radius_multiplier", 1.0);
    p.tensile_strength =
        k.quantity("tensile_strength", dim::pressure, std::numeric_limits<double>::infinity());
    p.shear_strength =
        k.quantity("shear_strength", dim::pressure, std::numeric_limits<double>::infinity());
    p.damping_ratio = k.number("damping_ratio", 0.0);
    p.contact_when_bonded = k.boolean("contact_when_bonded", true);
    try {
      p.check();
    } catch (const InputError& e) {
      throw InputError(root.source_name() + ": [bond] " + e.what());
    }
    c.bms = b;
  }
  if (root.has("cms")) {
    const ConfigTable t = root.table("cms");
    CmsConfig m;
    m.count = static_cast<int>(t.integer("count", 150, Range::closed(1, 1000000)));
    m.resolution = static_cast<int>(t.integer("resolution", 64, Range::closed(8, 1024)));
    m.min_radius_fraction = t.number("min_radius_fraction", 0.02, Range{0.0, 1.0, true, false});
    m.match_volume = t.boolean("match_volume", true);
    m.integration_cells =
        static_cast<int>(t.integer("integration_cells", 128, Range::closed(8, 1024)));
    m.material = t.has("material") ? t.string("material") : sphere.string("material");
    table.index_of(m.material);
    c.cms = m;
  }
  return c;
}

std::string plate_config_toml(const PlateConfig& c) {
  std::string out;
  const auto number = [](double v) { return fmt::format("{:.17g}", v); };
  for (const Material& m : c.materials.materials)
    out += fmt::format(
        "[[material]]\nname = \"{}\"\nyoungs_modulus = {}\npoisson_ratio = {}\ndensity = "
        "{}\n\n",
        m.name, number(m.youngs_modulus), number(m.poisson_ratio), number(m.density));
  for (const Interaction& in : c.materials.interactions)
    out += fmt::format(
        "[[interaction]]\nfirst = \"{}\"\nsecond = \"{}\"\nrestitution = {}\n"
        "sliding_friction = {}\nrolling_friction = {}\n{}{}\n",
        in.first, in.second, number(in.restitution), number(in.sliding_friction),
        number(in.rolling_friction),
        in.effective_modulus
            ? fmt::format("effective_modulus = {}\n", number(*in.effective_modulus))
            : std::string(),
        normal_law_toml(in.normal_law));
  const RunConfig& r = c.run;
  out += "[run]\n";
  if (r.time_step) out += fmt::format("time_step = {}\n", number(*r.time_step));
  out += fmt::format("time_step_fraction = {}\nmax_overlap_fraction = {}\nlocal_damping = {}\n\n",
                     number(r.time_step_fraction), number(r.max_overlap_fraction),
                     number(r.local_damping));
  const auto& names = c.materials.materials;
  out += fmt::format("[sphere]\nradius = {}\nmaterial = \"{}\"\n\n", number(c.setup.radius),
                     names[static_cast<std::size_t>(c.setup.sphere_material)].name);
  out += fmt::format(
      "[plate]\nmaterial = \"{}\"\nspeed = {}\nramp = {}\nsymmetric = {}\nmax_deformation = {}\n"
      "records = {}\n",
      names[static_cast<std::size_t>(c.setup.plate_material)].name, number(c.setup.speed),
      number(c.setup.ramp), c.setup.symmetric ? "true" : "false", number(c.setup.max_deformation),
      c.setup.records);
  if (c.setup.final_speed > 0.0)
    out += fmt::format("final_speed = {}\n", number(c.setup.final_speed));
  if (c.cms) {
    const CmsConfig& m = *c.cms;
    out += fmt::format(
        "\n[cms]\ncount = {}\nresolution = {}\nmin_radius_fraction = {}\nmatch_volume = {}\n"
        "integration_cells = {}\nmaterial = \"{}\"\n",
        m.count, m.resolution, number(m.min_radius_fraction), m.match_volume ? "true" : "false",
        m.integration_cells, m.material);
  }
  if (!c.bms) return out;
  const BmsConfig& b = *c.bms;
  out += fmt::format(
      "\n[bms]\ncount = {}\nlattice = \"{}\"\nplacement = \"{}\"\nseed = {}\nfills = {}\n"
      "bond_multiplier = {}\nmaterial = \"{}\"\n\n[bond]\n",
      b.count, b.lattice, b.placement, b.seed, b.fills, number(b.bond_multiplier), b.material);
  const BondParameters& p = b.bond;
  if (p.modulus > 0.0)
    out +=
        fmt::format("modulus = {}\nshear_ratio = {}\n", number(p.modulus), number(p.shear_ratio));
  else
    out += fmt::format("normal_stiffness = {}\nshear_stiffness = {}\n", number(p.normal_stiffness),
                       number(p.shear_stiffness));
  out += fmt::format("radius_multiplier = {}\n", number(p.radius_multiplier));
  if (std::isfinite(p.tensile_strength))
    out += fmt::format("tensile_strength = {}\n", number(p.tensile_strength));
  if (std::isfinite(p.shear_strength))
    out += fmt::format("shear_strength = {}\n", number(p.shear_strength));
  out += fmt::format("damping_ratio = {}\ncontact_when_bonded = {}\n", number(p.damping_ratio),
                     p.contact_when_bonded ? "true" : "false");
  return out;
}

}  // namespace shapepress::scenarios
