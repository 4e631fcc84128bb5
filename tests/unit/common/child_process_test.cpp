// A child process runs in its folder with its environment, its output reaches the log (and the
// line callback, a last line without a newline too), and its end is told as an exit status or a
// signal; a program that is not there is an input error naming it.
#include <unistd.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "common/child_process.hpp"
#include "common/error.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

class ChildProcessTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              ("shapepress-child-" + std::to_string(::getpid()) + "-" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  std::string log_text() const {
    std::ifstream in(folder_ / "log.txt");
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  ChildCommand shell(const std::string& script) const {
    return {{"sh", "-c", script}, "the shell", "", {}, {}, folder_ / "log.txt"};
  }
  fs::path folder_;
};

TEST_F(ChildProcessTest, OutputAndErrorsGoToTheLog) {
  const ChildEnd end = run_child(shell("echo out; echo err >&2; exit 3"));
  EXPECT_EQ(end.exit_code, 3);
  EXPECT_EQ(end.signal, 0);
  EXPECT_EQ(end.how(), "exit status 3");
  EXPECT_EQ(log_text(), "out\nerr\n");
}

TEST_F(ChildProcessTest, LinesArriveAsPrintedTheLastOneWithoutANewlineToo) {
  std::vector<std::string> lines;
  const ChildEnd end =
      run_child(shell("printf 'one\\ntwo\\nthree'"), [&](const std::string& line, int pid, double) {
        EXPECT_GT(pid, 0);
        lines.push_back(line);
      });
  EXPECT_EQ(end.exit_code, 0);
  EXPECT_THAT(lines, ElementsAre("one", "two", "three"));
  EXPECT_EQ(log_text(), "one\ntwo\nthree\n");
}

TEST_F(ChildProcessTest, RunsInItsFolderWithItsEnvironment) {
  fs::create_directories(folder_ / "work");
  ChildCommand command = shell("pwd; echo \"$SHAPEPRESS_CHILD_TEST\"");
  command.folder = folder_ / "work";
  command.environment = {"SHAPEPRESS_CHILD_TEST=set by the parent"};
  EXPECT_EQ(run_child(command).exit_code, 0);
  EXPECT_EQ(log_text(), fs::canonical(folder_ / "work").string() + "\nset by the parent\n");
}

TEST_F(ChildProcessTest, ASignalIsToldAsOne) {
  const ChildEnd end = run_child(shell("kill -9 $$"));
  EXPECT_EQ(end.signal, 9);
  EXPECT_EQ(end.exit_code, 128 + 9);
  EXPECT_THAT(end.how(), HasSubstr("signal 9"));
}

TEST_F(ChildProcessTest, AMissingProgramIsAnInputErrorNamingIt) {
  ChildCommand command = shell("");
  command.arguments = {"shapepress-no-such-program", "-v"};
  command.role = "the mesher";
  command.install_hint = "install it";
  try {
    run_child(command);
    FAIL() << "a missing program ran";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("the mesher 'shapepress-no-such-program'"));
    EXPECT_THAT(e.what(), HasSubstr("(install it)"));
  }
  // With the output followed through a pipe as well.
  EXPECT_THROW(run_child(command, [](const std::string&, int, double) {}), InputError);
}

}  // namespace
}  // namespace shapepress
