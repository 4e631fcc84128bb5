#include "packing/pack_config.hpp"

#include <fmt/format.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "common/error.hpp"
#include "common/units.hpp"

namespace shapepress::packing {
namespace {

const OptionTable<PackRequest>& pack_table() {
  static const OptionTable<PackRequest> t = [] {
    OptionTable<PackRequest> p("pack", "the bed: how many bodies, the die's cross-section");
    p.integer("count", &PackRequest::count, Range::non_negative(),
              "bodies (0: draw until target_mass)")
        .quantity("target_mass", &PackRequest::target_mass, dim::mass, Range::positive(),
                  "draw bodies until their mass (body volume × density) reaches this")
        .default_text("none (count)")
        .choice("weighting", &PackRequest::weighting,
                std::vector<std::pair<std::string, TemplateWeighting>>{
                    {"number", TemplateWeighting::number}, {"volume", TemplateWeighting::volume}},
                "what the [[template]] weights share: the number of bodies or their volume")
        .integer("seed", &PackRequest::seed, Range::non_negative(),
                 "random seed (sizes, templates, orientations, insertion); --seed overrides")
        .quantity("box_x", &PackRequest::box_x, dim::length, Range::positive(),
                  "periodic box length along x (the paper's 1 mm)")
        .quantity("box_y", &PackRequest::box_y, dim::length, Range::positive(),
                  "periodic box length along y")
        .quantity("floor", &PackRequest::floor, dim::length, Range::any(), "the die floor's z");
    return p;
  }();
  return t;
}

const OptionTable<TemplateChoice>& template_table() {
  static const OptionTable<TemplateChoice> t = [] {
    OptionTable<TemplateChoice> c(
        "template",
        "one per template a body may take (none: one \"sphere\"); searched in the TEMPLATES "
        "files in order");
    c.string("name", &TemplateChoice::name, "\"sphere\", \"bms/<name>\" or \"cms/<name>\"")
        .required()
        .number("weight", &TemplateChoice::weight, Range::positive(),
                "share of bodies (pack.weighting = number) or of volume (volume)");
    return c;
  }();
  return t;
}

struct Sizes {
  std::string summary;
  double diameter_min = 0.0, diameter_max = 0.0;
};

const OptionTable<Sizes>& sizes_table() {
  static const OptionTable<Sizes> t = [] {
    OptionTable<Sizes> s("sizes",
                         "the volume-equivalent diameters: a shape-stats summary.json (its Q3 "
                         "x10/x50/x90) or size_quantiles, truncated to [diameter_min, "
                         "diameter_max]");
    s.string("summary", &Sizes::summary,
             "shape-stats summary.json (relative to this config's folder)")
        .quantity("diameter_min", &Sizes::diameter_min, dim::length, Range::positive(),
                  "smallest diameter kept (the paper drops particles under 180 um)")
        .required()
        .quantity("diameter_max", &Sizes::diameter_max, dim::length, Range::positive(),
                  "largest diameter kept")
        .required();
    return s;
  }();
  return t;
}

const OptionTable<SizeQuantiles>& quantiles_table() {
  static const OptionTable<SizeQuantiles> t = size_quantile_table(
      "sizes", "diameters at size_quantile_levels (Table 2's x10, x50, x90)", "none (summary)",
      "the levels' weighting (Q3 or Q0); the measured x10/x50/x90 use the same");
  return t;
}

const OptionTable<PackRequest>& material_table() {
  static const OptionTable<PackRequest> t = [] {
    OptionTable<PackRequest> m(
        "material",
        "Hertz–Mindlin contacts between bodies and with the walls while packing (bodies rigid; "
        "a reduced E allows a larger time step: the bed's overlaps stay small at rest)");
    m.quantity("density", &PackRequest::density, dim::density, Range::positive(),
               "of the bodies (Avicel's true density ~1500 kg/m^3)")
        .quantity("youngs_modulus", &PackRequest::youngs_modulus, dim::pressure, Range::positive(),
                  "contact modulus while packing (reduced from the solid's)")
        .number("poisson_ratio", &PackRequest::poisson_ratio, Range{0.0, 0.5, true, false},
                "Poisson's ratio")
        .number("restitution", &PackRequest::restitution, Range::open_closed(0.0, 1.0),
                "restitution of every contact (low: the bed comes to rest sooner)")
        .number("friction", &PackRequest::friction, Range::non_negative(),
                "sliding friction between bodies")
        .number("wall_friction", &PackRequest::wall_friction, Range::non_negative(),
                "sliding friction with the floor and punch")
        .number("rolling_friction", &PackRequest::rolling_friction, Range::non_negative(),
                "rolling friction of every contact");
    return m;
  }();
  return t;
}

const OptionTable<PackRequest>& settle_table() {
  static const OptionTable<PackRequest> t = [] {
    OptionTable<PackRequest> s("settle", "insertion and the gravity settle");
    s.choice("insertion", &PackRequest::insertion,
             std::vector<std::pair<std::string, Insertion>>{{"pour", Insertion::pour},
                                                            {"deposit", Insertion::deposit}},
             "how the settle starts: the pour falls from its insertion region; a deposit lays "
             "the poured bodies down first (dropped to contact, shaken lower, no overlap), so the "
             "settle starts near the settled bed's height")
        .write_when([](const PackRequest& r) { return r.insertion != Insertion::pour; })
        .number("insertion_fraction", &PackRequest::insertion_fraction,
                Range{0.0, 0.5, false, false},
                "bounding-sphere volume fraction of the insertion region (sets its height)")
        .integer("attempts_per_body", &PackRequest::attempts_per_body, Range::at_least(1),
                 "random insertion tries per body before the region is made taller")
        .quantity("gravity", &PackRequest::gravity, dim::acceleration, Range::positive(),
                  "downwards")
        .number("kinetic_energy_ratio", &PackRequest::kinetic_energy_ratio, Range::positive(),
                "at rest when the kinetic energy is below this × sum of m g d over the bodies")
        .quantity("damping_time", &PackRequest::damping_time, dim::time, Range::non_negative(),
                  "viscous drag time on every body's motion, v -> v exp(-dt/tau) (0: none); a "
                  "clump's contacts alone damp too little to bring a bed to rest")
        .number("density_scale", &PackRequest::settle_density_scale, Range::at_least(1.0),
                "mass scaling s of pack: settle, press (at speed / √s) and relaxation at s × "
                "density (a √s longer step, s^(2/3) deeper overlaps under the bed's weight), "
                "then a release at the true density")
        .quantity("max_time", &PackRequest::max_settle_time, dim::time, Range::positive(),
                  "longest settle, press or relaxation (a warning when reached)")
        .quantity("time_step", &PackRequest::time_step, dim::time, Range::positive(),
                  "fixed time step")
        .default_text("time_step_fraction of the engine's bound")
        .number("time_step_fraction", &PackRequest::time_step_fraction, Range::open_closed(0, 1),
                "of the Rayleigh time / rigid-clump period bound (simulate/timestep.hpp)");
    return s;
  }();
  return t;
}

const OptionTable<PackRequest>& press_table() {
  static const OptionTable<PackRequest> t = [] {
    OptionTable<PackRequest> p(
        "press",
        "optional pre-compression: the punch presses the settled bed to a solid fraction (by "
        "body volume, or shape volume), goes back up, and the bed relaxes");
    p.number("solid_fraction", &PackRequest::target_solid_fraction, Range::positive(),
             "target solid fraction by solid_fraction_volume (the paper: 0.59)")
        .default_text("none (no press)")
        .choice("solid_fraction_volume", &PackRequest::solid_fraction_volume,
                solid_volume_choices(),
                "the volume the target and the settled and pre-compression fractions are by: "
                "the bodies' in the bed or their shapes' (meshes'); one for spheres")
        .number("friction", &PackRequest::press_friction, Range::non_negative(),
                "sliding friction of every contact while pressing (0: the bodies slide into a "
                "denser bed); the bed relaxes with [material]'s")
        .quantity("speed", &PackRequest::punch_speed, dim::velocity, Range::positive(),
                  "punch speed")
        .number("solid_fraction_ceiling", &PackRequest::solid_fraction_ceiling,
                Range::open_closed(0.0, 1.0),
                "a target above it is refused (rigid bodies with small overlaps)");
    return p;
  }();
  return t;
}

const OptionTable<CheckpointPolicy>& run_table() {
  static const OptionTable<CheckpointPolicy> t = [] {
    OptionTable<CheckpointPolicy> r("run", "checkpoints for pack --resume");
    r.integer("checkpoint_every", &CheckpointPolicy::every_steps, Range::non_negative(),
              "steps between checkpoints (0: by wall time only)")
        .number("checkpoint_minutes", &CheckpointPolicy::minutes, Range::non_negative(),
                "minutes of wall time between checkpoints (0: by steps only)");
    return r;
  }();
  return t;
}

}  // namespace

SizeQuantiles read_summary_sizes(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("sizes.summary: cannot open '{}'", path.string()));
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("'{}': not JSON ({})", path.string(), e.what()));
  }
  if (!j.contains("size") || !j["size"].is_object())
    throw InputError(
        fmt::format("'{}': no \"size\" object: not a shape-stats summary.json", path.string()));
  SizeQuantiles q;
  q.levels = {0.1, 0.5, 0.9};
  q.volume_weighted = true;  // shape-stats' size.x10_m.. are Q3
  for (const char* key : {"x10_m", "x50_m", "x90_m"}) {
    const auto& v = j["size"][key];
    if (!v.is_number())
      throw InputError(fmt::format("'{}': size.{} is missing or not a number", path.string(), key));
    q.diameters.push_back(v.get<double>());
  }
  try {
    q.check();
  } catch (const InputError& e) {
    throw InputError(fmt::format("'{}': {}", path.string(), e.what()));
  }
  return q;
}

OptionTable<SizeQuantiles> size_quantile_table(std::string section, std::string diameters_help,
                                               std::string absent_text,
                                               std::string weighting_help) {
  OptionTable<SizeQuantiles> q(std::move(section));
  q.numbers("size_quantiles", &SizeQuantiles::diameters, dim::length, Range::positive(),
            std::move(diameters_help))
      .required()
      .default_text(std::move(absent_text))
      .numbers("size_quantile_levels", &SizeQuantiles::levels, dim::dimensionless,
               Range{0.0, 1.0, false, false}, "cumulative fraction at each of size_quantiles")
      .required()
      .default_text("with size_quantiles")
      .choice("size_weighting", &SizeQuantiles::volume_weighted,
              std::vector<std::pair<std::string, bool>>{{"volume", true}, {"number", false}},
              std::move(weighting_help));
  return q;
}

PackConfig read_pack_config(const ConfigTable& root, const std::filesystem::path& config_path,
                            const std::filesystem::path& summary_override) {
  PackConfig c;
  PackRequest& r = c.request;
  pack_table().read(root.table("pack"), r);
  if (root.has("material")) material_table().read(root.table("material"), r);
  if (root.has("settle")) settle_table().read(root.table("settle"), r);
  if (root.has("press")) press_table().read(root.table("press"), r);
  if (root.has("run")) run_table().read(root.table("run"), c.checkpoints);
  for (const ConfigTable& t : root.tables("template"))
    r.templates.push_back(template_table().read(t));
  if (r.templates.empty()) r.templates.push_back({"sphere", 1.0});
  const ConfigTable s = root.table("sizes");
  const Sizes sizes = sizes_table().read(s);
  if (!summary_override.empty()) {
    if (s.has("size_quantiles")) quantiles_table().read(s);  // read: not an unknown key
    c.summary = summary_override.string();
    r.sizes = read_summary_sizes(summary_override);
  } else if (s.has("summary") == s.has("size_quantiles")) {
    throw InputError(root.source_name() +
                     ": [sizes] needs summary (a shape-stats summary.json) or size_quantiles, "
                     "one of the two");
  } else if (s.has("summary")) {
    c.summary = sizes.summary;
    std::filesystem::path summary = sizes.summary;
    if (summary.is_relative()) summary = config_path.parent_path() / summary;
    r.sizes = read_summary_sizes(summary);
  } else {
    r.sizes = quantiles_table().read(s);
    try {
      r.sizes.check();
    } catch (const InputError& e) {
      throw InputError(root.source_name() + ": [sizes] " + e.what());
    }
  }
  r.diameter_min = sizes.diameter_min;
  r.diameter_max = sizes.diameter_max;
  if (r.count > 0 && r.target_mass)
    throw InputError(root.source_name() + ": give pack.count or pack.target_mass, not both");
  try {
    r.check();
  } catch (const InputError& e) {
    throw InputError(root.source_name() + ": " + e.what());
  }
  return c;
}

std::string pack_config_toml(const PackConfig& c) {
  std::string out = pack_table().write(c.request) + "\n";
  for (const TemplateChoice& t : c.request.templates)
    out += "[[template]]\n" + template_table().lines(t) + "\n";
  out += "[sizes]\n";
  Sizes sizes{c.summary, c.request.diameter_min, c.request.diameter_max};
  out += sizes_table().lines(sizes);
  if (c.summary.empty()) out += quantiles_table().lines(c.request.sizes);
  out += "\n" + material_table().write(c.request) + "\n" + settle_table().write(c.request) + "\n";
  if (c.request.target_solid_fraction) out += press_table().write(c.request) + "\n";
  out += run_table().write(c.checkpoints);
  return out;
}

StageOptions pack_config_options() {
  StageOptions o{"pack",
                 "A bed of bodies (spheres, BMS and CMS templates of fill) poured into a periodic "
                 "die, settled and optionally pre-compressed (a quantity is a number in the SI "
                 "unit or a string with a unit).",
                 {}};
  o.sections.push_back(pack_table().docs());
  o.sections.push_back(template_table().docs());
  o.sections.back().repeated = true;
  OptionSection sizes = sizes_table().docs();
  for (const OptionDoc& row : quantiles_table().docs().rows)
    sizes.rows.push_back(row);
  o.sections.push_back(sizes);
  for (const auto* t : {&material_table(), &settle_table(), &press_table()})
    o.sections.push_back(t->docs());
  o.sections.push_back(run_table().docs());
  return o;
}

}  // namespace shapepress::packing
