// `generate --resume`: a generate killed with SIGKILL at three chosen checkpoints and resumed each
// time ends with the uninterrupted run's meshes, shapes.csv, effective.toml and run.json, byte for
// byte (generate's run.json holds no time); SIGTERM writes a checkpoint and exits 143; a folder
// with nothing to resume is exit 2 naming it, a finished one says so.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "tests/support/command.hpp"
#include "tests/support/files.hpp"
#include "tests/support/kill_resume.hpp"

namespace shapepress::geometry {
namespace {

using shapepress::testing::CommandResult;
using shapepress::testing::files_under;
using shapepress::testing::fresh_directory;
using shapepress::testing::kill_at_checkpoints;
using shapepress::testing::KilledRuns;
using shapepress::testing::read_text;
using shapepress::testing::run_shapepress;
using shapepress::testing::shell_quoted;
using shapepress::testing::spread_steps;
using shapepress::testing::terminate_when;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

const fs::path data = fs::path(SHAPEPRESS_TEST_DATA) / "geometry";

// Eight coarse particles (642 vertices) with 16 views each: 2–4 s on 2 cores, a checkpoint every
// two particle steps.
std::string small_generate(const fs::path& targets, const fs::path& out) {
  return "generate --targets " + shell_quoted(targets) +
         " --count 8 --subdivisions 3 --directions 16 --checkpoint-every 2 --out " +
         shell_quoted(out);
}

TEST(GenerateResume, KilledThreeTimesEndsAsTheUninterruptedRun) {
  const fs::path dir = fresh_directory("generate_resume");
  // Started on two threads and resumed on one: the particles do not depend on the threads.
  const std::string start =
      "--threads 2 " + small_generate(data / "avicel_ph200_projected.toml", dir / "run");
  const CommandResult whole = run_shapepress(start);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_FALSE(fs::exists(dir / "run" / "checkpoints"));  // gone once whole
  fs::rename(dir / "run", dir / "uninterrupted");

  // Killed at particle steps 6, 12 and 18 of the 24 (8 particles drawn, shaped, described):
  // in the draws, the fit's silhouettes and the descriptors.
  const std::string resume = "--threads 1 generate --resume " + shell_quoted(dir / "run");
  const KilledRuns runs = kill_at_checkpoints(
      start, resume, {dir / "run" / "checkpoints", "particles_", spread_steps(24, 2, 3)});
  EXPECT_NE(std::count(runs.resumed_from.begin(), runs.resumed_from.end(), "start"),
            static_cast<std::ptrdiff_t>(runs.resumed_from.size()));
  ASSERT_TRUE(runs.finished) << runs.output;

  const fs::path ref = dir / "uninterrupted", run = dir / "run";
  const std::vector<fs::path> files = files_under(ref);
  EXPECT_EQ(files_under(run), files);  // no checkpoint, no hidden temporary left
  EXPECT_EQ(files.size(), 8u + 3u);    // the meshes, shapes.csv, effective.toml, run.json
  for (const fs::path& file : files)
    EXPECT_EQ(read_text(run / file), read_text(ref / file)) << file;

  const CommandResult again = run_shapepress(resume);
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_THAT(again.output, HasSubstr("nothing to resume"));
}

TEST(GenerateResume, SigtermWritesACheckpointAndExitsWithItsCode) {
  const fs::path dir = fresh_directory("generate_sigterm");
  const fs::path out = dir / "shapes";
  // SIGTERM once a checkpoint is out (box targets: the other branch of the shape phase).
  const CommandResult stopped =
      terminate_when(small_generate(data / "paper_box_targets.toml", out),
                     shell_quoted(out / "checkpoints") + "/*_*.json", "0.02");
  EXPECT_EQ(stopped.exit_code, 128 + 15) << stopped.output;
  EXPECT_THAT(stopped.output, HasSubstr("generate --resume"));
  EXPECT_FALSE(fs::exists(out / "shapes.csv"));
  EXPECT_FALSE(fs::exists(out / "run.json"));
  EXPECT_TRUE(fs::exists(out / "checkpoints" / "resume.json"));

  const CommandResult resumed = run_shapepress("generate --resume " + shell_quoted(out));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr("checkpoint at step"));
  EXPECT_TRUE(fs::exists(out / "shapes.csv"));
  EXPECT_TRUE(fs::exists(out / "particle_0007.stl"));
  EXPECT_FALSE(fs::exists(out / "checkpoints"));
}

TEST(GenerateResume, KilledBeforeItsFirstCheckpointStartsAgain) {
  const fs::path dir = fresh_directory("generate_resume_early");
  const fs::path out = dir / "shapes";
  // No checkpoint by steps or time: SIGKILL once the run has recorded how it was started.
  std::string command = "(";
  command += SHAPEPRESS_BINARY;
  command += " generate --targets " + shell_quoted(data / "paper_box_targets.toml");
  command += " --count 3 --subdivisions 2 --checkpoint-minutes 0 --out " + shell_quoted(out);
  command += " & pid=$!; while ! ls " + shell_quoted(out / "checkpoints" / "resume.json");
  command += " >/dev/null 2>&1 && kill -0 $pid 2>/dev/null; do sleep 0.01; done;";
  command += " kill -KILL $pid; wait $pid)";
  const CommandResult killed = shapepress::testing::run_command(command);
  ASSERT_NE(killed.exit_code, 0) << killed.output;  // killed, not finished
  const CommandResult resumed = run_shapepress("generate --resume " + shell_quoted(out));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr("no checkpoint yet: starting the run again"));
  EXPECT_TRUE(fs::exists(out / "particle_0002.stl"));
  EXPECT_FALSE(fs::exists(out / "checkpoints"));
}

TEST(GenerateResume, NothingToResumeIsExitTwoNamingTheFolder) {
  const fs::path dir = fresh_directory("generate_resume_nothing");
  const CommandResult result = run_shapepress("generate --resume " + shell_quoted(dir / "nowhere"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_THAT(result.output, HasSubstr("nowhere"));
  EXPECT_FALSE(fs::exists(dir / "nowhere"));
}

}  // namespace
}  // namespace shapepress::geometry
