// The plate config written back (plate_config_toml, calibrate's calibrated.toml) reads back to the
// same normal law and parameters, and the law's keys are documented from the law itself.
#include <gtest/gtest.h>

#include <string>
#include <variant>

#include "common/config.hpp"
#include "common/error.hpp"
#include "scenarios/config_io.hpp"
#include "simulate/contact_law_config.hpp"

namespace shapepress::scenarios {
namespace {

const std::string config = R"(
[[material]]
name = "avicel"
youngs_modulus = "2.58e8 Pa"
poisson_ratio = 0.30
density = "1541.1 kg/m^3"

[[material]]
name = "tool"
youngs_modulus = "7.62e10 Pa"
poisson_ratio = 0.31
density = "7800 kg/m^3"

[[interaction]]
first = "avicel"
second = "avicel"
restitution = 0.352
sliding_friction = 0.561
rolling_friction = 0.3
normal_law = "multicontact"
plasticity_ratio = 0.3
loading_stiffness = 1.5e6
adhesion_stiffness = 2e5
pull_off_force = "-0.1 mN"
multicontact_prefactor = 1.3

[[interaction]]
first = "avicel"
second = "tool"
restitution = 0.352
sliding_friction = 0.707
effective_modulus = "1 GPa"

[sphere]
radius = "0.2 mm"
material = "avicel"

[plate]
material = "tool"
speed = "1 mm/s"
)";

TEST(PlateConfigToml, MulticontactLawAndParametersReadBack) {
  const PlateConfig first = read_plate_config(ConfigTable::parse(config, "first.toml"));
  const ConfigTable written = ConfigTable::parse(plate_config_toml(first), "written.toml");
  const PlateConfig second = read_plate_config(written);
  written.check_unknown_keys();
  ASSERT_EQ(second.materials.interactions.size(), 2u);
  const Interaction& a = first.materials.interactions[0];
  const Interaction& b = second.materials.interactions[0];
  ASSERT_TRUE(std::holds_alternative<MulticontactLaw>(b.normal_law));
  const MulticontactParameters& p = std::get<MulticontactLaw>(a.normal_law).parameters;
  const MulticontactParameters& q = std::get<MulticontactLaw>(b.normal_law).parameters;
  EXPECT_EQ(q.plasticity_ratio, p.plasticity_ratio);
  EXPECT_EQ(q.plasticity_ratio, 0.3);
  ASSERT_TRUE(q.loading_stiffness.has_value());
  EXPECT_EQ(*q.loading_stiffness, 1.5e6);
  EXPECT_EQ(q.adhesion_stiffness, 2e5);
  EXPECT_EQ(q.pull_off_force, p.pull_off_force);
  EXPECT_EQ(q.pull_off_force, -1e-4);
  EXPECT_EQ(q.prefactor, 1.3);
  // The Hertz pair stays Hertz, its stated E* kept.
  const Interaction& c = second.materials.interactions[1];
  EXPECT_TRUE(std::holds_alternative<HertzLaw>(c.normal_law));
  ASSERT_TRUE(c.effective_modulus.has_value());
  EXPECT_EQ(*c.effective_modulus, 1e9);
  // Written twice, the same text.
  EXPECT_EQ(plate_config_toml(second), plate_config_toml(first));
}

TEST(PlateConfigToml, AbsentLoadingStiffnessStaysAbsent) {
  std::string text = config;
  text.erase(text.find("loading_stiffness = 1.5e6\n"),
             std::string("loading_stiffness = 1.5e6\n").size());
  const PlateConfig first = read_plate_config(ConfigTable::parse(text, "first.toml"));
  const PlateConfig second =
      read_plate_config(ConfigTable::parse(plate_config_toml(first), "written.toml"));
  EXPECT_FALSE(std::get<MulticontactLaw>(second.materials.interactions[0].normal_law)
                   .parameters.loading_stiffness.has_value());
}

TEST(NormalLawOptions, EveryLawKeyIsDocumentedOnce) {
  const std::vector<OptionDoc> rows = normal_law_options();
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.front().key, "normal_law");
  for (const std::string key : {"plasticity_ratio", "loading_stiffness", "adhesion_stiffness",
                                "pull_off_force", "multicontact_prefactor"}) {
    int found = 0;
    for (const OptionDoc& row : rows)
      if (row.key == key) {
        ++found;
        EXPECT_FALSE(row.help.empty()) << key;
        EXPECT_FALSE(row.range.empty()) << key;
      }
    EXPECT_EQ(found, 1) << key;
  }
}

TEST(NormalLawOptions, AKeyOfAnotherLawNamesThatLaw) {
  const ConfigTable t =
      ConfigTable::parse("normal_law = \"hertz\"\nmulticontact_prefactor = 1\n", "i.toml");
  try {
    read_normal_law(t, "interaction a–b");
    ADD_FAILURE() << "a multi-contact key under a Hertz pair was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("normal_law = \"multicontact\""), std::string::npos);
  }
  // With the law replaced (plate --model multicontact) the same table is read.
  EXPECT_TRUE(std::holds_alternative<MulticontactLaw>(
      read_normal_law(t, "interaction a–b", std::string("multicontact"))));
}

}  // namespace
}  // namespace shapepress::scenarios
