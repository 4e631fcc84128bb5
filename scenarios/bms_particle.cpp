#include "scenarios/bms_particle.hpp"

#include <fmt/format.h>

#include "geometry/signed_distance.hpp"
#include "geometry/sphere_fill.hpp"

namespace shapepress::scenarios {

PlateParticle bms_sphere(const MaterialTable& materials, double radius, const BmsConfig& config,
                         const std::string& name, BmsParticleInfo* info, BmsFillCache* cache) {
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
  particle.bonds = create_bonds(particle.spheres, config.bond_multiplier, config.bond, {name});
  if (info) {
    info->sub_sphere_radius = particle.spheres.size() == 0 ? 0.0 : particle.spheres.radius[0];
    info->spheres = particle.spheres.size();
    info->bonds = particle.bonds.size();
  }
  return particle;
}

}  // namespace shapepress::scenarios
