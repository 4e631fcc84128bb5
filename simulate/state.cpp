#include "simulate/state.hpp"

#include <numbers>

namespace shapepress::simulate {

void SphereState::add_sphere(double x, double y, double z, double r, double density,
                             int material_index) {
  const double m = 4.0 / 3.0 * std::numbers::pi * r * r * r * density;
  const std::size_t index = size();
  position.push_back(x, y, z);
  velocity.push_back(0, 0, 0);
  angular_velocity.push_back(0, 0, 0);
  force.push_back(0, 0, 0);
  torque.push_back(0, 0, 0);
  radius.push_back(r);
  mass.push_back(m);
  inverse_mass.push_back(m > 0.0 ? 1.0 / m : 0.0);
  inverse_inertia.push_back(m > 0.0 ? 1.0 / (0.4 * m * r * r) : 0.0);
  material.push_back(material_index);
  body.push_back(static_cast<std::int32_t>(index));
  body_radius.push_back(r);
}

}  // namespace shapepress::simulate
