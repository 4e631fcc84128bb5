// One table of command-line options parses them, records them for --resume and rebuilds them
// (every bit of a number back), refuses a damaged record naming the option, writes them typed
// into run.json and documents them.
#include <unistd.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/command_options.hpp"
#include "common/error.hpp"
#include "common/resume.hpp"
#include "common/sha256.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

struct ToyCli {
  std::string config;
  std::string out;
  std::string shape = "disc";
  std::string label;
  int count = 0;  // 0: the config's
  std::optional<std::uint64_t> seed;
  double fraction = 0.1;
  bool snapshot = false;
  std::vector<std::string> inputs;
  std::string resume;
};

CommandOptions toy_command(ToyCli& cli) {
  CommandOptions options("toy");
  options.texts("inputs", &cli.inputs, "input files")
      .text("--config", &cli.config, "config")
      .config()
      .text("--shape", &cli.shape, "shape")
      .choices({"disc", "square"})
      .show_default()
      .text("--label", &cli.label, "a label | with a bar")
      .whole("--count", &cli.count, "count")
      .range(Range::closed(1, 100))
      .whole("--seed", &cli.seed, "seed")
      .number("--fraction", &cli.fraction, "fraction")
      .range(Range::positive())
      .show_default()
      .recorded_as("the_fraction")
      .flag("--snapshot", &cli.snapshot, "snapshot")
      .text("--out", &cli.out, "out")
      .output();
  return options;
}

class CommandOptionsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    start_ = fs::current_path();
    folder_ = fs::temp_directory_path() /
              ("shapepress-command-options-" + std::to_string(::getpid()) + "-" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_ / "run");
    testing::write_text(folder_ / "c.toml", "x = 1\n");
    fs::current_path(folder_);
  }
  void TearDown() override {
    fs::current_path(start_);
    fs::remove_all(folder_);
  }
  // Parses `line` with the toy's table into `cli`.
  void parse(ToyCli& cli, const std::string& line) {
    CLI::App app;
    toy_command(cli).add_to(app, &cli.resume, "resume");
    app.parse(line, false);
  }
  fs::path start_, folder_;
};

TEST_F(CommandOptionsTest, ARecordGivesTheOptionsBack) {
  ToyCli given;
  parse(given,
        "a.h5 b.h5 --config c.toml --shape square --count 7 --seed 18446744073709551615 "
        "--fraction 0.30000000000000004 --snapshot --out run");
  const RunInvocation record = toy_command(given).invocation("toy --config c.toml");
  EXPECT_EQ(record.config, "c.toml");
  EXPECT_FALSE(record.arguments.contains("label"));  // not given
  EXPECT_FALSE(record.arguments.contains("out"));
  EXPECT_EQ(record.arguments.at("the_fraction").front(), exact_text(0.30000000000000004));
  write_invocation(folder_ / "run" / "resume.json", record);

  ToyCli resumed;
  EXPECT_EQ(toy_command(resumed).resume(folder_ / "run" / "resume.json", "run"),
            "toy --config c.toml");
  EXPECT_EQ(resumed.inputs, (std::vector<std::string>{"a.h5", "b.h5"}));
  EXPECT_EQ(resumed.config, "c.toml");
  EXPECT_EQ(resumed.shape, "square");
  EXPECT_EQ(resumed.count, 7);
  EXPECT_EQ(resumed.seed, std::optional<std::uint64_t>(18446744073709551615ULL));
  EXPECT_EQ(resumed.fraction, 0.30000000000000004);
  EXPECT_TRUE(resumed.snapshot);
  EXPECT_EQ(resumed.out, (folder_ / "run").string());
}

TEST_F(CommandOptionsTest, ADefaultOutsideTheRangeStandsForNotGiven) {
  ToyCli given;
  parse(given, "--config c.toml --out run");
  write_invocation(folder_ / "run" / "resume.json", toy_command(given).invocation("toy"));
  ToyCli resumed;
  toy_command(resumed).resume(folder_ / "run" / "resume.json", "run");
  EXPECT_EQ(resumed.count, 0);
  EXPECT_FALSE(resumed.seed);
}

TEST_F(CommandOptionsTest, ADamagedRecordIsRefusedNamingTheOption) {
  const auto refused = [&](std::map<std::string, std::vector<std::string>> arguments) {
    write_invocation(
        folder_ / "run" / "resume.json",
        {"toy", folder_, "c.toml", sha256_file(folder_ / "c.toml"), std::move(arguments), {}});
    ToyCli resumed;
    try {
      toy_command(resumed).resume(folder_ / "run" / "resume.json", "run");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::map<std::string, std::vector<std::string>> whole = {
      {"shape", {"disc"}}, {"count", {"7"}}, {"the_fraction", {"0.5"}}, {"snapshot", {"0"}}};
  EXPECT_EQ(refused(whole), "accepted");
  for (const auto& [key, text] :
       std::vector<std::pair<std::string, std::string>>{{"count", "x"},
                                                        {"count", "101"},
                                                        {"seed", "-5"},
                                                        {"shape", "circle"},
                                                        {"the_fraction", "-1"},
                                                        {"snapshot", "yes"}}) {
    auto damaged = whole;
    damaged[key] = {text};
    const std::string message = refused(damaged);
    EXPECT_THAT(message, HasSubstr("resume.json: argument '" + key + "' is '" + text + "'"));
  }
  for (const char* required : {"shape", "count", "the_fraction", "snapshot"}) {
    auto missing = whole;
    missing.erase(required);
    EXPECT_THAT(refused(missing), HasSubstr(std::string("no argument '") + required + "'"));
  }
}

TEST_F(CommandOptionsTest, RunJsonHasTheOptionsTyped) {
  ToyCli given;
  parse(given, "--config c.toml --count 3 --out run");
  const nlohmann::ordered_json json = toy_command(given).json();
  EXPECT_EQ(json["count"], 3);
  EXPECT_EQ(json["fraction"], 0.1);  // by its name, not its record key
  EXPECT_EQ(json["snapshot"], false);
  EXPECT_TRUE(json["seed"].is_null());
  EXPECT_EQ(json["out"], "run");
}

TEST_F(CommandOptionsTest, TheTableDocumentsAndFillsItsMarkers) {
  ToyCli defaults;
  const CommandOptions table = toy_command(defaults);
  const std::string markdown = table.markdown();
  EXPECT_THAT(markdown, HasSubstr("| `--shape` | disc \\| square | disc | shape |"));
  EXPECT_THAT(markdown, HasSubstr("| `--count` | whole number in [1, 100] | - | count |"));
  EXPECT_THAT(markdown, HasSubstr("a label \\| with a bar"));
  const std::string document = "# Toy\n<!-- options: toy -->\nold\n<!-- end options -->\nrest\n";
  EXPECT_EQ(with_option_tables(document, {table}),
            "# Toy\n<!-- options: toy -->\n" + markdown + "<!-- end options -->\nrest\n");
  EXPECT_THROW(with_option_tables("# no markers\n", {table}), InputError);
}

}  // namespace
}  // namespace shapepress
