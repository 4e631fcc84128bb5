#include "common/progress.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/error.hpp"

namespace shapepress {
namespace {

using ::testing::HasSubstr;

TEST(Progress, LineShowsPercentRateAndEta) {
  ProgressReporter progress("compact", 1000.0, {.quiet = true});
  std::string line = progress.format_line(250.0, 10.0, "gap 3.2 mm");
  EXPECT_THAT(line, HasSubstr("compact"));
  EXPECT_THAT(line, HasSubstr(" 25.0 %"));
  EXPECT_THAT(line, HasSubstr("25 steps/s"));
  EXPECT_THAT(line, HasSubstr("ETA 0:30"));  // 750 steps left at 25 steps/s
  EXPECT_THAT(line, HasSubstr("gap 3.2 mm"));
}

// A run that outlives its first estimate (compact's spring-back) renews the total when it prints,
// instead of sitting at 100 % with no ETA.
TEST(Progress, ARenewedTotalKeepsThePercentAndEtaMeaningful) {
  ProgressReporter progress("compact", 1000.0, {.interval_seconds = 0.0});
  ::testing::internal::CaptureStderr();
  progress.update(1500.0, "unload", [] { return 2000.0; });
  const std::string line = ::testing::internal::GetCapturedStderr();
  EXPECT_THAT(line, HasSubstr(" 75.0 %"));
  EXPECT_THAT(line, ::testing::Not(HasSubstr("ETA ?")));
  EXPECT_THAT(line, HasSubstr("unload"));
}

TEST(Progress, DurationsReadLikeAClock) {
  EXPECT_EQ(format_duration(5.0), "0:05");
  EXPECT_EQ(format_duration(3723.0), "1:02:03");
  EXPECT_EQ(format_duration(-1.0), "?");
}

TEST(Errors, ExitCodesFollowTheErrorKind) {
  EXPECT_EQ(exit_code_for(InputError("bad")), ExitCode::bad_input);
  EXPECT_EQ(exit_code_for(ComputationError("diverged")), ExitCode::computation_failed);
  EXPECT_EQ(exit_code_for(std::runtime_error("other")), ExitCode::computation_failed);
}

}  // namespace
}  // namespace shapepress
