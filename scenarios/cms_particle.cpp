#include "scenarios/cms_particle.hpp"

#include <algorithm>

#include "geometry/signed_distance.hpp"
#include "geometry/sphere_fill.hpp"

namespace shapepress::scenarios {

PlateParticle cms_sphere(const MaterialTable& materials, double radius, const CmsConfig& config,
                         const std::string& name, CmsParticleInfo* info) {
  geometry::RigidFillOptions options;
  options.sphere_count = config.count;
  options.resolution = config.resolution;
  options.min_radius_fraction = config.min_radius_fraction;
  options.match_volume = config.match_volume;
  const geometry::SphereTemplate filled =
      geometry::fill_rigid(geometry::sphere_distance(radius), options);
  const int material = materials.index_of(config.material);
  std::vector<Vector3> centres;
  for (const geometry::Vec3& c : filled.centres)
    centres.push_back({c.x(), c.y(), c.z() + radius});
  PlateParticle particle;
  add_clump(particle.spheres, particle.clumps, centres, filled.radii,
            materials.material(material).density, material, name, config.integration_cells);
  if (info) {
    info->spheres = centres.size();
    const auto [lo, hi] = std::minmax_element(filled.radii.begin(), filled.radii.end());
    info->min_radius = *lo;
    info->max_radius = *hi;
    info->volume = particle.clumps.volume[0];
    info->mass = particle.clumps.mass[0];
  }
  return particle;
}

}  // namespace shapepress::scenarios
