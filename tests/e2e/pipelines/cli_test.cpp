// The shapepress binary as a user meets it: --help, --version, every stage's --help, and the
// exit code 2 with a "did you mean" for a mistyped stage or option.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "pipelines/stages.hpp"
#include "tests/support/command.hpp"

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
  if (registered_stages().empty()) GTEST_SKIP() << "no stage registered to misspell";
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
  if (registered_stages().empty()) GTEST_SKIP() << "no stage registered";
  std::string name(registered_stages().front().name);
  CommandResult option = run_shapepress(name + " --quite");
  EXPECT_EQ(option.exit_code, 2) << option.output;
  EXPECT_THAT(option.output, HasSubstr("Did you mean '--quiet'"));
}

TEST(Cli, BadGlobalValuesExitTwo) {
  EXPECT_EQ(run_shapepress("--threads -3").exit_code, 2);
  EXPECT_EQ(run_shapepress("--threads many").exit_code, 2);
}

}  // namespace
}  // namespace shapepress
