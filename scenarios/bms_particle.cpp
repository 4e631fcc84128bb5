#include "scenarios/bms_particle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "common/error.hpp"
#include "geometry/press_frame.hpp"
#include "geometry/templates_file.hpp"

#include "geometry/signed_distance.hpp"
#include "geometry/sphere_fill.hpp"

namespace shapepress::scenarios {

PlateParticle bms_sphere(const MaterialTable& materials, double radius, const BmsConfig& config,
                         const std::string& name, BmsParticleInfo* info, BmsFillCache* cache,
                         int stack) {
  config.bond.check();
  geometry::BondedFillOptions options;
  options.target_count = config.count;
  options.lattice = geometry::lattice_from_name(config.lattice);
  options.placement =
      config.placement == "centre" ? geometry::Placement::centre : geometry::Placement::inside;
  // The filler bonds by Eq. 10 too, only to keep one connected cluster; m_b is checked by
  // create_bonds below with the engine's message, so the filler gets a valid one.
  options.bond_multiplier =
      config.bond_multiplier > 1.0 && config.bond_multiplier < 1.4 ? config.bond_multiplier : 1.15;
  options.seed = config.seed;
  const int material = materials.index_of(config.material);
  const double density = materials.material(material).density;
  const auto fill = [&] {
    const geometry::SphereTemplate filled =
        geometry::fill_bonded(geometry::sphere_distance(radius), options);
    SphereState spheres;
    for (std::size_t i = 0; i < filled.centres.size(); ++i) {
      const geometry::Vec3& c = filled.centres[i];
      spheres.add_sphere(c.x(), c.y(), c.z() + radius, filled.radii[i], density, material);
      spheres.body.back() = 0;
    }
    return spheres;
  };
  PlateParticle particle;
  particle.spheres =
      cache ? cache->get(fmt::format("{} {} {} {} {:.17g} {:.17g} {} {:.17g}", config.count,
                                     config.lattice, config.placement, config.seed,
                                     options.bond_multiplier, radius, material, density),
                         fill)
            : fill();
  particle.spheres = stacked(particle.spheres, stack, radius);
  particle.bonds = create_bonds(particle.spheres, config.bond_multiplier, config.bond,
                                std::vector<std::string>(static_cast<std::size_t>(stack), name));
  if (info) {
    info->sub_sphere_radius = particle.spheres.size() == 0 ? 0.0 : particle.spheres.radius[0];
    info->spheres = particle.spheres.size() / static_cast<std::size_t>(stack);
    info->bonds = particle.bonds.size() / static_cast<std::size_t>(stack);
  }
  return particle;
}

namespace {

// The template's sub-spheres (centres, radii) in the press frame, from the file.
struct TurnedTemplate {
  std::vector<geometry::Vec3> centres;
  std::vector<double> radii;
  double low = 0.0, high = 0.0;  // the lowest and highest sub-sphere surface along z
  double volume_radius = 0.0;    // of the shape it fills, R = (3V / 4π)^{1/3}
};

TurnedTemplate turned_template(const BmsConfig& config) {
  const std::vector<geometry::TemplateRecord> records = geometry::read_templates(config.templates);
  const geometry::TemplateRecord* chosen = nullptr;
  std::vector<std::string> names;
  for (const geometry::TemplateRecord& r : records) {
    if (r.bond_multiplier <= 0.0) continue;  // a CMS template
    names.push_back(r.name);
    if (r.name == config.template_name || config.template_name.empty()) chosen = &r;
  }
  if (chosen == nullptr || (config.template_name.empty() && names.size() != 1))
    throw InputError(fmt::format(
        "{}: {} (its BMS templates: {})", config.templates,
        config.template_name.empty() ? "bms.template must name one of several BMS templates"
                                     : fmt::format("no BMS template '{}'", config.template_name),
        names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "))));
  // The body frame's axes are the template's principal axes, ascending moments: identity. A
  // direction is given in the mesh's frame: x_mesh = origin + R x_body, so R^T turns it in.
  std::array<double, 3> direction = config.direction;
  if (config.axis == geometry::PressAxis::direction) {
    const geometry::Vec3 d =
        chosen->body_axes.transpose() * geometry::Vec3(direction[0], direction[1], direction[2]);
    if (d.norm() == 0.0) throw InputError("bms.direction: a zero vector gives no pressing axis");
    direction = {d.x(), d.y(), d.z()};
  }
  const geometry::Mat3 frame =
      geometry::press_frame(geometry::Mat3::Identity(), config.axis, direction);
  TurnedTemplate t;
  t.volume_radius = std::cbrt(3.0 * chosen->shape_mass.volume / (4.0 * std::numbers::pi));
  t.low = std::numeric_limits<double>::infinity();
  t.high = -t.low;
  for (std::size_t i = 0; i < chosen->body.centres.size(); ++i) {
    t.centres.push_back(frame * chosen->body.centres[i]);
    t.radii.push_back(chosen->body.radii[i]);
    t.low = std::min(t.low, t.centres.back().z() - t.radii.back());
    t.high = std::max(t.high, t.centres.back().z() + t.radii.back());
  }
  return t;
}

}  // namespace

double bms_template_half_height(const BmsConfig& config) {
  const TurnedTemplate t = turned_template(config);
  return 0.5 * (t.high - t.low);
}

PlateParticle bms_template(const MaterialTable& materials, const BmsConfig& config,
                           const std::string& name, BmsParticleInfo* info, int stack) {
  config.bond.check();
  const TurnedTemplate t = turned_template(config);
  const int material = materials.index_of(config.material);
  const double density = materials.material(material).density;
  PlateParticle particle;
  for (std::size_t i = 0; i < t.centres.size(); ++i) {
    particle.spheres.add_sphere(t.centres[i].x(), t.centres[i].y(), t.centres[i].z() - t.low,
                                t.radii[i], density, material);
    particle.spheres.body.back() = 0;
  }
  particle.spheres = stacked(particle.spheres, stack, t.volume_radius);
  particle.bonds = create_bonds(particle.spheres, config.bond_multiplier, config.bond,
                                std::vector<std::string>(static_cast<std::size_t>(stack), name));
  if (info) {
    double mean = 0.0;
    for (double r : t.radii)
      mean += r / static_cast<double>(t.radii.size());
    info->sub_sphere_radius = mean;
    info->spheres = particle.spheres.size() / static_cast<std::size_t>(stack);
    info->bonds = particle.bonds.size() / static_cast<std::size_t>(stack);
  }
  return particle;
}

PlateParticle bms_particle(const MaterialTable& materials, double radius, const BmsConfig& config,
                           const std::string& name, BmsParticleInfo* info, BmsFillCache* cache,
                           int stack) {
  return config.templates.empty() ? bms_sphere(materials, radius, config, name, info, cache, stack)
                                  : bms_template(materials, config, name, info, stack);
}

}  // namespace shapepress::scenarios
