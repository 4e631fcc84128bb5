#include "common/units.hpp"

#include <gtest/gtest.h>

#include "common/error.hpp"

namespace shapepress {
namespace {

// Relative tolerance: unit factors are exact decimal scalings, so only round-off remains.
constexpr double kRelative = 1e-12;

void expect_si(std::string_view text, Dimension dimension, double expected) {
  SCOPED_TRACE(std::string(text));
  EXPECT_NEAR(parse_quantity(text, dimension, "key"), expected, std::abs(expected) * kRelative);
}

TEST(Units, ParsesTheIssueExamples) {
  expect_si("0.5um", dim::length, 0.5e-6);
  expect_si("30MPa", dim::pressure, 30e6);
  expect_si("2.58e8 Pa", dim::pressure, 2.58e8);
  expect_si("1e-6 s", dim::time, 1e-6);
  expect_si("225 \u00b5m", dim::length, 225e-6);  // micro sign
  expect_si("225 \u03bcm", dim::length, 225e-6);  // Greek mu
}

TEST(Units, ParsesCompoundUnits) {
  expect_si("1541 kg/m^3", dim::density, 1541.0);
  expect_si("1541 kg/m3", dim::density, 1541.0);
  expect_si("1.541 g/cm3", dim::density, 1541.0);
  expect_si("1.15e6 N/m3", dim::stiffness_per_area, 1.15e6);
  expect_si("2.5 m/s", dim::velocity, 2.5);
  expect_si("9.81 m/s^2", dim::acceleration, 9.81);
  expect_si("9.81 m/s\u00b2", dim::acceleration, 9.81);
  expect_si("76.2 GPa", dim::pressure, 76.2e9);
  expect_si("5 mN", dim::force, 5e-3);
  expect_si("3 kN*m", dim::energy, 3e3);
  expect_si("12 %", dim::dimensionless, 0.12);
}

TEST(Units, BareNumberIsSI) {
  expect_si("0.01", dim::length, 0.01);
  expect_si("-3.5e2", dim::pressure, -350.0);
}

TEST(Units, WrongDimensionNamesKeyAndBothDimensions) {
  try {
    parse_quantity("3 kg", dim::length, "pixel-size");
    FAIL() << "a mass was accepted as a length";
  } catch (const InputError& e) {
    std::string message = e.what();
    EXPECT_NE(message.find("pixel-size"), std::string::npos) << message;
    EXPECT_NE(message.find("mass"), std::string::npos) << message;
    EXPECT_NE(message.find("length"), std::string::npos) << message;
  }
}

TEST(Units, RejectsGarbageUnknownUnitsAndNonFinite) {
  EXPECT_THROW(parse_quantity("abc", dim::length, "k"), InputError);
  EXPECT_THROW(parse_quantity("", dim::length, "k"), InputError);
  EXPECT_THROW(parse_quantity("3 furlongs", dim::length, "k"), InputError);
  EXPECT_THROW(parse_quantity("nan m", dim::length, "k"), InputError);
  EXPECT_THROW(parse_quantity("inf Pa", dim::pressure, "k"), InputError);
  EXPECT_THROW(parse_quantity("3 MPa", dim::time, "k"), InputError);
}

TEST(Units, NamesDimensionsAndSIUnits) {
  EXPECT_EQ(dimension_name(dim::pressure), "pressure");
  EXPECT_EQ(si_unit(dim::pressure), "Pa");
  EXPECT_EQ(si_unit(dim::density), "kg*m^-3");
  EXPECT_EQ(si_unit(dim::stiffness_per_area), "N/m^3");
}

}  // namespace
}  // namespace shapepress
