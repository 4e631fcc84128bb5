#include "scenarios/config_io.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include "scenarios/bms_particle.hpp"

#include <fmt/format.h>

#include "common/error.hpp"
#include "geometry/sphere_fill.hpp"
#include "packing/pack_config.hpp"
#include "simulate/contact_law_config.hpp"

namespace shapepress::scenarios {

namespace {

const OptionTable<Material>& material_table() {
  static const OptionTable<Material> t = [] {
    OptionTable<Material> m("material",
                            "one per material, named for [[interaction]] and the "
                            "particle, wall and plate tables");
    m.string("name", &Material::name, "the name other tables use")
        .required()
        .quantity("youngs_modulus", &Material::youngs_modulus, dim::pressure, Range::positive(),
                  "Young's modulus E")
        .required()
        .number("poisson_ratio", &Material::poisson_ratio, Range{-1.0, 0.5, false, false},
                "Poisson's ratio")
        .required()
        .quantity("density", &Material::density, dim::density, Range::non_negative(),
                  "density (unused for walls and plates)")
        .quantity("loading_modulus", &Material::loading_modulus, dim::pressure, Range::positive(),
                  "E of the multi-contact law's loading branch, k1 = 4/3 E*_L sqrt(R*) per "
                  "contact: a calibrated loading stiffness as the modulus it implies, so every "
                  "size of contact gets its own k1")
        .default_text("youngs_modulus");
    return m;
  }();
  return t;
}

// The plain keys of an [[interaction]]; `normal_law` and each law's keys are the laws' own
// (read_normal_law, normal_law_toml, normal_law_options).
const OptionTable<Interaction>& interaction_table() {
  static const OptionTable<Interaction> t = [] {
    OptionTable<Interaction> i("interaction", "one per pair of materials that touch");
    i.string("first", &Interaction::first, "material name of one side")
        .required()
        .string("second", &Interaction::second, "material name of the other side")
        .required()
        .number("restitution", &Interaction::restitution, Range::open_closed(0.0, 1.0),
                "coefficient of restitution e")
        .required()
        .number("sliding_friction", &Interaction::sliding_friction, Range::non_negative(),
                "sliding friction coefficient")
        .required()
        .number("rolling_friction", &Interaction::rolling_friction, Range::non_negative(),
                "rolling friction coefficient")
        .quantity("effective_modulus", &Interaction::effective_modulus, dim::pressure,
                  Range::positive(),
                  "E* of the pair, replacing the one the materials' E and nu give")
        .default_text("from the materials")
        .choice("contact_radius", &Interaction::body_contact_radius,
                std::vector<std::pair<std::string, bool>>{{"sphere", false}, {"body", true}},
                "R* of a contact between sub-spheres of two different bodies: the sub-spheres' "
                "or the bodies' (volume-equivalent radii)");
    return i;
  }();
  return t;
}

std::string materials_toml(const MaterialConfig& c) {
  std::string out;
  for (const Material& m : c.materials)
    out += "[[material]]\n" + material_table().lines(m) + "\n";
  for (const Interaction& in : c.interactions)
    out +=
        "[[interaction]]\n" + interaction_table().lines(in) + normal_law_toml(in.normal_law) + "\n";
  return out;
}

void add_material_sections(StageOptions& options) {
  options.sections.push_back(material_table().docs());
  options.sections.back().repeated = true;
  options.sections.push_back(interaction_table().docs());
  options.sections.back().repeated = true;
  for (OptionDoc& row : normal_law_options())
    options.sections.back().rows.push_back(std::move(row));
}

}  // namespace

MaterialConfig read_materials(const ConfigTable& root,
                              const std::optional<std::string>& normal_law) {
  MaterialConfig out;
  for (const ConfigTable& t : root.tables("material"))
    out.materials.push_back(material_table().read(t));
  for (const ConfigTable& t : root.tables("interaction")) {
    Interaction in = interaction_table().read(t);
    in.normal_law = read_normal_law(t, "interaction " + in.first + "–" + in.second, normal_law);
    out.interactions.push_back(in);
  }
  return out;
}

EngineSettings RunSettings::engine_settings(double step, double default_skin) const {
  EngineSettings settings = engine;
  settings.time_step = step;
  settings.skin = skin.value_or(default_skin);
  return settings;
}

namespace {

// The [run] keys both engine stages honour. `run` maps the stage's config to its RunSettings.
template <class S, class Run>
void add_run_rows(OptionTable<S>& t, Run run, std::string skin_default) {
  t.quantity(
       "time_step", [run](auto& c) -> auto& { return run(c).time_step; }, dim::time,
       Range::positive(), "fixed time step, refused above the stability limit")
      .default_text("time_step_fraction of the critical step")
      .number(
          "time_step_fraction", [run](auto& c) -> auto& { return run(c).time_step_fraction; },
          Range::open_closed(0.0, 1.0),
          "time step as a fraction of the Rayleigh time (and of the bond and clump period "
          "bounds)")
      .number(
          "bond_time_step_fraction",
          [run](auto& c) -> auto& { return run(c).bond_time_step_fraction; },
          Range::open_closed(0.0, 1.0),
          "the bonds' bound on the step as a fraction of their period bound (Gershgorin's); "
          "a step above the bed's bonds' stability limit (run.json's bond_stability_step_s: 0.9 "
          "of the longest stable step from their top frequency and damping rate, by Lanczos) "
          "is refused; their fastest modes need stability, not resolution")
      .default_text("time_step_fraction")
      .quantity(
          "skin", [run](auto& c) -> auto& { return run(c).skin; }, dim::length,
          Range::non_negative(), "Verlet list skin")
      .default_text(std::move(skin_default))
      .number(
          "max_overlap_fraction",
          [run](auto& c) -> auto& { return run(c).engine.max_overlap_fraction; },
          Range::open_closed(0.0, 1.0),
          "divergence check: an overlap beyond this fraction of a radius stops the run")
      .number(
          "local_damping", [run](auto& c) -> auto& { return run(c).engine.local_damping; },
          Range{0.0, 1.0, true, false},
          "Cundall's local damping alpha on every sphere, for quasi-static loading only "
          "(engine.hpp)");
}

const auto plate_run = [](auto& c) -> auto& {
  return c.run;
};

const OptionTable<PlateConfig>& plate_run_table() {
  static const OptionTable<PlateConfig> t = [] {
    OptionTable<PlateConfig> r("run", "time step and engine settings");
    add_run_rows(r, plate_run, "0.1 x the smallest (sub-)sphere radius");
    r.unused("steps", "plate runs until plate.max_deformation")
        .unused("record_every", "plate records plate.records rows, evenly spaced in approach")
        .unused("snapshot_every", "plate --snapshot writes the state at the last row")
        .unused("gravity", "the plate rig presses its particle without gravity")
        .integer("checkpoint_every", &PlateConfig::checkpoint_every, Range::non_negative(),
                 "steps of a fill between checkpoints for plate --resume (0: by wall time "
                 "only; calibrate resumes by evaluation instead)")
        .number("checkpoint_minutes", &PlateConfig::checkpoint_minutes, Range::non_negative(),
                "minutes of wall time between checkpoints for plate --resume (0: by steps only)");
    return r;
  }();
  return t;
}

const OptionTable<PlateConfig>& sphere_table() {
  static const OptionTable<PlateConfig> t = [] {
    OptionTable<PlateConfig> s("sphere", "the sphere pressed (or filled by --particle bms | cms)");
    s.quantity(
         "radius", [](auto& c) -> auto& { return c.setup.radius; }, dim::length, Range::positive(),
         "radius R (with [bms] templates: not given, half the template's height along its axis)")
        .default_text("required")
        .write_when([](const PlateConfig& c) { return !c.bms || c.bms->templates.empty(); })
        .string("material", &PlateConfig::sphere_material, "its [[material]]")
        .required();
    return s;
  }();
  return t;
}

const OptionTable<PlateConfig>& plate_table() {
  static const OptionTable<PlateConfig> t = [] {
    OptionTable<PlateConfig> p("plate", "the two plates and their approach");
    const auto setup = [](auto& c) -> auto& {
      return c.setup;
    };
    p.string("material", &PlateConfig::plate_material, "the plates' [[material]]")
        .required()
        .quantity(
            "speed", [setup](auto& c) -> auto& { return setup(c).speed; }, dim::velocity,
            Range::positive(), "approach speed of the top plate")
        .required()
        .number(
            "max_deformation", [setup](auto& c) -> auto& { return setup(c).max_deformation; },
            Range{0.0, 0.5, false, false}, "approach / 2R at the end of the run")
        .integer(
            "records", [setup](auto& c) -> auto& { return setup(c).records; },
            Range::closed(1, 100000), "rows of force.csv, evenly spaced in approach")
        .number(
            "ramp", [setup](auto& c) -> auto& { return setup(c).ramp; }, Range::any(),
            "deformation over which the top plate speeds up from rest (sin^2)")
        .range_from(
            [](const PlateConfig& c) {
              return Range{0.0, c.setup.max_deformation, true, false};
            },
            "in [0, max_deformation)")
        .boolean(
            "symmetric", [setup](auto& c) -> auto& { return setup(c).symmetric; },
            "both plates approach, each at half the speed")
        .quantity(
            "final_speed", [setup](auto& c) -> auto& { return setup(c).final_speed; },
            dim::velocity, Range::positive(),
            "speed at max_deformation, reached linearly in deformation after the ramp")
        .default_text("speed")
        .write_when([](const PlateConfig& c) { return c.setup.final_speed > 0.0; })
        .boolean(
            "unload", [setup](auto& c) -> auto& { return setup(c).unload; },
            "after max_deformation the plates go back to where they first touched (the loading's "
            "speed at each approach, from rest at the turn), recording `records` more rows: the "
            "unloading curve and the deformation the particle keeps (force.csv step 2)")
        .write_when([](const PlateConfig& c) { return c.setup.unload; })
        .integer(
            "stack", [setup](auto& c) -> auto& { return setup(c).stack; }, Range::closed(1, 100),
            "copies of the particle pressed one on another, each its own body: what the stack "
            "adds to that many times one particle's approach is their contacts' (sphere and bms; "
            "the deformation is the approach over the stack's height)")
        .write_when([](const PlateConfig& c) { return c.setup.stack > 1; });
    return p;
  }();
  return t;
}

const OptionTable<BmsConfig>& bms_table() {
  static const OptionTable<BmsConfig> t = [] {
    OptionTable<BmsConfig> b("bms", "plate --particle bms: bonded sub-spheres filling the sphere");
    std::vector<std::pair<std::string, std::string>> lattices;
    for (const char* name : geometry::lattice_names)
      lattices.emplace_back(name, name);
    const auto fill_of_sphere = [](const BmsConfig& c) { return c.templates.empty(); };
    b.string("templates", &BmsConfig::templates,
             "a templates.h5 of `fill`: its BMS template is pressed instead of a fill of the "
             "sphere (count, lattice, placement, seed and fills do not apply; R is half the "
             "template's height along `axis`)")
        .string("template", &BmsConfig::template_name,
                "the /bms/<name> of `templates` (empty: the file's only BMS template)")
        .when([](const BmsConfig& c) { return !c.templates.empty(); }, "without bms.templates")
        .choice("axis", &BmsConfig::axis,
                std::vector<std::pair<std::string, geometry::PressAxis>>{
                    {"short", geometry::PressAxis::short_axis},
                    {"middle", geometry::PressAxis::middle_axis},
                    {"long", geometry::PressAxis::long_axis},
                    {"direction", geometry::PressAxis::direction}},
                "the plates' axis: a principal axis of the template (short: the largest moment), "
                "or `direction`")
        .when([](const BmsConfig& c) { return !c.templates.empty(); }, "without bms.templates")
        .numbers("direction", &BmsConfig::direction, dim::dimensionless, Range::any(),
                 "the plates' axis in the frame of the mesh the template was filled from (a "
                 "fem-plate run's axis_direction; calibrate --reference sets it)")
        .when(
            [](const BmsConfig& c) {
              return !c.templates.empty() && c.axis == geometry::PressAxis::direction;
            },
            "unless bms.templates and bms.axis = \"direction\"")
        .integer("count", &BmsConfig::count, Range::closed(1, 1000000), "sub-spheres")
        .when(fill_of_sphere, "with bms.templates")
        .choice("lattice", &BmsConfig::lattice, lattices, "arrangement of the sub-spheres")
        .when(fill_of_sphere, "with bms.templates")
        .choice("placement", &BmsConfig::placement,
                std::vector<std::pair<std::string, std::string>>{{"inside", "inside"},
                                                                 {"centre", "centre"}},
                "sub-spheres wholly inside the sphere, or their centres")
        .when(fill_of_sphere, "with bms.templates")
        .integer("seed", &BmsConfig::seed, Range::non_negative(), "seed of the (first) fill")
        .when(fill_of_sphere, "with bms.templates")
        .integer("fills", &BmsConfig::fills, Range::closed(1, 1000),
                 "the mean curve of this many fills, seeds seed, seed + 1, ...")
        // m_b <= 1 is refused by create_bonds with the reason.
        .number("bond_multiplier", &BmsConfig::bond_multiplier, Range::any(),
                "m_b: sub-spheres closer than m_b (ri + rj) are bonded (> 1)")
        .string("material", &BmsConfig::material, "the sub-spheres' contact [[material]]")
        .default_text("the sphere's");
    return b;
  }();
  return t;
}

// [bond] comes in three forms, chosen by the keys given (read_bond).
const OptionTable<BondParameters>& bond_modulus_table() {
  static const OptionTable<BondParameters> t = [] {
    OptionTable<BondParameters> b("bond");
    b.quantity("modulus", &BondParameters::modulus, dim::pressure, Range::any(),
               "bond Young's modulus E (one form of the stiffness: kn = E / (ri + rj))")
        .required()
        .default_text("required in this form")
        .number("shear_ratio", &BondParameters::shear_ratio, Range::any(), "ks / kn, with modulus");
    return b;
  }();
  return t;
}

const OptionTable<BondParameters>& bond_fraction_table() {
  static const OptionTable<BondParameters> t = [] {
    OptionTable<BondParameters> b("bond");
    b.number("modulus_fraction", &BondParameters::modulus_fraction, Range::positive(),
             "bond Young's modulus as a fraction of the body material's solid modulus (its "
             "loading_modulus, else youngs_modulus): the third form, kn = fraction E / (ri + rj)")
        .required()
        .default_text("required in this form")
        .number("shear_ratio", &BondParameters::shear_ratio, Range::any(),
                "ks / kn, with modulus or modulus_fraction");
    return b;
  }();
  return t;
}

const OptionTable<BondParameters>& bond_stiffness_table() {
  static const OptionTable<BondParameters> t = [] {
    OptionTable<BondParameters> b("bond");
    b.quantity("normal_stiffness", &BondParameters::normal_stiffness, dim::stiffness_per_area,
               Range::any(), "kn per unit bond area (the other form, instead of modulus)")
        .required()
        .default_text("required in this form")
        .quantity("shear_stiffness", &BondParameters::shear_stiffness, dim::stiffness_per_area,
                  Range::any(), "ks per unit bond area, with normal_stiffness")
        .required()
        .default_text("required in this form");
    return b;
  }();
  return t;
}

const OptionTable<BondParameters>& bond_table() {
  static const OptionTable<BondParameters> t = [] {
    // Signs are checked by BondParameters::check() so that every cause reads the same way.
    OptionTable<BondParameters> b(
        "bond",
        "the parallel bonds of BMS bodies: modulus or modulus_fraction (with shear_ratio), or "
        "normal_stiffness and shear_stiffness; one form");
    b.number("radius_multiplier", &BondParameters::radius_multiplier, Range::any(),
             "lambda: bond radius / smaller sub-sphere radius")
        .quantity("tensile_strength", &BondParameters::tensile_strength, dim::pressure,
                  Range::any(), "tensile strength (inf: unbreakable)")
        .quantity("shear_strength", &BondParameters::shear_strength, dim::pressure, Range::any(),
                  "shear strength (inf: unbreakable)")
        .number("damping_ratio", &BondParameters::damping_ratio, Range::any(),
                "viscous damping of every bond mode, of the critical")
        .boolean("contact_when_bonded", &BondParameters::contact_when_bonded,
                 "bonded sub-spheres that overlap also interact through the contact law");
    return b;
  }();
  return t;
}

const OptionTable<CmsConfig>& cms_table() {
  static const OptionTable<CmsConfig> t = [] {
    OptionTable<CmsConfig> m("cms", "plate --particle cms: one rigid clump filling the sphere");
    m.integer("count", &CmsConfig::count, Range::closed(1, 1000000),
              "sub-spheres asked of the filler (plate --spheres)")
        .integer("resolution", &CmsConfig::resolution, Range::closed(8, 1024),
                 "filler grid cells along the diameter")
        .number("min_radius_fraction", &CmsConfig::min_radius_fraction,
                Range{0.0, 1.0, true, false}, "smallest sub-sphere / largest")
        .boolean("match_volume", &CmsConfig::match_volume,
                 "grow the radii until the union has the sphere's volume")
        .integer("integration_cells", &CmsConfig::integration_cells, Range::closed(8, 1024),
                 "voxels along the clump's longest side (mass, inertia)")
        .string("material", &CmsConfig::material, "the sub-spheres' [[material]]")
        .default_text("the sphere's");
    return m;
  }();
  return t;
}

// `body_material`: the [[material]] of the bodies' sub-spheres, whose solid modulus a
// modulus_fraction is of.
BondParameters read_bond(const ConfigTable& root, const MaterialConfig& materials,
                         const std::string& body_material) {
  const ConfigTable k = root.table("bond");
  BondParameters p;
  if (k.has("modulus") + k.has("modulus_fraction") +
          (k.has("normal_stiffness") || k.has("shear_stiffness")) >
      1)
    throw InputError(root.source_name() +
                     ": bond: give modulus or modulus_fraction (with shear_ratio), or "
                     "normal_stiffness and shear_stiffness: one form");
  if (k.has("modulus")) {
    bond_modulus_table().read(k, p);
  } else if (k.has("modulus_fraction")) {
    bond_fraction_table().read(k, p);
    const Material* m = materials.find(body_material);
    if (!m)
      throw InputError(root.source_name() + ": bond.modulus_fraction: no [[material]] '" +
                       body_material + "' for the bodies");
    p.modulus = p.modulus_fraction * m->loading_modulus.value_or(m->youngs_modulus);
  } else {
    if (k.has("shear_ratio"))
      throw InputError(root.source_name() +
                       ": key 'bond.shear_ratio' is not used without bond.modulus (give "
                       "shear_stiffness)");
    bond_stiffness_table().read(k, p);
  }
  bond_table().read(k, p);
  p.model = read_bond_model(k, root.source_name() + ": [bond]");
  try {
    p.check();
  } catch (const InputError& e) {
    throw InputError(root.source_name() + ": [bond] " + e.what());
  }
  return p;
}

// [bond] in its two forms, for the docs.
OptionSection bond_docs() {
  OptionSection bond = bond_table().docs();
  std::vector<OptionDoc> rows = bond_modulus_table().docs().rows;
  rows.push_back(bond_fraction_table().docs().rows.front());
  for (const OptionDoc& row : bond_stiffness_table().docs().rows)
    rows.push_back(row);
  rows.insert(rows.end(), bond.rows.begin(), bond.rows.end());
  for (OptionDoc& row : bond_model_options())
    rows.push_back(std::move(row));
  bond.rows = rows;
  return bond;
}

std::string bond_toml(const BondParameters& p) {
  return "[bond]\n" +
         (p.modulus_fraction > 0.0 ? bond_fraction_table().lines(p)
          : p.modulus > 0.0        ? bond_modulus_table().lines(p)
                                   : bond_stiffness_table().lines(p)) +
         bond_table().lines(p) + bond_model_toml(p.model);
}

}  // namespace

PlateConfig read_plate_config(const ConfigTable& root,
                              const std::optional<std::string>& normal_law) {
  PlateConfig c;
  c.materials = read_materials(root, normal_law);
  if (root.has("run")) plate_run_table().read(root.table("run"), c);
  const MaterialTable table = c.materials.table();
  sphere_table().read(root.table("sphere"), c);
  c.setup.sphere_material = table.index_of(c.sphere_material);
  plate_table().read(root.table("plate"), c);
  c.setup.plate_material = table.index_of(c.plate_material);
  if (root.has("bms")) {
    BmsConfig b = bms_table().read(root.table("bms"));
    if (b.material.empty()) b.material = c.sphere_material;
    table.index_of(b.material);
    b.bond = read_bond(root, c.materials, b.material);
    c.bms = b;
  }
  const bool from_template = c.bms && !c.bms->templates.empty();
  if (from_template && root.table("sphere").has("radius"))
    throw InputError(fmt::format(
        "{}: key 'sphere.radius' is not used with bms.templates: R is half the template's height "
        "along bms.axis",
        root.source_name()));
  if (from_template) {
    if (c.bms->fills != 1)
      throw InputError(fmt::format("{}: bms.fills {}: a template is one particle (fills = 1)",
                                   root.source_name(), c.bms->fills));
    c.setup.radius = bms_template_half_height(*c.bms);
  } else if (!(c.setup.radius > 0.0)) {
    throw InputError(fmt::format(
        "{}: missing required key 'sphere.radius' (a length; or a template: [bms] templates)",
        root.source_name()));
  }
  if (root.has("cms")) {
    CmsConfig m = cms_table().read(root.table("cms"));
    if (m.material.empty()) m.material = c.sphere_material;
    table.index_of(m.material);
    c.cms = m;
  }
  return c;
}

std::string plate_config_toml(const PlateConfig& c) {
  std::string out = materials_toml(c.materials) + plate_run_table().write(c) + "\n" +
                    sphere_table().write(c) + "\n" + plate_table().write(c);
  if (c.cms) out += "\n" + cms_table().write(*c.cms);
  if (c.bms) out += "\n" + bms_table().write(*c.bms) + "\n" + bond_toml(c.bms->bond);
  return out;
}

StageOptions plate_config_options(std::string stage) {
  StageOptions o{std::move(stage),
                 "The plate rig: one particle between two plates (a quantity is a number in the "
                 "SI unit or a string with a unit).",
                 {}};
  add_material_sections(o);
  for (const auto* t : {&plate_run_table(), &sphere_table(), &plate_table()})
    o.sections.push_back(t->docs());
  o.sections.push_back(bms_table().docs());
  o.sections.push_back(bond_docs());
  o.sections.push_back(cms_table().docs());
  return o;
}

namespace {

const auto compact_run = [](auto& c) -> auto& {
  return c.run;
};

const OptionTable<CompactConfig>& compact_run_table() {
  static const OptionTable<CompactConfig> t = [] {
    OptionTable<CompactConfig> r("run", "time step, engine settings, length of the run");
    add_run_rows(r, compact_run, "0.1 x the smallest sphere diameter");
    const auto setup = [](auto& c) -> auto& {
      return c.setup;
    };
    r.integer(
         "bond_substeps", [](auto& c) -> auto& { return c.run.engine.bond_substeps; },
         Range::closed(0, 1000),
         "bond sub-steps per step (multiple time stepping: the bonds on fraction x their period "
         "bound, the contacts on fraction x theirs; 0: as many as that needs; 1: single-rate)")
        .integer(
            "steps", [setup](auto& c) -> auto& { return setup(c).max_steps; },
            Range::non_negative(), "total step count to stop at (0: when the punch program ends)")
        .integer(
            "record_every", [setup](auto& c) -> auto& { return setup(c).record_every; },
            Range::at_least(1), "steps between rows of punch.csv")
        .integer(
            "snapshot_every", [setup](auto& c) -> auto& { return setup(c).snapshot_every; },
            Range::non_negative(), "steps between snapshots (0: none)")
        .integer("checkpoint_every", &CompactConfig::checkpoint_every, Range::non_negative(),
                 "steps between checkpoints for --resume (0: by wall time only)")
        .number("checkpoint_minutes", &CompactConfig::checkpoint_minutes, Range::non_negative(),
                "minutes of wall time between checkpoints for --resume (0: by steps only)")
        .numbers(
            "gravity", [](auto& c) -> auto& { return c.run.engine.gravity; }, dim::acceleration,
            Range::any(), "[gx, gy, gz]")
        .number("density_scale", &CompactConfig::density_scale, Range::positive(),
                "mass scaling: every particle's density x this, for quasi-static runs only "
                "(the time step grows as its square root)");
    return r;
  }();
  return t;
}

const OptionTable<CompactConfig>& box_table() {
  static const OptionTable<CompactConfig> t = [] {
    OptionTable<CompactConfig> b("box", "the die: periodic in x and y, plates below and above");
    b.quantity("x", &CompactConfig::box_x, dim::length, Range::positive(), "periodic length in x")
        .required()
        .quantity("y", &CompactConfig::box_y, dim::length, Range::positive(),
                  "periodic length in y")
        .required()
        .quantity("bottom", &CompactConfig::bottom, dim::length, Range::any(),
                  "height of the bottom plate")
        .quantity("punch", &CompactConfig::punch, dim::length, Range::any(),
                  "initial height of the punch, above bottom")
        .default_text("the top of a packing made by pack (required for any other bed)")
        // NaN stands for "not given": the written config leaves it out, so it still means the
        // packing's top when read back.
        .write_when([](const CompactConfig& c) { return !std::isnan(c.punch); });
    return b;
  }();
  return t;
}

const OptionTable<CompactConfig>& particles_table() {
  static const OptionTable<CompactConfig> t = [] {
    OptionTable<CompactConfig> p("particles", "the bed");
    p.string("material", &CompactConfig::particle_material, "the particles' [[material]]")
        .required();
    return p;
  }();
  return t;
}

const OptionTable<CompactConfig>& walls_table() {
  static const OptionTable<CompactConfig> t = [] {
    OptionTable<CompactConfig> w("walls", "the bottom plate and the punch");
    w.string("material", &CompactConfig::wall_material, "the walls' [[material]]").required();
    return w;
  }();
  return t;
}

const OptionTable<CompactConfig>& punch_table() {
  static const OptionTable<CompactConfig> t = [] {
    OptionTable<CompactConfig> p("punch", "the punch program");
    const auto program = [](auto& c) -> auto& {
      return c.setup.program;
    };
    const auto servo = [](const CompactConfig& c) {
      return c.setup.program.mode == PunchProgram::Mode::servo;
    };
    const auto displacement = [servo](const CompactConfig& c) { return !servo(c); };
    p.choice(
         "mode", [program](auto& c) -> auto& { return program(c).mode; },
         std::vector<std::pair<std::string, PunchProgram::Mode>>{
             {"displacement", PunchProgram::Mode::displacement},
             {"servo", PunchProgram::Mode::servo}},
         "move to a gap or strain, or hold a stress")
        .quantity(
            "hold_time", [program](auto& c) -> auto& { return program(c).hold_time; }, dim::time,
            Range::non_negative(), "hold at the target")
        .quantity(
            "unload_speed", [program](auto& c) -> auto& { return program(c).unload_speed; },
            dim::velocity, Range::non_negative(), "upwards after the hold (0: end after it)")
        .quantity(
            "target_stress", [program](auto& c) -> auto& { return program(c).target_stress; },
            dim::pressure, Range::positive(), "servo: punch stress to reach")
        .required()
        .when(servo, "with punch.mode = \"displacement\"")
        .quantity(
            "max_speed", [program](auto& c) -> auto& { return program(c).max_speed; },
            dim::velocity, Range::positive(), "servo: fastest punch speed")
        .required()
        .when(servo, "with punch.mode = \"displacement\"")
        .quantity(
            "speed", [program](auto& c) -> auto& { return program(c).speed; }, dim::velocity,
            Range::positive(), "displacement: downwards punch speed")
        .required()
        .when(displacement, "with punch.mode = \"servo\"")
        .quantity(
            "target_gap", [program](auto& c) -> auto& { return program(c).target_gap; },
            dim::length, Range::positive(), "displacement: gap to reach (or target_strain)")
        .when(displacement, "with punch.mode = \"servo\"")
        .number("target_strain", &CompactConfig::target_strain, Range{0.0, 1.0, false, false},
                "displacement: strain from H0 to reach (or target_gap)")
        .when(displacement, "with punch.mode = \"servo\"")
        .number("target_solid_fraction", &CompactConfig::target_solid_fraction,
                Range{0.0, 1.0, false, false},
                "displacement: solid fraction to reach, by the bed's solid volume (or "
                "target_gap, target_strain): one endpoint for beds of any kind")
        .when(displacement, "with punch.mode = \"servo\"")
        .choice(
            "strain_reference", [](auto& c) -> auto& { return c.setup.strain_reference; },
            std::vector<std::pair<std::string, CompactionSetup::StrainReference>>{
                {"start", CompactionSetup::StrainReference::start},
                {"fill", CompactionSetup::StrainReference::fill},
                {"solid_fraction", CompactionSetup::StrainReference::solid_fraction}},
            "H0: the gap when loading starts, the loose fill height (generate.height), or "
            "the gap at which the bed's solid fraction is reference_solid_fraction")
        .number(
            "reference_solid_fraction",
            [](auto& c) -> auto& { return c.setup.reference_solid_fraction; },
            Range{0.0, 1.0, false, false},
            "the solid fraction of H0 with strain_reference = \"solid_fraction\"")
        .choice(
            "solid_fraction_volume", [](auto& c) -> auto& { return c.setup.solid_fraction_volume; },
            packing::solid_volume_choices(),
            "the volume the bed's solid fraction is by (punch.csv's solid_fraction, "
            "target_solid_fraction, reference_solid_fraction, the ceiling, Heckel): the bodies' "
            "in the bed or their shapes' (meshes'); one for spheres")
        .quantity(
            "relax_time", [program](auto& c) -> auto& { return program(c).relax_time; }, dim::time,
            Range::non_negative(),
            "the punch still this long before loading, the bed settling under the compaction's "
            "contact law (not recorded in punch.csv)")
        .quantity(
            "release_time", [program](auto& c) -> auto& { return program(c).release_time; },
            dim::time, Range::non_negative(),
            "after unloading, the punch follows the bed's spring-back this long at "
            "release_stress_fraction of the peak stress; the elastic recovery is read at its end")
        .number(
            "release_stress_fraction",
            [program](auto& c) -> auto& { return program(c).release_stress_fraction; },
            Range{0.0, 1.0, false, false}, "the stress held while releasing, of the peak")
        .number(
            "max_solid_fraction", [](auto& c) -> auto& { return c.setup.max_solid_fraction; },
            Range{0.0, 1.0, false, false}, "loading stops when the solid fraction passes it");
    return p;
  }();
  return t;
}

const auto generated = [](auto& c) -> auto& {
  return *c.generate;
};

const OptionTable<CompactConfig>& generate_table() {
  static const OptionTable<CompactConfig> t = [] {
    CompactConfig defaults;  // the rows' defaults are those of a [generate] table present
    defaults.generate.emplace();
    OptionTable<CompactConfig> g(
        "generate", "a random bed, settled under gravity (when no --packing)", defaults);
    g.integer(
         "count", [](auto& c) -> auto& { return generated(c).count; }, Range::at_least(1),
         "spheres")
        .required()
        .quantity(
            "diameter_min", [](auto& c) -> auto& { return generated(c).diameter_min; }, dim::length,
            Range::positive(), "smallest diameter")
        .required()
        .quantity(
            "diameter_max", [](auto& c) -> auto& { return generated(c).diameter_max; }, dim::length,
            Range::positive(), "largest diameter")
        .default_from([](const CompactConfig& c) { return c.generate->diameter_min; },
                      "diameter_min")
        .integer(
            "seed", [](auto& c) -> auto& { return generated(c).seed; }, Range::non_negative(),
            "random seed")
        .quantity("height", &CompactConfig::fill_height, dim::length, Range::positive(),
                  "top of the insertion region above box.bottom")
        .default_from([](const CompactConfig& c) { return c.punch - c.bottom; }, "box height")
        .quantity("settle_time", &CompactConfig::settle_time, dim::time, Range::non_negative(),
                  "settling under gravity (9.81 m/s^2 down if run.gravity is zero)")
        .number("settle_friction", &CompactConfig::settle_friction, Range::non_negative(),
                "sliding and rolling friction of every interaction while settling")
        .default_text("the interactions' own");
    return g;
  }();
  return t;
}

const OptionTable<SizeQuantiles>& size_table_options() {
  static const OptionTable<SizeQuantiles> t = size_quantile_table(
      "generate", "diameters of a size distribution truncated to [diameter_min, diameter_max]",
      "none (uniform diameters)", "the levels' weighting");
  return t;
}

const OptionTable<ClumpsConfig>& clumps_table() {
  static const OptionTable<ClumpsConfig> t = [] {
    OptionTable<ClumpsConfig> k(
        "clumps",
        "rigid CMS clumps inserted at random in the [generate] region (else the box), of the "
        "particles' material: templates or spheres, one of the two");
    k.integer("count", &ClumpsConfig::count, Range::at_least(1), "clumps")
        .required()
        .integer("seed", &ClumpsConfig::seed, Range::non_negative(), "random seed")
        .integer("integration_cells", &ClumpsConfig::integration_cells, Range::closed(8, 1024),
                 "voxels along a clump's longest side (mass, inertia)")
        .string("templates", &ClumpsConfig::templates, "a templates.h5 (its /cms groups)")
        .string("template", &ClumpsConfig::template_name, "one /cms/<name> of templates")
        .default_text("all, in turn")
        .when([](const ClumpsConfig& c) { return !c.templates.empty(); },
              "without clumps.templates")
        .numbers("spheres", &ClumpsConfig::spheres, dim::length, Range::any(),
                 "one template inline: x, y, z, r per sub-sphere (body frame)");
    return k;
  }();
  return t;
}

}  // namespace

CompactConfig read_compact_config(const ConfigTable& root) {
  CompactConfig c;
  c.materials = read_materials(root);
  if (root.has("run")) compact_run_table().read(root.table("run"), c);
  box_table().read(root.table("box"), c);
  if (root.table("box").has("punch") && !(c.punch > c.bottom))
    throw InputError(root.source_name() + ": box.punch must be above box.bottom");
  if (!root.table("box").has("punch") && (root.has("generate") || root.has("clumps")))
    throw InputError(root.source_name() +
                     ": box.punch is required with [generate] or [clumps] (it bounds the pour)");
  particles_table().read(root.table("particles"), c);
  walls_table().read(root.table("walls"), c);
  const ConfigTable punch = root.table("punch");
  if (punch.has("target_gap") + punch.has("target_strain") + punch.has("target_solid_fraction") > 1)
    throw InputError(root.source_name() +
                     ": give one of punch.target_gap, target_strain and target_solid_fraction");
  punch_table().read(punch, c);
  if (c.setup.program.release_time > 0.0 && !(c.setup.program.unload_speed > 0.0))
    throw InputError(root.source_name() +
                     ": punch.release_time follows the unloading: it needs punch.unload_speed > 0");
  if (c.setup.strain_reference == CompactionSetup::StrainReference::fill && !root.has("generate"))
    throw InputError(root.source_name() +
                     ": punch.strain_reference = \"fill\" needs a [generate] table (the loose "
                     "fill height is generate.height)");
  if (root.has("generate")) {
    const ConfigTable g = root.table("generate");
    c.generate.emplace();
    generate_table().read(g, c);
    InsertionRequest& r = *c.generate;
    if (g.has("size_quantiles")) {
      const SizeQuantiles q = size_table_options().read(g);
      try {
        q.check();
        size_table(q, r.diameter_min, r.diameter_max);
      } catch (const InputError& e) {
        throw InputError(root.source_name() + ": [generate] " + e.what());
      }
      r.sizes = q;
    }
    if (*c.fill_height > c.punch - c.bottom)
      throw InputError(root.source_name() + ": generate.height is above box.punch");
    r.z_low = c.bottom;
    r.z_high = c.bottom + *c.fill_height;
  }
  if (root.has("clumps")) {
    const ConfigTable t = root.table("clumps");
    if (t.has("templates") == t.has("spheres"))
      throw InputError(root.source_name() +
                       ": [clumps] needs templates (a templates file) or spheres (x, y, z, r per "
                       "sub-sphere), one of the two");
    ClumpsConfig k = clumps_table().read(t);
    if (!t.has("templates") && (k.spheres.empty() || k.spheres.size() % 4 != 0))
      throw InputError(root.source_name() +
                       ": clumps.spheres must hold x, y, z, r (metres) per sub-sphere");
    c.clumps = k;
  }
  if (root.has("bond")) c.bond = read_bond(root, c.materials, c.particle_material);
  return c;
}

std::string compact_config_toml(const CompactConfig& c) {
  std::string out = materials_toml(c.materials);
  for (const auto* t :
       {&compact_run_table(), &box_table(), &particles_table(), &walls_table(), &punch_table()})
    out += t->write(c) + "\n";
  if (c.generate) {
    out += generate_table().write(c);
    if (c.generate->sizes) out += size_table_options().lines(*c.generate->sizes);
    out += "\n";
  }
  if (c.clumps) out += clumps_table().write(*c.clumps);
  if (c.bond) out += "\n" + bond_toml(*c.bond);
  return out;
}

StageOptions compact_config_options() {
  StageOptions o{"compact",
                 "A bed of spheres (and clumps) in a periodic die pressed by a punch (a quantity "
                 "is a number in the SI unit or a string with a unit).",
                 {}};
  add_material_sections(o);
  for (const auto* t :
       {&compact_run_table(), &box_table(), &particles_table(), &walls_table(), &punch_table()})
    o.sections.push_back(t->docs());
  OptionSection generate = generate_table().docs();
  for (const OptionDoc& row : size_table_options().docs().rows)
    generate.rows.push_back(row);
  o.sections.push_back(generate);
  o.sections.push_back(clumps_table().docs());
  OptionSection bond = bond_docs();
  bond.help = "the parallel bonds of the BMS bodies of a packing from pack (compact --packing)";
  o.sections.push_back(bond);
  return o;
}

}  // namespace shapepress::scenarios
