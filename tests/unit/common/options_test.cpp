#include "common/options.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <limits>
#include <optional>

#include "common/error.hpp"
#include "tests/support/errors.hpp"

namespace shapepress {
namespace {

using ::testing::HasSubstr;

using testing::input_error_of;

enum class Mode { slow, fast };

struct Inner {
  double damping = 0.0;
};

struct Settings {
  double length = 1e-3;
  std::optional<double> step;
  std::int64_t count = 10;
  bool flag = false;
  std::string name;
  Mode mode = Mode::slow;
  double speed = 0.0;
  std::array<double, 3> gravity = {0.0, 0.0, 0.0};
  std::vector<double> sizes;
  double low = 0.0, high = 0.0;
  double strength = std::numeric_limits<double>::infinity();
  Inner inner;
};

OptionTable<Settings> settings_table() {
  OptionTable<Settings> t("run", "a test section");
  t.quantity("length", &Settings::length, dim::length, Range::positive(), "a length")
      .quantity("step", &Settings::step, dim::time, Range::positive(), "a time step")
      .default_text("from the Rayleigh time")
      .integer("count", &Settings::count, Range::at_least(1), "a count")
      .boolean("flag", &Settings::flag, "a flag")
      .string("name", &Settings::name, "a name")
      .choice("mode", &Settings::mode,
              std::vector<std::pair<std::string, Mode>>{{"slow", Mode::slow}, {"fast", Mode::fast}},
              "the mode")
      .quantity("speed", &Settings::speed, dim::velocity, Range::positive(), "fast only")
      .required()
      .when([](const Settings& s) { return s.mode == Mode::fast; }, "with run.mode = \"slow\"")
      .numbers("gravity", &Settings::gravity, dim::acceleration, Range::any(), "gravity")
      .numbers("sizes", &Settings::sizes, dim::length, Range::positive(), "sizes")
      .quantity("low", &Settings::low, dim::length, Range::non_negative(), "low")
      .quantity("high", &Settings::high, dim::length, Range::non_negative(), "high")
      .default_from([](const Settings& s) { return s.low; }, "low")
      .quantity("strength", &Settings::strength, dim::pressure, Range::positive(), "strength")
      .number(
          "damping", [](auto& s) -> auto& { return s.inner.damping; }, Range{0.0, 1.0, true, false},
          "nested")
      .unused("steps", "this stage runs until its end");
  return t;
}

Settings read(std::string_view text) {
  const ConfigTable root = ConfigTable::parse(text, "t.toml");
  Settings s = settings_table().read(root.table("run"));
  root.check_unknown_keys();
  return s;
}

TEST(Options, DefaultsAreTheStructsOwn) {
  const Settings s = read("[run]\n");
  EXPECT_EQ(s.length, 1e-3);
  EXPECT_FALSE(s.step);
  EXPECT_EQ(s.count, 10);
  EXPECT_EQ(s.mode, Mode::slow);
  EXPECT_EQ(s.high, 0.0);
  const OptionSection docs = settings_table().docs();
  ASSERT_EQ(docs.rows.size(), 14u);
  EXPECT_EQ(docs.rows[0].default_value, "0.001");
  EXPECT_EQ(docs.rows[0].unit, "m");
  EXPECT_EQ(docs.rows[0].range, "> 0");
  EXPECT_EQ(docs.rows[1].default_value, "from the Rayleigh time");
  EXPECT_EQ(docs.rows[5].range, "slow | fast");
  EXPECT_EQ(docs.rows[6].default_value, "required");
  EXPECT_EQ(docs.rows[10].default_value, "low");
  EXPECT_EQ(docs.rows[11].default_value, "inf");
}

TEST(Options, ReadsUnitsNestedFieldsAndDependentDefaults) {
  const Settings s = read(
      "[run]\nlength = \"2 mm\"\nstep = 1e-6\nmode = \"fast\"\nspeed = \"3 mm/s\"\n"
      "gravity = [0, 0, -9.81]\nlow = \"1 mm\"\ndamping = 0.5\n");
  EXPECT_DOUBLE_EQ(s.length, 2e-3);
  EXPECT_EQ(*s.step, 1e-6);
  EXPECT_EQ(s.mode, Mode::fast);
  EXPECT_DOUBLE_EQ(s.speed, 3e-3);
  EXPECT_EQ(s.gravity[2], -9.81);
  EXPECT_DOUBLE_EQ(s.high, 1e-3);  // high defaults to low
  EXPECT_EQ(s.inner.damping, 0.5);
}

TEST(Options, UnknownKeyIsAnErrorNamingIt) {
  EXPECT_THAT(input_error_of([] { read("[run]\nlenght = 1\n"); }), HasSubstr("'run.lenght'"));
}

TEST(Options, UnusedKeyIsAnErrorNamingItAndWhy) {
  const std::string message = input_error_of([] { read("[run]\nsteps = 100\n"); });
  EXPECT_THAT(message, HasSubstr("'run.steps' is not used"));
  EXPECT_THAT(message, HasSubstr("runs until its end"));
}

TEST(Options, KeyOfAnotherModeIsAnError) {
  EXPECT_THAT(input_error_of([] { read("[run]\nspeed = 1\n"); }),
              HasSubstr("'run.speed' is not used with run.mode = \"slow\""));
  EXPECT_THAT(input_error_of([] { read("[run]\nmode = \"fast\"\n"); }),
              HasSubstr("missing required key 'run.speed'"));
}

TEST(Options, RangeAndUnitAreChecked) {
  EXPECT_THAT(input_error_of([] { read("[run]\nlength = -1\n"); }), HasSubstr("out of range"));
  EXPECT_THAT(input_error_of([] { read("[run]\ncount = 0\n"); }), HasSubstr("out of range"));
  EXPECT_THAT(input_error_of([] { read("[run]\nlength = \"3 kg\"\n"); }), HasSubstr("mass"));
  EXPECT_THAT(input_error_of([] { read("[run]\ngravity = [1, 2]\n"); }),
              HasSubstr("array of 3 numbers"));
  EXPECT_THAT(input_error_of([] { read("[run]\nmode = \"medium\"\n"); }),
              HasSubstr("not one of: slow, fast"));
}

TEST(Options, WrittenValuesReadBackToTheSameBits) {
  Settings s;
  s.length = 0.1 + 0.2;  // not a short decimal
  s.step = 1.0 / 3.0;
  s.count = 7;
  s.flag = true;
  s.name = "say \"hi\"\\";
  s.mode = Mode::fast;
  s.speed = 2.5e-7;
  s.gravity = {0.0, -1e-300, 9.81};
  s.sizes = {1e-6, 2e-6};
  s.low = 1e-3;
  s.high = 4e-3;
  s.inner.damping = 0.7;
  const std::string text = settings_table().write(s);
  EXPECT_THAT(text, HasSubstr("[run]\n"));
  EXPECT_THAT(text, HasSubstr("strength = inf\n"));
  const Settings back = read(text);
  EXPECT_EQ(back.length, s.length);
  EXPECT_EQ(back.step, s.step);
  EXPECT_EQ(back.count, s.count);
  EXPECT_EQ(back.flag, s.flag);
  EXPECT_EQ(back.name, s.name);
  EXPECT_EQ(back.mode, s.mode);
  EXPECT_EQ(back.speed, s.speed);
  EXPECT_EQ(back.gravity, s.gravity);
  EXPECT_EQ(back.sizes, s.sizes);
  EXPECT_EQ(back.low, s.low);
  EXPECT_EQ(back.high, s.high);
  EXPECT_EQ(back.strength, s.strength);
  EXPECT_EQ(back.inner.damping, s.inner.damping);
  // A key of an inactive mode is not written (it would be refused on reading back).
  s.mode = Mode::slow;
  EXPECT_THAT(settings_table().write(s), ::testing::Not(HasSubstr("speed")));
}

TEST(Options, MarkdownListsEveryKey) {
  StageOptions stage{"test", "A test stage.", {settings_table().docs()}};
  stage.sections.push_back({"material", "", true, {{"name", "", "text", "required", "a | b"}}});
  const std::string markdown = options_markdown(stage);
  EXPECT_THAT(markdown, HasSubstr("## shapepress test"));
  EXPECT_THAT(markdown, HasSubstr("### [run]"));
  EXPECT_THAT(markdown, HasSubstr("| `length` | m | > 0 | 0.001 | a length |"));
  EXPECT_THAT(markdown, HasSubstr("### [[material]]"));
  EXPECT_THAT(markdown, HasSubstr("a \\| b"));
  EXPECT_THAT(options_text(stage), HasSubstr("damping"));
}

}  // namespace
}  // namespace shapepress
