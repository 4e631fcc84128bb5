#pragma once
// A bonded multi-sphere (BMS) particle for the plate rig: the sphere filled with touching
// sub-spheres by the geometry stage's filler (geometry/sphere_fill.hpp, the same mechanism
// `shapepress fill` uses), bonded by Eq. 10 (create_bonds).
#include <string>

#include "simulate/config_io.hpp"
#include "simulate/plate.hpp"

namespace shapepress::simulate {

struct BmsParticleInfo {
  double sub_sphere_radius = 0.0;  // m
  std::size_t spheres = 0;
  std::size_t bonds = 0;
};

// Sub-spheres of `config.material` (default: the sphere's) filling a sphere of `radius` centred
// at (0, 0, radius), all of body 0 named `name`. InputError for a bad count, m_b, stiffness, or
// a sub-sphere left unbonded.
PlateParticle bms_sphere(const MaterialTable& materials, double radius, const BmsConfig& config,
                         const std::string& name, BmsParticleInfo* info = nullptr);

}  // namespace shapepress::simulate
