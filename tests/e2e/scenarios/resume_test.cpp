// `compact --resume`: a compaction killed with SIGKILL at random points (seeded) and resumed
// each time ends with the outputs of the uninterrupted run, punch.csv byte for byte; SIGTERM
// writes a checkpoint and exits 128 + 15; an output folder that cannot be made is exit 2.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include "simulate/snapshot.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::read_text;
using shapepress::testing::run_command;
using shapepress::testing::run_shapepress;
using shapepress::testing::shell_quoted;
using shapepress::testing::write_text;
using ::testing::HasSubstr;

// A small compaction (150 spheres poured and settled, a slow load, hold, unload) checkpointing
// every 300 steps, so a kill can land before the first checkpoint, between two, or while one is
// written.
std::string resumable_config() {
  return shapepress::testing::test_data_text("scenarios/powder.toml") + R"(
[run]
record_every = 50
snapshot_every = 1000
checkpoint_every = 300
gravity = [0.0, 0.0, -9.81]

[box]
x = "6 mm"
y = "6 mm"
punch = "20 mm"
)" + shapepress::testing::test_data_text("scenarios/powder-die.toml") +
         R"(
[generate]
count = 150
diameter_min = "0.8 mm"
diameter_max = "1.2 mm"
seed = 3
settle_time = "20 ms"

[punch]
speed = "0.1 m/s"
target_strain = 0.1
hold_time = "0.5 ms"
unload_speed = "0.5 m/s"
)";
}

std::vector<std::filesystem::path> files_under(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) files.push_back(std::filesystem::relative(entry.path(), folder));
  std::sort(files.begin(), files.end());
  return files;
}

// Two snapshots hold the same state, contacts and walls (their creation times aside).
void expect_same_snapshot(const std::filesystem::path& a, const std::filesystem::path& b) {
  const simulate::LoadedSnapshot x = simulate::read_snapshot(a), y = simulate::read_snapshot(b);
  EXPECT_EQ(x.checkpoint.step, y.checkpoint.step) << b;
  EXPECT_EQ(x.checkpoint.time, y.checkpoint.time) << b;
  for (const auto& [p, q] : {std::pair(&x.state.position, &y.state.position),
                             std::pair(&x.state.velocity, &y.state.velocity),
                             std::pair(&x.state.angular_velocity, &y.state.angular_velocity),
                             std::pair(&x.state.force, &y.state.force)}) {
    EXPECT_TRUE(p->x == q->x && p->y == q->y && p->z == q->z) << b;
  }
  ASSERT_EQ(x.checkpoint.walls.size(), y.checkpoint.walls.size());
  for (std::size_t k = 0; k < x.checkpoint.walls.size(); ++k)
    EXPECT_EQ(x.checkpoint.walls[k].position, y.checkpoint.walls[k].position) << b;
  EXPECT_EQ(x.checkpoint.first, y.checkpoint.first) << b;
  EXPECT_EQ(x.checkpoint.second, y.checkpoint.second) << b;
  EXPECT_EQ(x.checkpoint.wall_force, y.checkpoint.wall_force) << b;
  EXPECT_EQ(x.scenario, y.scenario) << b;
}

TEST(CompactResume, KilledThreeTimesEndsAsTheUninterruptedRun) {
  const auto dir = fresh_directory("compact_resume");
  write_text(dir / "compact.toml", resumable_config());
  const std::string start = "compact --config " + shell_quoted(dir / "compact.toml") + " --out " +
                            shell_quoted(dir / "run");
  const auto t0 = std::chrono::steady_clock::now();
  const auto whole = run_shapepress(start);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "checkpoints"));  // gone once whole
  // The same --out, so run.json's command and effective.toml's header are the same too.
  std::filesystem::rename(dir / "run", dir / "uninterrupted");

  // Three kills, each a seeded fraction of the whole run's wall time into an attempt.
  std::mt19937 random(23);
  std::uniform_real_distribution<double> fraction(0.4, 0.9);
  std::vector<std::string> resumed_from;
  bool finished_early = false;  // an attempt outran its kill: nothing left to resume
  for (int attempt = 0; attempt < 3 && !finished_early; ++attempt) {
    // A resumed attempt skips the pour and settle, most of the run's start: it is killed sooner.
    const double kill_after = fraction(random) * seconds * (attempt == 0 ? 1.0 : 0.4);
    const std::string arguments =
        attempt == 0 ? start : "compact --resume " + shell_quoted(dir / "run");
    std::string command = "timeout -s KILL ";
    command += std::to_string(kill_after);
    command += " ";
    command += SHAPEPRESS_BINARY;
    command += " ";
    command += arguments;
    const auto killed = run_command(command);
    std::smatch step;
    resumed_from.push_back(
        std::regex_search(killed.output, step, std::regex(R"(checkpoint at step (\d+))"))
            ? step[1].str()
            : "start");
    std::printf("attempt %d: killed after %.2f s of %.2f s (resumed from %s), exit %d\n",
                attempt + 1, kill_after, seconds, resumed_from.back().c_str(), killed.exit_code);
    finished_early = killed.exit_code == 0;
  }
  EXPECT_NE(resumed_from.back(), "start");  // at least one resume from a checkpoint
  if (!finished_early) {
    const auto finished = run_shapepress("compact --resume " + shell_quoted(dir / "run"));
    ASSERT_EQ(finished.exit_code, 0) << finished.output;
    std::smatch step;
    std::printf("last resume: from %s\n",
                std::regex_search(finished.output, step, std::regex(R"(checkpoint at step (\d+))"))
                    ? step[1].str().c_str()
                    : "the start");
  }

  const auto ref = dir / "uninterrupted", run = dir / "run";
  EXPECT_EQ(files_under(run), files_under(ref));  // no checkpoint, no hidden temporary left
  for (const auto* name : {"punch.csv", "run.json", "effective.toml", "snapshots.xdmf"})
    EXPECT_EQ(read_text(run / name), read_text(ref / name)) << name;
  for (const auto& file : files_under(ref / "snapshots"))
    expect_same_snapshot(ref / "snapshots" / file, run / "snapshots" / file);
}

TEST(CompactResume, SigtermWritesACheckpointAndExitsWithItsCode) {
  const auto dir = fresh_directory("compact_sigterm");
  write_text(dir / "compact.toml", resumable_config());
  // SIGTERM once the run is well into its steps (the first snapshot is out).
  // (Appended piece by piece: GCC 12 at -O3 warns falsely (-Wrestrict) on one long sum.)
  std::string command = "(";
  command += SHAPEPRESS_BINARY;
  command += " compact --config ";
  command += shell_quoted(dir / "compact.toml");
  command += " --out ";
  command += shell_quoted(dir / "run");
  command += " & pid=$!; while [ ! -e ";
  command += shell_quoted(dir / "run" / "snapshots" / "step_0000001000.h5");
  command += " ] && kill -0 $pid 2>/dev/null; do sleep 0.05; done; kill -TERM $pid; wait $pid)";
  const auto stopped = run_command(command);
  EXPECT_EQ(stopped.exit_code, 128 + 15) << stopped.output;
  EXPECT_THAT(stopped.output, HasSubstr("--resume"));
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "punch.csv"));
  const auto resumed = run_shapepress("compact --resume " + shell_quoted(dir / "run"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr("checkpoint at step"));
}

TEST(CompactResume, NothingToResumeIsExitTwoNamingTheFolder) {
  const auto dir = fresh_directory("compact_resume_nothing");
  const auto result = run_shapepress("compact --resume " + shell_quoted(dir / "nowhere"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_THAT(result.output, HasSubstr("nowhere"));
}

TEST(CompactResume, AnOutputFolderThatCannotBeMadeIsExitTwoNamingIt) {
  const auto dir = fresh_directory("compact_out_unwritable");
  write_text(dir / "compact.toml", resumable_config());
  write_text(dir / "file", "not a folder");
  const auto result =
      run_shapepress("--quiet compact --config " + shell_quoted(dir / "compact.toml") + " --out " +
                     shell_quoted(dir / "file" / "run"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_THAT(result.output, HasSubstr((dir / "file").string()));
}

}  // namespace
}  // namespace shapepress
