#include "common/config.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/error.hpp"
#include "tests/support/errors.hpp"

namespace shapepress {
namespace {

using ::testing::HasSubstr;

using testing::input_error_of;

constexpr std::string_view kMaterial = R"(
seed = 7
[material]
youngs_modulus = "2.58e8 Pa"
poisson_ratio = 0.3
density = 1541.1
radius = "225 um"
method = "bonded"
[[walls]]
name = "bottom"
[[walls]]
name = "punch"
)";

TEST(Config, ReadsTypedValuesAndQuantities) {
  ConfigTable config = ConfigTable::parse(kMaterial, "material.toml");
  EXPECT_EQ(config.integer("seed"), 7);
  ConfigTable material = config.table("material");
  EXPECT_DOUBLE_EQ(material.quantity("youngs_modulus", dim::pressure), 2.58e8);
  EXPECT_DOUBLE_EQ(material.number("poisson_ratio", std::nullopt, Range::closed(-1, 0.5)), 0.3);
  EXPECT_DOUBLE_EQ(material.quantity("density", dim::density), 1541.1);
  EXPECT_DOUBLE_EQ(material.quantity("radius", dim::length), 225e-6);
  EXPECT_EQ(material.choice("method", {"bonded", "rigid"}), "bonded");
  EXPECT_DOUBLE_EQ(material.number("restitution", 0.5), 0.5);  // fallback
  std::vector<ConfigTable> walls = config.tables("walls");
  ASSERT_EQ(walls.size(), 2u);
  EXPECT_EQ(walls[0].string("name"), "bottom");
  EXPECT_EQ(walls[1].string("name"), "punch");
  EXPECT_NO_THROW(config.check_unknown_keys());
}

TEST(Config, UnknownKeyIsNamedWithFileAndLine) {
  ConfigTable config = ConfigTable::parse("[material]\ndensity = 1.0\ndensty = 2.0\n", "m.toml");
  config.table("material").number("density");
  std::string message = input_error_of([&] { config.check_unknown_keys(); });
  EXPECT_THAT(message, HasSubstr("m.toml:3"));
  EXPECT_THAT(message, HasSubstr("material.densty"));
}

TEST(Config, UnreadTableIsUnknownToo) {
  ConfigTable config = ConfigTable::parse("a = 1\n[extra]\nb = 2\n", "x.toml");
  config.integer("a");
  EXPECT_THAT(input_error_of([&] { config.check_unknown_keys(); }), HasSubstr("'extra'"));
}

TEST(Config, MalformedTomlNamesFileAndLine) {
  std::string message =
      input_error_of([] { ConfigTable::parse("a = 1\nb = [1, 2\n", "bad.toml"); });
  EXPECT_THAT(message, HasSubstr("bad.toml:"));
  EXPECT_THAT(message, HasSubstr("malformed TOML"));
}

TEST(Config, WrongTypeIsNamed) {
  ConfigTable config = ConfigTable::parse("n = \"three\"\nflag = 1\n", "t.toml");
  EXPECT_THAT(input_error_of([&] { config.integer("n"); }), HasSubstr("'n' must be an integer"));
  EXPECT_THAT(input_error_of([&] { config.boolean("flag"); }), HasSubstr("true or false"));
}

TEST(Config, NaNAndOutOfRangeAreRejected) {
  ConfigTable config = ConfigTable::parse("e = nan\nE = -5.0\nnu = 0.7\nr = \"-1 mm\"\n", "r.toml");
  EXPECT_THAT(input_error_of([&] { config.number("e"); }), HasSubstr("NaN"));
  EXPECT_THAT(
      input_error_of([&] { config.quantity("E", dim::pressure, std::nullopt, Range::positive()); }),
      HasSubstr("r.toml:2: key 'E' = -5 Pa is out of range: must be > 0"));
  EXPECT_THAT(input_error_of([&] { config.number("nu", std::nullopt, Range::closed(-1, 0.5)); }),
              HasSubstr("in [-1, 0.5]"));
  EXPECT_THAT(
      input_error_of([&] { config.quantity("r", dim::length, std::nullopt, Range::positive()); }),
      HasSubstr("out of range"));
}

TEST(Config, WrongDimensionNamesFileLineAndKey) {
  ConfigTable config = ConfigTable::parse("[geometry]\nradius = \"3 kg\"\n", "d.toml");
  std::string message =
      input_error_of([&] { config.table("geometry").quantity("radius", dim::length); });
  EXPECT_THAT(message, HasSubstr("d.toml:2"));
  EXPECT_THAT(message, HasSubstr("geometry.radius"));
  EXPECT_THAT(message, HasSubstr("mass"));
}

TEST(Config, MissingRequiredKeyAndInvalidChoice) {
  ConfigTable config = ConfigTable::parse("method = \"glued\"\n", "c.toml");
  EXPECT_THAT(input_error_of([&] { config.number("density"); }),
              HasSubstr("missing required key 'density'"));
  EXPECT_THAT(input_error_of([&] {
                config.choice("method", {"bonded", "rigid"});
              }),
              HasSubstr("not one of: bonded, rigid"));
}

TEST(Config, MissingFileIsNamed) {
  EXPECT_THAT(input_error_of([] { ConfigTable::load_file("/nonexistent/run.toml"); }),
              HasSubstr("/nonexistent/run.toml"));
}

TEST(Config, QuantityArraysAreCheckedElementwise) {
  ConfigTable config = ConfigTable::parse("sizes = [\"180 um\", 2.5e-4, \"1 s\"]\n", "a.toml");
  EXPECT_THAT(input_error_of([&] { config.quantities("sizes", dim::length); }),
              HasSubstr("sizes[2]"));
}

}  // namespace
}  // namespace shapepress
