// The plate and compact configs through their option tables: every key read, written as the
// effective config and read back to the same values; keys a stage does not use refused by name.
#include "scenarios/config_io.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <variant>

#include "common/error.hpp"
#include "tests/support/errors.hpp"

namespace shapepress::scenarios {
namespace {

using ::testing::HasSubstr;

const std::string materials = R"(
[[material]]
name = "rubber"
youngs_modulus = "18.5 MPa"
poisson_ratio = 0.46
density = "1100 kg/m^3"

[[material]]
name = "steel"
youngs_modulus = "210 GPa"
poisson_ratio = 0.3
density = 7800

[[interaction]]
first = "rubber"
second = "rubber"
restitution = 0.7
sliding_friction = 0.5
rolling_friction = 0.01

[[interaction]]
first = "rubber"
second = "steel"
restitution = 0.9
sliding_friction = 0.3
effective_modulus = "2e7 Pa"
normal_law = "multicontact"
plasticity_ratio = 0.5
adhesion_stiffness = 1e3
pull_off_force = -1e-3
)";

// Every plate key, none at its default.
const std::string plate_text = materials + R"(
[run]
time_step = "2e-7 s"
time_step_fraction = 0.15
skin = "0.05 mm"
max_overlap_fraction = 0.8
local_damping = 0.3

[sphere]
radius = "10 mm"
material = "rubber"

[plate]
material = "steel"
speed = "0.2 m/s"
max_deformation = 0.3
records = 12
ramp = 0.01
symmetric = true
final_speed = "0.5 m/s"

[bms]
count = 321
lattice = "random"
placement = "centre"
seed = 7
fills = 3
bond_multiplier = 1.2
material = "steel"

[bond]
modulus = "3.7e7 Pa"
shear_ratio = 0.6
radius_multiplier = 0.9
tensile_strength = "1 MPa"
shear_strength = "2 MPa"
damping_ratio = 0.1
contact_when_bonded = false

[cms]
count = 40
resolution = 32
min_radius_fraction = 0.1
match_volume = false
integration_cells = 64
material = "steel"
)";

PlateConfig read_plate(const std::string& text) {
  const ConfigTable root = ConfigTable::parse(text, "plate.toml");
  PlateConfig c = read_plate_config(root);
  root.check_unknown_keys();
  return c;
}

using testing::input_error_of;

TEST(PlateConfig, EveryKeyRoundTripsThroughTheEffectiveConfig) {
  const PlateConfig a = read_plate(plate_text);
  EXPECT_EQ(*a.run.skin, 0.05e-3);
  EXPECT_EQ(a.run.engine.local_damping, 0.3);
  EXPECT_EQ(a.setup.final_speed, 0.5);
  const std::string written = plate_config_toml(a);
  const PlateConfig b = read_plate(written);
  EXPECT_EQ(plate_config_toml(b), written);  // a fixed point: nothing lost, nothing added
  EXPECT_EQ(b.run.time_step, a.run.time_step);
  EXPECT_EQ(b.run.time_step_fraction, a.run.time_step_fraction);
  EXPECT_EQ(b.run.skin, a.run.skin);
  EXPECT_EQ(b.run.engine.max_overlap_fraction, a.run.engine.max_overlap_fraction);
  EXPECT_EQ(b.run.engine.local_damping, a.run.engine.local_damping);
  EXPECT_EQ(b.setup.radius, a.setup.radius);
  EXPECT_EQ(b.setup.sphere_material, a.setup.sphere_material);
  EXPECT_EQ(b.setup.plate_material, a.setup.plate_material);
  EXPECT_EQ(b.setup.speed, a.setup.speed);
  EXPECT_EQ(b.setup.ramp, a.setup.ramp);
  EXPECT_EQ(b.setup.symmetric, a.setup.symmetric);
  EXPECT_EQ(b.setup.final_speed, a.setup.final_speed);
  EXPECT_EQ(b.setup.max_deformation, a.setup.max_deformation);
  EXPECT_EQ(b.setup.records, a.setup.records);
  ASSERT_TRUE(b.bms && b.cms);
  EXPECT_EQ(b.bms->count, 321);
  EXPECT_EQ(b.bms->lattice, "random");
  EXPECT_EQ(b.bms->placement, "centre");
  EXPECT_EQ(b.bms->seed, 7u);
  EXPECT_EQ(b.bms->fills, 3);
  EXPECT_EQ(b.bms->bond_multiplier, 1.2);
  EXPECT_EQ(b.bms->material, "steel");
  EXPECT_EQ(b.bms->bond.modulus, 3.7e7);
  EXPECT_EQ(b.bms->bond.shear_ratio, 0.6);
  EXPECT_EQ(b.bms->bond.radius_multiplier, 0.9);
  EXPECT_EQ(b.bms->bond.tensile_strength, 1e6);
  EXPECT_EQ(b.bms->bond.shear_strength, 2e6);
  EXPECT_EQ(b.bms->bond.damping_ratio, 0.1);
  EXPECT_FALSE(b.bms->bond.contact_when_bonded);
  EXPECT_EQ(b.cms->count, 40);
  EXPECT_EQ(b.cms->resolution, 32);
  EXPECT_EQ(b.cms->min_radius_fraction, 0.1);
  EXPECT_FALSE(b.cms->match_volume);
  EXPECT_EQ(b.cms->integration_cells, 64);
  ASSERT_EQ(b.materials.interactions.size(), 2u);
  const Interaction& in = b.materials.interactions[1];
  EXPECT_EQ(*in.effective_modulus, 2e7);
  ASSERT_TRUE(std::holds_alternative<MulticontactLaw>(in.normal_law));
  EXPECT_EQ(std::get<MulticontactLaw>(in.normal_law).parameters.plasticity_ratio, 0.5);
  EXPECT_EQ(std::get<MulticontactLaw>(in.normal_law).parameters.pull_off_force, -1e-3);
  EXPECT_EQ(b.materials.interactions[0].rolling_friction, 0.01);
  EXPECT_EQ(b.materials.materials[1].density, 7800.0);
}

TEST(PlateConfig, StiffnessFormOfTheBondRoundTrips) {
  std::string text = plate_text;
  text.replace(text.find("modulus = \"3.7e7 Pa\"\nshear_ratio = 0.6"),
               std::string("modulus = \"3.7e7 Pa\"\nshear_ratio = 0.6").size(),
               "normal_stiffness = 1.15e6\nshear_stiffness = 1.25e6");
  const PlateConfig a = read_plate(text);
  const std::string written = plate_config_toml(a);
  EXPECT_THAT(written, ::testing::Not(HasSubstr("modulus = 0")));
  const PlateConfig b = read_plate(written);
  EXPECT_EQ(b.bms->bond.normal_stiffness, 1.15e6);
  EXPECT_EQ(b.bms->bond.shear_stiffness, 1.25e6);
  EXPECT_EQ(b.bms->bond.modulus, 0.0);
  EXPECT_THAT(input_error_of([&] {
                text.replace(text.find("normal_stiffness"), 0, "shear_ratio = 1\n");
                read_plate(text);
              }),
              HasSubstr("bond.shear_ratio"));
}

// [bond] model: the default writes no line (its configs stay as they were); elastic_plastic
// round-trips with its keys; a bad value, a key of another model or an unknown model is an
// InputError naming the key (exit 2).
TEST(PlateConfig, TheBondModelRoundTripsAndBadValuesAreRefusedByName) {
  EXPECT_THAT(plate_config_toml(read_plate(plate_text)), ::testing::Not(HasSubstr("model")));
  const auto with_bond_keys = [](const std::string& keys) {
    std::string text = plate_text;
    text.replace(text.find("[bond]\n"), 7, "[bond]\n" + keys);
    return text;
  };
  const PlateConfig a = read_plate(with_bond_keys(
      "model = \"elastic_plastic\"\nyield_stress = \"20 MPa\"\nhardening_ratio = 0.1\n"));
  const auto& plastic = std::get<ElasticPlasticBond>(a.bms->bond.model);
  EXPECT_EQ(plastic.yield_stress, 2e7);
  EXPECT_EQ(plastic.shear_yield_stress, std::numeric_limits<double>::infinity());
  EXPECT_EQ(plastic.hardening_ratio, 0.1);
  const std::string written = plate_config_toml(a);
  EXPECT_THAT(written,
              HasSubstr("model = \"elastic_plastic\"\nyield_stress = 20000000\n"
                        "shear_yield_stress = inf\nhardening_ratio = 0.10000000000000001"));
  const PlateConfig b = read_plate(written);
  EXPECT_TRUE(b.bms->bond.model == a.bms->bond.model);
  EXPECT_EQ(plate_config_toml(b), written);
  EXPECT_THAT(input_error_of([&] {
                read_plate(with_bond_keys("model = \"elastic_plastic\"\nyield_stress = -1\n"));
              }),
              HasSubstr("bond.yield_stress"));
  EXPECT_THAT(input_error_of([&] {
                read_plate(with_bond_keys("model = \"elastic_plastic\"\nhardening_ratio = -0.5\n"));
              }),
              HasSubstr("bond.hardening_ratio"));
  EXPECT_THAT(
      input_error_of([&] { read_plate(with_bond_keys("shear_yield_stress = \"1 MPa\"\n")); }),
      HasSubstr("shear_yield_stress need model = \"elastic_plastic\""));
  EXPECT_THAT(input_error_of([&] { read_plate(with_bond_keys("model = \"plastic\"\n")); }),
              HasSubstr("bond.model"));
}

TEST(PlateConfig, RunKeysThePlateRigDoesNotUseAreRefusedByName) {
  for (const char* key :
       {"steps = 10", "record_every = 5", "snapshot_every = 5", "gravity = [0, 0, -9.81]"}) {
    std::string text = plate_text;
    text.replace(text.find("[run]\n"), 6, "[run]\n" + std::string(key) + "\n");
    const std::string message = input_error_of([&] { read_plate(text); });
    const std::string name(key, std::string(key).find(' '));
    EXPECT_THAT(message, HasSubstr("'run." + name + "' is not used")) << key;
  }
}

TEST(PlateConfig, DefaultsAreWrittenToo) {
  const PlateConfig a = read_plate(materials + R"(
[sphere]
radius = "1 mm"
material = "rubber"
[plate]
material = "steel"
speed = 0.01
)");
  const std::string written = plate_config_toml(a);
  EXPECT_THAT(written, HasSubstr("time_step_fraction = 0.2\n"));
  EXPECT_THAT(written, HasSubstr("max_deformation = 0.01\n"));
  EXPECT_THAT(written, HasSubstr("records = 50\n"));
  EXPECT_EQ(plate_config_toml(read_plate(written)), written);
}

const std::string compact_text = materials + R"(
[run]
time_step_fraction = 0.1
steps = 5000
record_every = 20
snapshot_every = 1000
skin = "0.1 mm"
gravity = [0.0, 0.0, -9.81]
max_overlap_fraction = 0.9
local_damping = 0.2

[box]
x = "6 mm"
y = "5 mm"
bottom = "1 mm"
punch = "20 mm"

[particles]
material = "rubber"

[walls]
material = "steel"

[punch]
speed = "0.5 m/s"
target_strain = 0.1
hold_time = "0.5 ms"
unload_speed = "0.4 m/s"
strain_reference = "fill"
max_solid_fraction = 0.7

[generate]
count = 150
diameter_min = "0.8 mm"
size_quantiles = ["0.9 mm", "1.1 mm"]
size_quantile_levels = [0.2, 0.8]
size_weighting = "number"
diameter_max = "1.2 mm"
seed = 3
height = "15 mm"
settle_time = "20 ms"
settle_friction = 0.9

[clumps]
count = 4
seed = 2
integration_cells = 32
spheres = [0, 0, 0, 1e-4, 1e-4, 0, 0, 1e-4]
)";

CompactConfig read_compact(const std::string& text) {
  const ConfigTable root = ConfigTable::parse(text, "compact.toml");
  CompactConfig c = read_compact_config(root);
  root.check_unknown_keys();
  return c;
}

TEST(CompactConfig, EveryKeyRoundTripsThroughTheEffectiveConfig) {
  const CompactConfig a = read_compact(compact_text);
  EXPECT_EQ(a.setup.max_steps, 5000);
  EXPECT_EQ(a.run.engine.gravity[2], -9.81);
  EXPECT_EQ(a.setup.strain_reference, CompactionSetup::StrainReference::fill);
  EXPECT_DOUBLE_EQ(a.generate->z_high, 16e-3);
  const std::string written = compact_config_toml(a);
  const CompactConfig b = read_compact(written);
  EXPECT_EQ(compact_config_toml(b), written);
  EXPECT_EQ(b.run.skin, a.run.skin);
  EXPECT_EQ(b.run.time_step_fraction, a.run.time_step_fraction);
  EXPECT_EQ(b.run.engine.gravity, a.run.engine.gravity);
  EXPECT_EQ(b.run.engine.max_overlap_fraction, a.run.engine.max_overlap_fraction);
  EXPECT_EQ(b.run.engine.local_damping, a.run.engine.local_damping);
  EXPECT_EQ(b.setup.max_steps, a.setup.max_steps);
  EXPECT_EQ(b.setup.record_every, a.setup.record_every);
  EXPECT_EQ(b.setup.snapshot_every, a.setup.snapshot_every);
  EXPECT_EQ(b.box_x, a.box_x);
  EXPECT_EQ(b.box_y, a.box_y);
  EXPECT_EQ(b.bottom, a.bottom);
  EXPECT_EQ(b.punch, a.punch);
  EXPECT_EQ(b.particle_material, "rubber");
  EXPECT_EQ(b.wall_material, "steel");
  EXPECT_EQ(b.setup.program.speed, a.setup.program.speed);
  EXPECT_EQ(b.setup.program.hold_time, a.setup.program.hold_time);
  EXPECT_EQ(b.setup.program.unload_speed, a.setup.program.unload_speed);
  EXPECT_EQ(b.target_strain, a.target_strain);
  EXPECT_EQ(b.setup.max_solid_fraction, 0.7);
  EXPECT_EQ(b.generate->count, 150);
  EXPECT_EQ(b.generate->diameter_min, a.generate->diameter_min);
  EXPECT_EQ(b.generate->diameter_max, a.generate->diameter_max);
  EXPECT_EQ(b.generate->seed, 3u);
  EXPECT_EQ(b.generate->z_low, a.generate->z_low);
  EXPECT_EQ(b.generate->z_high, a.generate->z_high);
  EXPECT_EQ(b.generate->sizes->diameters, a.generate->sizes->diameters);
  EXPECT_EQ(b.generate->sizes->levels, a.generate->sizes->levels);
  EXPECT_FALSE(b.generate->sizes->volume_weighted);
  EXPECT_EQ(b.settle_time, a.settle_time);
  EXPECT_EQ(b.settle_friction, a.settle_friction);
  EXPECT_EQ(b.clumps->count, 4);
  EXPECT_EQ(b.clumps->spheres, a.clumps->spheres);
}

TEST(CompactConfig, ServoKeysAreRefusedInDisplacementModeAndTheOtherWay) {
  std::string text = compact_text;
  text.replace(text.find("max_solid_fraction = 0.7"), 24, "max_speed = 1");
  EXPECT_THAT(input_error_of([&] { read_compact(text); }),
              HasSubstr("'punch.max_speed' is not used with punch.mode = \"displacement\""));
  text = compact_text;
  text.replace(text.find("[punch]\n"), 8,
               "[punch]\nmode = \"servo\"\ntarget_stress = \"1 MPa\"\nmax_speed = 1\n");
  EXPECT_THAT(input_error_of([&] { read_compact(text); }),
              HasSubstr("'punch.speed' is not used with punch.mode = \"servo\""));
}

TEST(ConfigOptions, EveryStageDocumentsItsSections) {
  const StageOptions plate = plate_config_options();
  std::vector<std::string> names;
  for (const OptionSection& s : plate.sections)
    names.push_back(s.name);
  EXPECT_THAT(names, ::testing::ElementsAre("material", "interaction", "run", "sphere", "plate",
                                            "bms", "bond", "cms"));
  EXPECT_THAT(options_markdown(compact_config_options()), HasSubstr("| `size_quantiles` |"));
}

}  // namespace
}  // namespace shapepress::scenarios
