// The shapepress binary as a user meets it: --help, --version, every stage's --help, and the
// exit code 2 with a "did you mean" for a mistyped stage or option; the config keys of each stage
// and docs/config-reference.md generated from them.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "app/stages.hpp"
#include "common/options.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using ::testing::HasSubstr;

using shapepress::testing::CommandResult;
using shapepress::testing::run_shapepress;

TEST(Cli, HelpListsEveryRegisteredStage) {
  CommandResult help = run_shapepress("--help");
  EXPECT_EQ(help.exit_code, 0) << help.output;
  EXPECT_THAT(help.output, HasSubstr("--threads"));
  EXPECT_THAT(help.output, HasSubstr("--quiet"));
  EXPECT_THAT(help.output, HasSubstr("--log-level"));
  for (const Stage& stage : registered_stages())
    EXPECT_THAT(help.output, HasSubstr(std::string(stage.name)));
}

TEST(Cli, VersionNamesTheRevision) {
  CommandResult version = run_shapepress("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_THAT(version.output, ::testing::StartsWith("shapepress 0."));
}

TEST(Cli, EveryStageHasHelp) {
  for (const Stage& stage : registered_stages()) {
    CommandResult help = run_shapepress(std::string(stage.name) + " --help");
    EXPECT_EQ(help.exit_code, 0) << stage.name << ": " << help.output;
    EXPECT_THAT(help.output, HasSubstr(std::string(stage.name)));
  }
}

TEST(Cli, UnknownStageExitsTwoWithSuggestion) {
  CommandResult nonsense = run_shapepress("frobnicate");
  EXPECT_EQ(nonsense.exit_code, 2);
  EXPECT_THAT(nonsense.output, HasSubstr("'frobnicate' is not a shapepress stage"));
  ASSERT_FALSE(registered_stages().empty());
  std::string name(registered_stages().front().name);
  std::string typo = name.substr(0, name.size() - 1) + "x";
  CommandResult mistyped = run_shapepress(typo);
  EXPECT_EQ(mistyped.exit_code, 2) << mistyped.output;
  EXPECT_THAT(mistyped.output, HasSubstr("Did you mean '" + name + "'"));
}

TEST(Cli, UnknownOptionExitsTwoWithSuggestion) {
  CommandResult global = run_shapepress("--threadz 2");
  EXPECT_EQ(global.exit_code, 2) << global.output;
  EXPECT_THAT(global.output, HasSubstr("Did you mean '--threads'"));
  ASSERT_FALSE(registered_stages().empty());
  std::string name(registered_stages().front().name);
  CommandResult option = run_shapepress(name + " --quite");
  EXPECT_EQ(option.exit_code, 2) << option.output;
  EXPECT_THAT(option.output, HasSubstr("Did you mean '--quiet'"));
}

TEST(Cli, EveryStageWithAConfigPrintsItsKeys) {
  int stages = 0;
  for (const Stage& stage : registered_stages()) {
    if (!stage.config_options) continue;
    ++stages;
    // --config is required, yet --help-config alone answers.
    CommandResult keys = run_shapepress(std::string(stage.name) + " --help-config");
    EXPECT_EQ(keys.exit_code, 0) << stage.name << ": " << keys.output;
    for (const OptionSection& section : stage.config_options().sections)
      for (const OptionDoc& row : section.rows)
        EXPECT_THAT(keys.output, HasSubstr(row.key)) << stage.name;
  }
  EXPECT_GE(stages, 3);
}

// docs/config-reference.md is generated from the option tables: it must be what they give now.
TEST(Cli, ConfigReferenceIsWhatTheTablesGenerate) {
  const std::string expected = config_reference_markdown();
  EXPECT_EQ(shapepress::testing::read_text(shapepress::testing::repository_root() / "docs" /
                                           "config-reference.md"),
            expected)
      << "docs/config-reference.md is out of date: run scripts/update-config-reference.sh";
  CommandResult printed = run_shapepress("help-config --markdown");
  EXPECT_EQ(printed.exit_code, 0);
  EXPECT_EQ(printed.output, expected);
}

TEST(Cli, BadGlobalValuesExitTwo) {
  EXPECT_EQ(run_shapepress("--threads -3").exit_code, 2);
  EXPECT_EQ(run_shapepress("--threads many").exit_code, 2);
}

}  // namespace
}  // namespace shapepress
