// `compact --resume`: a compaction killed with SIGKILL at chosen checkpoints and resumed
// each time ends with the outputs of the uninterrupted run, punch.csv byte for byte; SIGTERM
// writes a checkpoint and exits 128 + 15; an output folder that cannot be made is exit 2.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "simulate/snapshot.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"
#include "tests/support/kill_resume.hpp"

namespace shapepress {
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
using shapepress::testing::write_text;
using ::testing::HasSubstr;

// A small compaction (150 spheres poured and settled, a slow load, hold, unload) checkpointing
// every 100 steps.
std::string resumable_config() {
  return shapepress::testing::test_data_text("scenarios/powder.toml") + R"(
[run]
record_every = 50
snapshot_every = 1000
checkpoint_every = 100
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
  const CommandResult whole = run_shapepress(start);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "checkpoints"));  // gone once whole
  const auto steps =
      nlohmann::json::parse(read_text(dir / "run" / "run.json"))["facts"]["final_step"]
          .get<std::int64_t>();
  // The same --out, so run.json's command and effective.toml's header are the same too.
  std::filesystem::rename(dir / "run", dir / "uninterrupted");

  // Killed at a quarter, half and three quarters of the compaction's steps (its checkpoints
  // every 100 steps), each attempt at a checkpoint past the one it resumed from.
  const KilledRuns runs =
      kill_at_checkpoints(start, "compact --resume " + shell_quoted(dir / "run"),
                          {dir / "run" / "checkpoints", "step_", spread_steps(steps, 100, 3)});
  // At least one attempt resumed from a checkpoint (a later one may find the run finished).
  EXPECT_NE(std::count(runs.resumed_from.begin(), runs.resumed_from.end(), "start"),
            static_cast<std::ptrdiff_t>(runs.resumed_from.size()));
  ASSERT_TRUE(runs.finished) << runs.output;

  const auto ref = dir / "uninterrupted", run = dir / "run";
  EXPECT_EQ(files_under(run), files_under(ref));  // no checkpoint, no hidden temporary left
  for (const auto* name : {"punch.csv", "effective.toml", "snapshots.xdmf"})
    EXPECT_EQ(read_text(run / name), read_text(ref / name)) << name;
  // run.json too, but for the loop's wall seconds: the resumed run states its attempts' sum.
  nlohmann::json resumed = nlohmann::json::parse(read_text(run / "run.json")),
                 uninterrupted = nlohmann::json::parse(read_text(ref / "run.json"));
  ASSERT_TRUE(resumed["facts"].contains("loop_s"));
  EXPECT_GT(resumed["facts"]["loop_s"].get<double>(), 0.0);
  resumed["facts"].erase("loop_s"), uninterrupted["facts"].erase("loop_s");
  EXPECT_EQ(resumed, uninterrupted);
  // Among them the counted work (advise's cost), kept across the kills: 150 spheres every step
  // of the compaction (the settle is an engine of its own, not counted), their contacts, no bonds.
  const auto count = [&](const char* key) { return resumed["facts"].at(key).get<std::int64_t>(); };
  EXPECT_EQ(count("sphere_steps"), 150 * count("steps"));
  EXPECT_GT(count("contact_steps"), count("steps"));
  EXPECT_EQ(count("bond_steps"), 0);
  EXPECT_EQ(count("counted_cost"), count("sphere_steps") + count("contact_steps"));
  for (const auto& file : files_under(ref / "snapshots"))
    expect_same_snapshot(ref / "snapshots" / file, run / "snapshots" / file);
}

TEST(CompactResume, SigtermWritesACheckpointAndExitsWithItsCode) {
  const auto dir = fresh_directory("compact_sigterm");
  write_text(dir / "compact.toml", resumable_config());
  // SIGTERM once the run is well into its steps (the first snapshot is out).
  const auto stopped =
      terminate_when("compact --config " + shell_quoted(dir / "compact.toml") + " --out " +
                         shell_quoted(dir / "run"),
                     shell_quoted(dir / "run" / "snapshots" / "step_0000001000.h5"), "0.05");
  EXPECT_EQ(stopped.exit_code, 128 + 15) << stopped.output;
  EXPECT_THAT(stopped.output, HasSubstr("--resume"));
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "punch.csv"));
  // A checkpoint whose loop's wall seconds are unknown ("nan": resumed once from a run that did
  // not keep them): the same run, which resumes to the same curve and states no loop_s it cannot
  // know.
  std::filesystem::copy(dir / "run", dir / "older", std::filesystem::copy_options::recursive);
  int stripped = 0;
  for (const auto& file : files_under(dir / "older" / "checkpoints")) {
    if (!file.string().starts_with("step_") || std::filesystem::path(file).extension() != ".json")
      continue;
    const std::string text = read_text(dir / "older" / "checkpoints" / file);
    const std::size_t at = text.find("\"loop_s\":");
    ASSERT_NE(at, std::string::npos) << file;
    const std::size_t value = at + std::string("\"loop_s\":").size();
    write_text(dir / "older" / "checkpoints" / file,
               text.substr(0, value) + "\"nan\"" + text.substr(text.find(',', value)));
    ++stripped;
  }
  EXPECT_GT(stripped, 0);
  const auto resumed = run_shapepress("compact --resume " + shell_quoted(dir / "run"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr("checkpoint at step"));
  const auto older = run_shapepress("compact --resume " + shell_quoted(dir / "older"));
  ASSERT_EQ(older.exit_code, 0) << older.output;
  EXPECT_EQ(read_text(dir / "older" / "punch.csv"), read_text(dir / "run" / "punch.csv"));
  const auto facts = [&](const char* run) {
    return nlohmann::json::parse(read_text(dir / run / "run.json"))["facts"];
  };
  EXPECT_GT(facts("run").value("loop_s", 0.0), 0.0);
  EXPECT_FALSE(facts("older").contains("loop_s"));
}

// `config` run whole into dir/whole, and again into dir/run stopped by SIGTERM once a checkpoint
// of run/checkpoints matching `checkpoint` (a glob) is out.
void run_whole_and_stopped(const std::filesystem::path& dir, const std::string& config,
                           const std::string& checkpoint) {
  write_text(dir / "compact.toml", config);
  const auto whole =
      run_shapepress("--quiet compact --config " + shell_quoted(dir / "compact.toml") + " --out " +
                     shell_quoted(dir / "whole"));
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const auto stopped =
      terminate_when("compact --config " + shell_quoted(dir / "compact.toml") + " --out " +
                         shell_quoted(dir / "run"),
                     shell_quoted(dir / "run" / "checkpoints") + "/" + checkpoint, "0.005");
  ASSERT_EQ(stopped.exit_code, 128 + 15) << stopped.output;
}

// The settle of a generated bed checkpoints too: stopped while settling, the run resumes in the
// settle and ends with the uninterrupted run's punch.csv.
TEST(CompactResume, StoppedWhileSettlingResumesInTheSettle) {
  const auto dir = fresh_directory("compact_settle_resume");
  // Any settle checkpoint: the newest two are kept, and on an idle machine the first is gone
  // within milliseconds.
  ASSERT_NO_FATAL_FAILURE(run_whole_and_stopped(dir, resumable_config(), "settle_*.json"));
  const auto resumed = run_shapepress("compact --resume " + shell_quoted(dir / "run"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr("settle's checkpoint at step"));
  EXPECT_EQ(read_text(dir / "run" / "punch.csv"), read_text(dir / "whole" / "punch.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "checkpoints"));
}

// The punch's relaxation before loading is not recorded: a run stopped while it relaxes has a
// checkpoint without records, which resumes in the relaxation and ends with the uninterrupted
// run's punch.csv.
TEST(CompactResume, StoppedWhileThePunchRelaxesResumesInTheRelaxation) {
  const auto dir = fresh_directory("compact_relax_resume");
  std::string config = resumable_config();
  config.insert(config.find("hold_time = "), "relax_time = \"10 ms\"\n");
  // The first checkpoint of the compaction (100 steps after the settle, of some 6000 relaxing).
  ASSERT_NO_FATAL_FAILURE(run_whole_and_stopped(dir, config, "step_*.json"));
  int relaxing = 0;
  for (const auto& file : files_under(dir / "run" / "checkpoints"))
    if (file.string().starts_with("step_"))
      relaxing +=
          read_text(dir / "run" / "checkpoints" / file).find("\"records\":[]") != std::string::npos;
  EXPECT_GT(relaxing, 0);
  const auto resumed = run_shapepress("compact --resume " + shell_quoted(dir / "run"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(read_text(dir / "run" / "punch.csv"), read_text(dir / "whole" / "punch.csv"));
  const auto facts = nlohmann::json::parse(read_text(dir / "run" / "run.json"))["facts"];
  EXPECT_EQ(facts["relax_time_s"].get<double>(), 0.01);
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
