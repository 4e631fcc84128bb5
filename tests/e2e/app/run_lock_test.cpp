// Two runs into one output (issue 42): the second, or a --resume of the run still running, is
// exit 2 naming the first and touches nothing of its; the first runs on undisturbed. The first is
// a real compaction, stopped by SIGTERM once the second was refused: the order of events is set
// by files the first writes, never by a wait of some seconds.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>

#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using shapepress::testing::read_text;
using shapepress::testing::run_command;
using shapepress::testing::shell_quoted;
using shapepress::testing::test_data_text;
using shapepress::testing::write_text;
using ::testing::HasSubstr;

// A small bed pressed so slowly that the run lasts far longer than the test needs it to.
std::string endless_compaction() {
  return test_data_text("scenarios/powder.toml") + test_data_text("scenarios/powder-die.toml") +
         R"(
[box]
x = "4 mm"
y = "4 mm"
punch = "12 mm"

[generate]
count = 30
diameter_min = "0.8 mm"
diameter_max = "1.2 mm"
seed = 3
settle_time = "1 ms"

[punch]
speed = "1 um/s"
target_strain = 0.05

[run]
checkpoint_every = 1000
)";
}

// A shell script: `command` in the background, then, once the shell test `ready` holds (or the
// command has ended), `then` ($pid is the command's). Built piece by piece: GCC 12 at -O3 warns
// falsely (-Wrestrict) on one long sum.
std::string when_ready(const std::string& command, const std::string& ready,
                       const std::string& then) {
  std::string script = "(";
  script += command;
  script += " & pid=$!; while ! { ";
  script += ready;
  script += "; } >/dev/null 2>&1 && kill -0 $pid 2>/dev/null; do sleep 0.02; done; ";
  script += then;
  script += ")";
  return script;
}

// The value of `name=` in the lines the shell script below prints.
int printed(const std::string& output, const std::string& name) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex(name + "=(\\d+)"))) return -1;
  return std::stoi(m[1].str());
}

TEST(RunLock, ASecondRunIntoARunningOneIsRefusedNamingTheFirst) {
  const fs::path scratch = testing::fresh_directory("run_lock");
  write_text(scratch / "c.toml", endless_compaction());
  const std::string binary = SHAPEPRESS_BINARY;
  const std::string run = shell_quoted(scratch / "run");
  std::string first = binary;
  first += " --threads 1 compact --config ";
  first += shell_quoted(scratch / "c.toml");
  first += " --out ";
  first += run;
  first += " > ";
  first += shell_quoted(scratch / "first.log");
  first += " 2>&1";
  std::string second = binary;
  second += " --quiet compact --config ";
  second += shell_quoted(scratch / "c.toml");
  second += " --out ";
  second += run;
  second += "; echo second=$?; ";
  second += binary;
  second += " --quiet compact --resume ";
  second += run;
  second +=
      "; echo resume=$?; kill -0 $pid && echo running=1; kill -TERM $pid; wait $pid; "
      "echo first=$?";
  // The first starts; once its first checkpoint is out (it is well into its steps, and holds its
  // folder), a second run into the folder and a --resume of it are each refused; then the first
  // is stopped, and says how it ended.
  const std::string script = when_ready(first, "ls " + run + "/checkpoints/*_*.json", second);
  const auto result = run_command(script);
  EXPECT_EQ(printed(result.output, "second"), 2) << result.output;
  EXPECT_EQ(printed(result.output, "resume"), 2) << result.output;
  EXPECT_EQ(printed(result.output, "running"), 1) << result.output;
  // The first was still stepping, and stopped by the signal with a checkpoint (128 + SIGTERM).
  EXPECT_EQ(printed(result.output, "first"), 128 + 15)
      << result.output << read_text(scratch / "first.log");
  // Each refusal names the output and the first run: its pid, its command.
  const std::regex refusal(
      "compact: error: .*/run: in use by another run \\(pid \\d+ on .*" +
      std::regex_replace(scratch.string(), std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") +
      "/c.toml --out .*/run\\)");
  const std::string& out = result.output;
  EXPECT_EQ(
      std::distance(std::sregex_iterator(out.begin(), out.end(), refusal), std::sregex_iterator()),
      2)
      << out;
  EXPECT_THAT(out, HasSubstr("--threads 1 compact"));  // the first's command, not the second's
  // Nothing of the first's was touched: its start record is its own, its checkpoint resumable.
  EXPECT_THAT(read_text(scratch / "run" / "checkpoints" / "resume.json"),
              HasSubstr("--threads 1 compact"));
  EXPECT_THAT(read_text(scratch / "first.log"), HasSubstr("--resume"));
  EXPECT_FALSE(fs::exists(scratch / "run" / ".shapepress.lock"));  // the first let go on exit
}

TEST(RunLock, AKilledRunLeavesItsFolderFree) {
  const fs::path scratch = testing::fresh_directory("run_lock");
  write_text(scratch / "c.toml", endless_compaction());
  const std::string start =
      std::string(SHAPEPRESS_BINARY) + " --quiet --threads 1 compact --config " +
      shell_quoted(scratch / "c.toml") + " --out " + shell_quoted(scratch / "run");
  // Killed with SIGKILL (no handler runs) once its first checkpoint is out.
  const auto killed =
      run_command(when_ready(start, "ls " + shell_quoted(scratch / "run") + "/checkpoints/*_*.json",
                             "kill -KILL $pid; wait $pid"));
  EXPECT_EQ(killed.exit_code, 128 + 9) << killed.output;
  EXPECT_TRUE(fs::exists(scratch / "run" / ".shapepress.lock"));  // its file, but not its lock
  // The next run takes the folder at once, and when it ends its lock file is gone. (A --resume
  // after SIGKILL, with the lock file left, is the kill tests' (CompactResume, PackResume, …).)
  const auto next = run_command(start + " --steps 1");
  EXPECT_EQ(next.exit_code, 0) << next.output;
  EXPECT_FALSE(fs::exists(scratch / "run" / ".shapepress.lock"));
  EXPECT_TRUE(fs::exists(scratch / "run" / "punch.csv"));
}

}  // namespace
}  // namespace shapepress
