#pragma once
// A conventional multi-sphere (CMS) particle for the plate rig: the sphere filled with
// overlapping sub-spheres by the geometry stage's CMS filler (geometry::fill_rigid, the same
// mechanism `shapepress fill --method cms` uses), made one rigid clump (clumps.hpp).
#include <string>
#include "scenarios/namespaces.hpp"

#include "scenarios/config_io.hpp"
#include "scenarios/plate.hpp"

namespace shapepress::scenarios {

struct CmsParticleInfo {
  std::size_t spheres = 0;  // sub-spheres the filler gave (it may give fewer than asked)
  double min_radius = 0.0, max_radius = 0.0;  // m
  double volume = 0.0;                        // m³, of the union
  double mass = 0.0;                          // kg
};

// Sub-spheres of `config.material` (default: the sphere's) filling a sphere of `radius` centred
// at (0, 0, radius), one clump named `name` of the material's density. InputError for a clump
// the engine cannot take (clump_geometry).
PlateParticle cms_sphere(const MaterialTable& materials, double radius, const CmsConfig& config,
                         const std::string& name, CmsParticleInfo* info = nullptr);

}  // namespace shapepress::scenarios
