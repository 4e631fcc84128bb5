// calibrate's parameters on a config (simulate/calibrate.hpp): the sub-spheres' contact modulus
// is their own material's, never the sphere's (the Hertz and Tatara references keep the bulk E).
#include <gtest/gtest.h>

#include <string>
#include <variant>

#include "common/config.hpp"
#include "common/error.hpp"
#include "scenarios/bms_particle.hpp"
#include "scenarios/calibrate.hpp"
#include "scenarios/config_io.hpp"

namespace shapepress::scenarios {
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

TEST(CalibrateParameters, APlatePairsStatedModulusSurvivesTheCalibratedToml) {
  // calibrated.toml is plate_config_toml of the fitted config: a stated E* of an interaction
  // (the plates' stiff contact with the sub-spheres) must come back from it.
  PlateConfig c = config_with("rubber-contact", true);
  Interaction plate{"rubber-contact", "wall", 0.7, 0.5};
  plate.effective_modulus = 1e9;
  c.materials.interactions.push_back(plate);
  c.materials.interactions.push_back({"rubber-contact", "rubber-contact", 0.7, 0.5});
  const PlateConfig again =
      read_plate_config(ConfigTable::parse(plate_config_toml(c), "calibrated.toml"));
  int stated = 0;
  for (const Interaction& in : again.materials.interactions)
    if (in.effective_modulus) {
      ++stated;
      EXPECT_EQ(in.first, "rubber-contact");
      EXPECT_EQ(in.second, "wall");
      EXPECT_DOUBLE_EQ(*in.effective_modulus, 1e9);
    }
  EXPECT_EQ(stated, 1);
  const MaterialTable table = again.materials.table();
  EXPECT_DOUBLE_EQ(
      table.pair(table.index_of("rubber-contact"), table.index_of("wall")).effective_modulus, 1e9);
}

TEST(CalibrateParameters, ANonPositiveStatedModulusNamesTheKey) {
  const std::string text = R"(
[[material]]
name = "m"
youngs_modulus = "18.5 MPa"
poisson_ratio = 0.46
density = "2000 kg/m^3"
[[interaction]]
first = "m"
second = "m"
restitution = 0.7
sliding_friction = 0.5
effective_modulus = "-1 GPa"
[sphere]
radius = "10 mm"
material = "m"
[plate]
material = "m"
speed = "0.4 m/s"
)";
  try {
    read_plate_config(ConfigTable::parse(text, "bad.toml"));
    FAIL() << "a negative effective_modulus was taken";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("effective_modulus"), std::string::npos)
        << error.what();
  }
}

TEST(CalibrateFills, TheCacheFillsOncePerKeyAndGivesTheSameSubSpheres) {
  // calibrate presses the same fills at every evaluation: a fill is made once per (count,
  // lattice, seed, …) and the cached sub-spheres are the bits a fresh fill gives, whatever the
  // bond parameters.
  BmsFillCache cache;
  int made = 0;
  const auto make = [&] {
    ++made;
    SphereState s;
    s.add_sphere(0, 0, 0, 1e-3, 2000.0, 0);
    return s;
  };
  EXPECT_EQ(cache.get("a", make).size(), 1u);
  EXPECT_EQ(cache.get("a", make).size(), 1u);
  EXPECT_EQ(made, 1);
  cache.get("b", make);
  EXPECT_EQ(made, 2);
  EXPECT_EQ(cache.size(), 2u);

  PlateConfig c = config_with("rubber-contact", true);
  c.bms->lattice = "random";
  c.bms->count = 60;
  const MaterialTable table = c.materials.table();
  BmsFillCache fills;
  const PlateParticle fresh = bms_sphere(table, c.setup.radius, *c.bms, "p");
  const PlateParticle first = bms_sphere(table, c.setup.radius, *c.bms, "p", nullptr, &fills);
  c.bms->bond.modulus = 9e6;  // other bonds, the same fill
  const PlateParticle again = bms_sphere(table, c.setup.radius, *c.bms, "p", nullptr, &fills);
  EXPECT_EQ(fills.size(), 1u);
  EXPECT_EQ(first.spheres.position, fresh.spheres.position);
  EXPECT_EQ(again.spheres.position, fresh.spheres.position);
  EXPECT_EQ(again.bonds.first, fresh.bonds.first);
  EXPECT_NE(again.bonds.normal_spring, fresh.bonds.normal_spring);
  c.bms->seed = 2;  // another fill
  bms_sphere(table, c.setup.radius, *c.bms, "p", nullptr, &fills);
  EXPECT_EQ(fills.size(), 2u);
}

TEST(CalibrateParameters, TheBondYieldAndHardeningAreTheElasticPlasticModels) {
  PlateConfig elastic = config_with("rubber-contact", true);
  // Elastic bonds have no yield stress to fit: the error names the model key.
  try {
    set_parameter(elastic, "yield_stress", 1e6);
    FAIL() << "an elastic bond took a yield stress";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("elastic_plastic"), std::string::npos) << error.what();
  }
  PlateConfig plastic = elastic;
  plastic.bms->bond.model = ElasticPlasticBond{2e6, 1e6, 0.1};
  EXPECT_DOUBLE_EQ(get_parameter(plastic, "yield_stress"), 2e6);
  EXPECT_DOUBLE_EQ(get_parameter(plastic, "shear_yield_stress"), 1e6);
  EXPECT_DOUBLE_EQ(get_parameter(plastic, "hardening_ratio"), 0.1);
  set_parameter(plastic, "yield_stress", 3e6);
  set_parameter(plastic, "hardening_ratio", 0.05);
  const auto& bond = std::get<ElasticPlasticBond>(plastic.bms->bond.model);
  EXPECT_DOUBLE_EQ(bond.yield_stress, 3e6);
  EXPECT_DOUBLE_EQ(bond.shear_yield_stress, 1e6);
  EXPECT_DOUBLE_EQ(bond.hardening_ratio, 0.05);
  // calibrated.toml keeps them.
  const PlateConfig again =
      read_plate_config(ConfigTable::parse(plate_config_toml(plastic), "calibrated.toml"));
  EXPECT_EQ(std::get<ElasticPlasticBond>(again.bms->bond.model), bond);
}

PlateRow plate_row(double deformation, double force) {
  PlateRow r;
  r.deformation = deformation;
  r.approach = 0.02 * deformation;
  r.top_force = force;
  return r;
}

TEST(CalibrateUnloading, TheUnloadingErrorIsOverThePeakAndTheResidualWhereTheForceEnds) {
  // Loading to 0.2 in two rows, unloading in two: down a line that lets go at 0.1.
  const std::vector<PlateRow> rows = {plate_row(0.1, 4.0), plate_row(0.2, 10.0),
                                      plate_row(0.1, 0.0), plate_row(0.0, 0.0)};
  const PlateUnloading unloaded = plate_unloading(rows, 2);
  EXPECT_DOUBLE_EQ(unloaded.peak_force, 10.0);
  EXPECT_NEAR(unloaded.residual_deformation, 0.1, 1e-12);
  EXPECT_NEAR(unloaded.residual_approach, 0.002, 1e-15);
  // The same unloading as the reference: no error.
  const std::vector<double> deformation = {0.2, 0.15, 0.1, 0.05, 0.0};
  EXPECT_NEAR(plate_unloading_error(rows, 2, deformation, {10.0, 5.0, 0.0, 0.0, 0.0}), 0.0, 1e-12);
  // A reference 1 N above everywhere from 0.2 to 0: 1 N over its peak of 11 N.
  EXPECT_NEAR(plate_unloading_error(rows, 2, deformation, {11.0, 6.0, 1.0, 1.0, 1.0}), 1.0 / 11.0,
              1e-12);
  // A run without unloading rows is not compared.
  EXPECT_THROW(plate_unloading_error({rows[0], rows[1]}, 2, deformation, {1, 1, 1, 1, 1}),
               InputError);
}

}  // namespace
}  // namespace shapepress::scenarios
