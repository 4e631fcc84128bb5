// The one checkpoint format (common/checkpoint.hpp) and the run around it (common/resume.hpp
// ResumableRun): a record gives back every bit of what was written; a record that is not JSON, cut
// short, of another stage or version, or without a key is refused naming the file and the key;
// a fresh start records how it was started and a resume keeps the records; a signal stops the
// loop after its checkpoint with 128 + the signal; a whole run's folder goes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "common/checkpoint.hpp"
#include "common/error.hpp"
#include "common/resume.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

CheckpointState example_state(const std::vector<double>& numbers) {
  std::vector<CheckpointState> rows;
  for (std::size_t k = 0; k < numbers.size(); ++k)
    rows.push_back(
        CheckpointState().whole("step", static_cast<std::int64_t>(k)).number("gap", numbers[k]));
  return CheckpointState()
      .whole("steps", -7)
      .unsigned_whole("seed", std::numeric_limits<std::uint64_t>::max())
      .flag("settled", true)
      .text("description", "BMS sphere \"R\" = 1 mm")
      .numbers("values", numbers)
      .wholes("bins", {0, 65535, -1})
      .list("rows", std::move(rows));
}

TEST(CheckpointRecord, GivesBackEveryBitOfWhatWasWritten) {
  std::vector<double> numbers = {0.1,
                                 1.0 / 3.0,
                                 -0.0,
                                 5e-324,
                                 std::numeric_limits<double>::max(),
                                 std::numeric_limits<double>::infinity(),
                                 -std::numeric_limits<double>::infinity(),
                                 3.0};
  std::mt19937_64 random(7);
  for (int k = 0; k < 200; ++k) {
    const std::uint64_t bits = random();
    double x = 0.0;
    std::memcpy(&x, &bits, sizeof x);
    if (std::isfinite(x)) numbers.push_back(x);
  }
  const fs::path folder = testing::fresh_directory("checkpoint_round_trip");
  const fs::path file = checkpoint_record_path(folder, "step", 1200);
  EXPECT_EQ(file.filename(), "step_0000001200.json");
  CheckpointState state = example_state(numbers);
  state.number("unknown", std::numeric_limits<double>::quiet_NaN());
  write_checkpoint_record(file, "compact", 1200, state);

  const CheckpointRecord record = read_checkpoint_record(file, "compact");
  EXPECT_EQ(record.stage, "compact");
  EXPECT_EQ(record.step, 1200);
  const CheckpointFields f = record.state();
  EXPECT_EQ(f.whole("steps"), -7);
  EXPECT_EQ(f.unsigned_whole("seed"), std::numeric_limits<std::uint64_t>::max());
  EXPECT_TRUE(f.flag("settled"));
  EXPECT_EQ(f.text("description"), "BMS sphere \"R\" = 1 mm");
  EXPECT_TRUE(std::isnan(f.number("unknown")));
  EXPECT_EQ(f.wholes("bins"), (std::vector<std::int64_t>{0, 65535, -1}));
  const std::vector<double> back = f.numbers("values");
  ASSERT_EQ(back.size(), numbers.size());
  for (std::size_t k = 0; k < numbers.size(); ++k) {
    EXPECT_EQ(std::memcmp(&back[k], &numbers[k], sizeof(double)), 0)
        << k << ": " << numbers[k] << " came back as " << back[k];
  }
  const std::vector<CheckpointFields> rows = f.list("rows");
  ASSERT_EQ(rows.size(), numbers.size());
  EXPECT_EQ(rows[3].whole("step"), 3);
  EXPECT_TRUE(std::signbit(rows[2].number("gap")));  // -0.0 stays negative
}

class CheckpointRefusal : public ::testing::Test {
 protected:
  void SetUp() override {
    folder = testing::fresh_directory("checkpoint_refusal");
    file = checkpoint_record_path(folder, "step", 40);
    write_checkpoint_record(file, "compact", 40, example_state({1.5, 2.5}));
    text = testing::read_text(file);
  }
  // Reading `file` as compact's throws an InputError naming the file and saying `what`.
  void expect_refused(const std::string& what, const std::function<void()>& read = {}) {
    try {
      if (read)
        read();
      else
        read_checkpoint_record(file, "compact");
      ADD_FAILURE() << "accepted: " << testing::read_text(file);
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(file.string()));
      EXPECT_THAT(e.what(), HasSubstr(what));
    }
  }
  void replace(const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from << " in " << text;
    std::string changed = text;
    changed.replace(at, from.size(), to);
    testing::write_text(file, changed);
  }
  fs::path folder, file;
  std::string text;
};

TEST_F(CheckpointRefusal, ACutShortRecordNamesTheFile) {
  testing::write_text(file, text.substr(0, text.size() / 2));
  expect_refused("not JSON or cut short");
  testing::write_text(file, "shapepress compact checkpoint 1\nsteps 40\n");  // an older format
  expect_refused("not JSON or cut short");
  replace("[1.5,", "[1e999,");  // past a double's range
  expect_refused("not a checkpoint record");
}

TEST_F(CheckpointRefusal, AnotherStagesRecordNamesTheStage) {
  expect_refused("key 'stage' is 'compact', not 'plate'",
                 [&] { read_checkpoint_record(file, "plate"); });
}

TEST_F(CheckpointRefusal, AnotherVersionNamesTheVersion) {
  replace("\"version\":1", "\"version\":2");
  expect_refused("key 'version' is 2");
}

TEST_F(CheckpointRefusal, AnotherFormatNamesTheKey) {
  replace("\"format\":\"shapepress checkpoint\"", "\"format\":\"a mesh\"");
  expect_refused("key 'format'");
  replace("\"format\":\"shapepress checkpoint\",", "");
  expect_refused("key 'format' is missing");
}

TEST_F(CheckpointRefusal, AMissingStepOrStateNamesTheKey) {
  replace("\"step\":40,", "");
  expect_refused("key 'step' is missing");
  replace("\"step\":40", "\"step\":-3");
  expect_refused("key 'step' is -3");
  replace(",\"state\":", ",\"status\":");
  expect_refused("key 'state' is missing");
}

TEST_F(CheckpointRefusal, AFieldMissingOrOfTheWrongTypeNamesItsKey) {
  const auto field = [&](const std::function<void(const CheckpointFields&)>& read) {
    return [&, read] {
      const CheckpointRecord record = read_checkpoint_record(file, "compact");
      read(record.state());
    };
  };
  expect_refused("key 'state.absent' is missing",
                 field([](const CheckpointFields& f) { f.number("absent"); }));
  expect_refused("key 'state.description' is \"BMS",
                 field([](const CheckpointFields& f) { f.number("description"); }));
  expect_refused("key 'state.steps' is -7, not in [0,",
                 field([](const CheckpointFields& f) { f.whole("steps", 0, 10); }));
  expect_refused("key 'state.seed' is", field([](const CheckpointFields& f) { f.whole("seed"); }));
  expect_refused("key 'state.settled' is true, not a number",
                 field([](const CheckpointFields& f) { f.number("settled"); }));
  expect_refused("key 'state.rows[1].gap_m' is missing", field([](const CheckpointFields& f) {
                   f.list("rows")[1].number("gap");
                   f.list("rows")[1].number("gap_m");
                 }));
  replace("\"gap\":2.5", "\"gap\":\"2.5\"");
  expect_refused("key 'state.rows[1].gap' is \"2.5\", not a number",
                 field([](const CheckpointFields& f) { f.list("rows")[1].number("gap"); }));
  replace("[0,65535,-1]", "[0,6.5,-1]");
  expect_refused("key 'state.bins[1]' is 6.5, not a whole number",
                 field([](const CheckpointFields& f) { f.wholes("bins"); }));
}

TEST(CheckpointRecords, AreListedByStepAndFoundBesideResumeJson) {
  const fs::path folder = testing::fresh_directory("checkpoint_records");
  EXPECT_FALSE(holds_checkpoints(folder));
  testing::write_text(folder / "resume.json", "{}");
  EXPECT_FALSE(holds_checkpoints(folder));  // how the run was started is not a checkpoint
  for (const std::int64_t step : {300, 20, 1000})
    write_checkpoint_record(checkpoint_record_path(folder, "particles", step), "generate", step,
                            CheckpointState());
  write_checkpoint_record(checkpoint_record_path(folder, "settle", 5), "compact", 5,
                          CheckpointState());
  EXPECT_TRUE(holds_checkpoints(folder));
  const auto records = checkpoint_records(folder, "particles");
  ASSERT_EQ(records.size(), 3u);
  EXPECT_EQ(records[0].first, 20);
  EXPECT_EQ(records[2].first, 1000);
  EXPECT_EQ(records[2].second.filename(), "particles_0000001000.json");
}

RunInvocation toy_invocation() {
  RunInvocation i;
  i.command_line = "shapepress toy --out run";
  i.working_directory = fs::current_path();
  i.config = "c.toml";
  return i;
}

TEST(ResumableRun, AFreshStartRecordsItsInvocationAndAResumeKeepsTheRecords) {
  const fs::path out = testing::fresh_directory("resumable_run");
  const fs::path folder = out / "checkpoints";
  fs::create_directories(folder);
  testing::write_text(folder / "step_0000000010.json", "another run's");
  {
    ResumableRun run("toy", out, folder, {.every_steps = 3, .minutes = 0.0});
    EXPECT_FALSE(run.start(false, toy_invocation()));
    EXPECT_FALSE(fs::exists(folder / "step_0000000010.json"));  // not this run's
    EXPECT_TRUE(fs::exists(folder / "resume.json"));
    int written = 0;
    for (std::int64_t step = 1; step <= 7; ++step)
      EXPECT_TRUE(run.after_step(step, [&] {
        write_checkpoint_record(checkpoint_record_path(folder, "step", step), "toy", step,
                                CheckpointState());
        ++written;
      }));
    EXPECT_EQ(written, 2);  // steps 3 and 6
  }
  testing::write_text(folder / ".step_0000000009.json.tmp.12345", "half");
  ResumableRun resumed("toy", out, folder, {.every_steps = 3, .minutes = 0.0});
  EXPECT_TRUE(resumed.start(true, toy_invocation()));
  EXPECT_TRUE(fs::exists(folder / "step_0000000006.json"));
  EXPECT_FALSE(fs::exists(folder / ".step_0000000009.json.tmp.12345"));
  resumed.finish();
  EXPECT_FALSE(fs::exists(folder));
  EXPECT_TRUE(fs::exists(out));
}

TEST(ResumableRun, ResumedWithoutARecordStartsAgain) {
  const fs::path out = testing::fresh_directory("resumable_run_again");
  const fs::path folder = out / "checkpoints";
  fs::create_directories(folder);
  testing::write_text(folder / "step_0000000010.h5", "a snapshot whose record never came");
  testing::write_text(folder / "step_0000000005.history", "an older build's text checkpoint");
  ResumableRun run("toy", out, folder, {});
  EXPECT_FALSE(run.start(true, toy_invocation()));
  EXPECT_FALSE(fs::exists(folder / "step_0000000010.h5"));
  EXPECT_FALSE(fs::exists(folder / "step_0000000005.history"));  // not read: warned of
  EXPECT_TRUE(fs::exists(folder / "resume.json"));
}

TEST(ResumableRun, AnErrorBeforeTheFirstRecordLeavesNoFolder) {
  const fs::path out = testing::fresh_directory("resumable_run_error");
  const fs::path folder = out / "checkpoints";
  try {
    ResumableRun run("toy", out, folder, {});
    run.start(false, toy_invocation());
    ASSERT_TRUE(fs::exists(folder / "resume.json"));
    throw InputError("bad input found while reading");
  } catch (const InputError&) {
  }
  EXPECT_FALSE(fs::exists(folder));
}

// (The signal stays noted for the rest of the process: ctest runs each test in its own.)
TEST(ResumableRun, ASignalStopsTheLoopAfterItsCheckpointWithItsExitCode) {
  const fs::path out = testing::fresh_directory("resumable_run_signal");
  const fs::path folder = out / "checkpoints";
  ResumableRun run("toy", out, folder, {.every_steps = 1000, .minutes = 0.0});
  run.start(false, toy_invocation());
  std::int64_t written = -1;
  EXPECT_TRUE(run.after_step(1, [&] { written = 1; }));
  std::raise(SIGTERM);
  EXPECT_FALSE(run.after_step(2, [&] { written = 2; }));
  EXPECT_EQ(written, 2);  // the checkpoint came with the signal, not at step 1000
  EXPECT_EQ(run.stopped(2), 128 + SIGTERM);
}

TEST(FinishedBeforeResume, AWholeRunIsLeftAsItIsButItsLeftoverCheckpoints) {
  const fs::path out = testing::fresh_directory("finished_before_resume");
  testing::write_text(out / "run.json", "{}");
  testing::write_text(out / "punch.csv", "step\n");
  fs::create_directories(out / "checkpoints");
  testing::write_text(out / "checkpoints" / "step_0000000010.json", "left by a kill");
  EXPECT_TRUE(finished_before_resume("toy", out.string(), out / "checkpoints", out / "run.json"));
  EXPECT_EQ(testing::read_text(out / "punch.csv"), "step\n");
  EXPECT_FALSE(fs::exists(out / "checkpoints"));
  // Not finished: resume.json is still there, or there is no run.json.
  fs::create_directories(out / "checkpoints");
  testing::write_text(out / "checkpoints" / "resume.json", "{}");
  EXPECT_FALSE(finished_before_resume("toy", out.string(), out / "checkpoints", out / "run.json"));
  fs::remove(out / "checkpoints" / "resume.json");
  fs::remove(out / "run.json");
  EXPECT_FALSE(finished_before_resume("toy", out.string(), out / "checkpoints", out / "run.json"));
}

}  // namespace
}  // namespace shapepress
