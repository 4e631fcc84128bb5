// calibrate's parameters on a config (simulate/calibrate.hpp): the sub-spheres' contact modulus
// is their own material's, never the sphere's (the Hertz and Tatara references keep the bulk E).
#include <gtest/gtest.h>

#include <string>

#include "common/config.hpp"
#include "common/error.hpp"
#include "simulate/calibrate.hpp"
#include "simulate/config_io.hpp"

namespace shapepress::simulate {
namespace {

// A BMS plate config whose sub-spheres use `bms_material` ("rubber" is the sphere's), with or
// without a material "rubber-contact" (71 GPa).
PlateConfig config_with(const std::string& bms_material, bool contact_material) {
  const std::string contact = R"(
[[material]]
name = "rubber-contact"
youngs_modulus = "71 GPa"
poisson_ratio = 0.46
density = "2000 kg/m^3"
)";
  const std::string text = R"(
[[material]]
name = "rubber"
youngs_modulus = "18.5 MPa"
poisson_ratio = 0.46
density = "2000 kg/m^3"
)" + (contact_material ? contact : std::string()) +
                           R"(
[[material]]
name = "wall"
youngs_modulus = "1 GPa"
poisson_ratio = 0.3
density = "7800 kg/m^3"
[[interaction]]
first = "rubber"
second = "rubber"
restitution = 0.7
sliding_friction = 0.5
[[interaction]]
first = "rubber"
second = "wall"
restitution = 0.7
sliding_friction = 0.5
[sphere]
radius = "10 mm"
material = "rubber"
[plate]
material = "wall"
speed = "0.4 m/s"
[bms]
count = 100
material = ")" + bms_material +
                           R"("
[bond]
modulus = "4 MPa"
)";
  return read_plate_config(ConfigTable::parse(text, "test.toml"));
}

double modulus_of(const PlateConfig& c, const std::string& name) {
  for (const Material& m : c.materials.materials)
    if (m.name == name) return m.youngs_modulus;
  return -1.0;
}

TEST(CalibrateParameters, ContactModulusIsTheSubSpheresOwnMaterials) {
  // Sub-spheres of their own material (a calibrated config): that material is fitted, no copy.
  PlateConfig own = config_with("rubber-contact", true);
  EXPECT_DOUBLE_EQ(get_parameter(own, "contact_modulus"), 71e9);
  set_parameter(own, "contact_modulus", 90e9);
  EXPECT_DOUBLE_EQ(modulus_of(own, "rubber-contact"), 90e9);
  EXPECT_DOUBLE_EQ(modulus_of(own, "rubber"), 18.5e6);
  EXPECT_EQ(own.materials.materials.size(), 3u);
  EXPECT_EQ(own.bms->material, "rubber-contact");
  // Sub-spheres of the sphere's material: a copy "rubber-contact" is made for them and fitted.
  PlateConfig bulk = config_with("rubber", false);
  set_parameter(bulk, "contact_modulus", 5e9);
  EXPECT_DOUBLE_EQ(modulus_of(bulk, "rubber"), 18.5e6);  // the bulk E stays the references'
  EXPECT_EQ(bulk.bms->material, "rubber-contact");
  EXPECT_DOUBLE_EQ(modulus_of(bulk, "rubber-contact"), 5e9);
  EXPECT_DOUBLE_EQ(get_parameter(bulk, "contact_modulus"), 5e9);
  set_parameter(bulk, "contact_modulus", 6e9);  // the copy is reused, not copied again
  EXPECT_EQ(bulk.materials.materials.size(), 3u);
  // The sphere's material for the sub-spheres while a "rubber-contact" exists: ambiguous.
  PlateConfig clash = config_with("rubber", true);
  EXPECT_THROW(set_parameter(clash, "contact_modulus", 5e9), InputError);
}

}  // namespace
}  // namespace shapepress::simulate
