// docs/stages.md's option tables are generated from the stages' option tables (common/
// command_options.hpp): the checked-in file must be what they give now.
#include <gtest/gtest.h>

#include <string>

#include "app/stages.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

TEST(StageOptionsDoc, StagesMdHoldsTheTablesTheStagesGenerate) {
  const std::string document =
      shapepress::testing::read_text(shapepress::testing::repository_root() / "docs" / "stages.md");
  EXPECT_EQ(document, with_stage_option_tables(document))
      << "docs/stages.md's option tables are out of date: run scripts/update-stage-options.sh";
}

}  // namespace
}  // namespace shapepress
