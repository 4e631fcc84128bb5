// The parameters a compaction calibration fits, on a compact config
// (scenarios/calibrate_compaction.hpp): a multi-contact parameter moves in every interaction of
// the particles, E is the particle material's, and a config that takes k1 from E starts from
// Hertz's k1 for its mean size.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>
#include <variant>

#include "common/config.hpp"
#include "common/error.hpp"
#include "scenarios/calibrate_compaction.hpp"
#include "scenarios/config_io.hpp"
#include "tests/support/files.hpp"

namespace shapepress::scenarios {
namespace {

CompactConfig bed(const std::string& text) {
  const ConfigTable root = ConfigTable::parse(text, "bed.toml");
  CompactConfig c = read_compact_config(root);
  root.check_unknown_keys();
  return c;
}

const std::string shipped = shapepress::testing::test_data_text("scenarios/calibration-bed.toml");

double k1_of(const Interaction& in) {
  return *std::get<MulticontactLaw>(in.normal_law).parameters.loading_stiffness;
}

TEST(CompactionParameters, MultiContactParametersMoveInEveryParticleInteraction) {
  CompactConfig c = bed(shipped);
  EXPECT_DOUBLE_EQ(get_parameter(c, "loading_stiffness"), 2e6);
  set_parameter(c, "loading_stiffness", 3e6);
  set_parameter(c, "plasticity_ratio", 0.5);
  set_parameter(c, "multicontact_prefactor", 2.0);
  ASSERT_EQ(c.materials.interactions.size(), 2u);  // avicel–avicel and avicel–tool
  for (const Interaction& in : c.materials.interactions) {
    EXPECT_DOUBLE_EQ(k1_of(in), 3e6);
    const auto& p = std::get<MulticontactLaw>(in.normal_law).parameters;
    EXPECT_DOUBLE_EQ(p.plasticity_ratio, 0.5);
    EXPECT_DOUBLE_EQ(p.prefactor, 2.0);
  }
  set_parameter(c, "youngs_modulus", 1e9);
  EXPECT_DOUBLE_EQ(get_parameter(c, "youngs_modulus"), 1e9);
  for (const Material& m : c.materials.materials)
    if (m.name == "tool") {
      EXPECT_DOUBLE_EQ(m.youngs_modulus, 7.62e10);  // the walls' stays
    }
  // The calibrated config written and read back carries the fitted values.
  const CompactConfig again = bed(compact_config_toml(c));
  EXPECT_DOUBLE_EQ(get_parameter(again, "loading_stiffness"), 3e6);
  EXPECT_DOUBLE_EQ(get_parameter(again, "plasticity_ratio"), 0.5);
}

TEST(CompactionParameters, KOneFromEStartsAtHertzForTheMeanSize) {
  const CompactConfig c =
      bed(std::regex_replace(shipped, std::regex("loading_stiffness = 2e6\n"), ""));
  // E* = E / (2 (1 - ν²)) of two avicel spheres, R* = d/4 for d = (250 + 350)/2 µm.
  const double e_star = 2.58e8 / (2.0 * (1.0 - 0.09));
  EXPECT_NEAR(get_parameter(c, "loading_stiffness"), 4.0 / 3.0 * e_star * std::sqrt(75e-6),
              1e-9 * 1.6e6);
}

// One material (docs/models.md): a k1 fitted for the bed's mean size is stated as the loading
// modulus it implies there, and back; a fitted loading modulus moves the k1 of every contact and
// the bonds stated as a fraction of it.
TEST(CompactionParameters, ALoadingModulusCarriesTheFitToEveryContactAndTheBonds) {
  const double d = 250e-6, nu = 0.3;
  const double k1 = 1.0307e7;
  const double modulus = implied_loading_modulus(k1, d, nu);
  EXPECT_NEAR(implied_loading_stiffness(modulus, d, nu), k1, 1e-9 * k1);
  EXPECT_NEAR(k1, 4.0 / 3.0 * modulus / (2.0 * (1.0 - nu * nu)) * std::sqrt(d / 4.0), 1e-9 * k1);
  // The spheres' k1 at 250 µm is a solid of about 1.8 GPa: 6.9 times Table 3's 258 MPa.
  EXPECT_NEAR(modulus / 2.58e8, 6.9, 0.1);
  std::string text = std::regex_replace(shipped, std::regex("loading_stiffness = 2e6\n"), "");
  text = std::regex_replace(text, std::regex("(density = [^\n]*\n)"),
                            "$1loading_modulus = \"1 GPa\"\n",
                            std::regex_constants::format_first_only);
  CompactConfig c = bed(text + "\n[bond]\nmodulus_fraction = 0.25\n");
  EXPECT_DOUBLE_EQ(get_parameter(c, "loading_modulus"), 1e9);
  ASSERT_TRUE(c.bond);
  EXPECT_DOUBLE_EQ(c.bond->modulus, 2.5e8);
  set_parameter(c, "loading_modulus", 2e9);
  EXPECT_DOUBLE_EQ(c.bond->modulus, 5e8);
  EXPECT_DOUBLE_EQ(get_parameter(bed(compact_config_toml(c)), "loading_modulus"), 2e9);
}

// The bodies' bonds as the compaction fits them: Ē (with its fraction of the solid's modulus)
// and an elastic_plastic model's yield, by the plate calibration's names; elastic bonds have no
// yield to fit.
TEST(CompactionParameters, BondModulusAndYieldAreFittedByTheirPlateNames) {
  std::string text = std::regex_replace(shipped, std::regex("(density = [^\n]*\n)"),
                                        "$1loading_modulus = \"1 GPa\"\n",
                                        std::regex_constants::format_first_only);
  CompactConfig plastic = bed(text +
                              "\n[bond]\nmodulus_fraction = 0.25\nmodel = \"elastic_plastic\"\n"
                              "yield_stress = \"5 MPa\"\nhardening_ratio = 0.1\n");
  EXPECT_DOUBLE_EQ(get_parameter(plastic, "modulus"), 2.5e8);
  set_parameter(plastic, "modulus", 5e8);
  EXPECT_DOUBLE_EQ(plastic.bond->modulus_fraction, 0.5);
  EXPECT_DOUBLE_EQ(get_parameter(plastic, "yield_stress"), 5e6);
  set_parameter(plastic, "yield_stress", 7e6);
  set_parameter(plastic, "hardening_ratio", 0.2);
  const CompactConfig again = bed(compact_config_toml(plastic));
  EXPECT_DOUBLE_EQ(get_parameter(again, "yield_stress"), 7e6);
  EXPECT_DOUBLE_EQ(get_parameter(again, "hardening_ratio"), 0.2);
  CompactConfig elastic = bed(text + "\n[bond]\nmodulus_fraction = 0.25\n");
  EXPECT_THROW(get_parameter(elastic, "yield_stress"), InputError);
  EXPECT_THROW(set_parameter(elastic, "normal_stiffness", 1e6), InputError);  // Ē form
  EXPECT_THROW(get_parameter(elastic, "radius_multiplier"), InputError);      // the FEM fit's
}

TEST(CompactionParameters, UnknownOrAbsentParametersAreInputErrors) {
  CompactConfig c = bed(shipped);
  EXPECT_THROW(get_parameter(c, "stiffness"), InputError);
  EXPECT_THROW(set_parameter(c, "normal_stiffness", 1e6), InputError);  // no [bond]
  CompactConfig hertz = bed(std::regex_replace(
      std::regex_replace(shipped, std::regex("normal_law = \"multicontact\"\n"), ""),
      std::regex("(plasticity_ratio|multicontact_prefactor|loading_stiffness) = [^\n]*\n"), ""));
  EXPECT_THROW(get_parameter(hertz, "plasticity_ratio"), InputError);
}

}  // namespace
}  // namespace shapepress::scenarios
