// One run at a time in an output (common/run_lock.hpp): a second lock on a held output is an
// InputError naming the holder; the lock goes with its holder and leaves no file or empty folder.
#include "common/run_lock.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>

#include "tests/support/errors.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::input_error_of;

TEST(RunFolderLock, ASecondLockOnAFolderNamesTheFirstHolder) {
  const fs::path scratch = testing::fresh_directory("run_lock");
  const fs::path run = scratch / "run";
  {
    const RunFolderLock first(run, RunOutput::folder, "shapepress compact --out run (the first)");
    EXPECT_TRUE(fs::is_directory(run));
    EXPECT_TRUE(fs::exists(run / ".shapepress.lock"));
    const std::string message =
        input_error_of([&] { const RunFolderLock second(run, RunOutput::folder, "the second"); });
    EXPECT_THAT(message, HasSubstr(run.string()));
    EXPECT_THAT(message, HasSubstr("in use by another run"));
    EXPECT_THAT(message, HasSubstr("pid " + std::to_string(::getpid())));
    EXPECT_THAT(message, HasSubstr("shapepress compact --out run (the first)"));
  }
  // Released: the folder it made is gone with it (nothing was written there), and a new run
  // takes the output.
  EXPECT_FALSE(fs::exists(run));
  const RunFolderLock again(run, RunOutput::folder, "the third");
  EXPECT_TRUE(fs::exists(run / ".shapepress.lock"));
}

TEST(RunFolderLock, AFolderWithOutputsStaysAndOnlyTheLockFileGoes) {
  const fs::path scratch = testing::fresh_directory("run_lock");
  const fs::path run = scratch / "a" / "b";
  {
    const RunFolderLock lock(run, RunOutput::folder, "run");
    testing::write_text(run / "punch.csv", "gap_m\n");
  }
  EXPECT_EQ(testing::files_under(scratch), std::vector<fs::path>{"a/b/punch.csv"});
  { const RunFolderLock lock(scratch / "c" / "d", RunOutput::folder, "run"); }
  EXPECT_FALSE(fs::exists(scratch / "c"));  // made by the lock, left empty: removed to the top
  EXPECT_TRUE(fs::exists(scratch));
}

TEST(RunFolderLock, AFileOutputIsLockedBesideItNotItsWholeFolder) {
  const fs::path scratch = testing::fresh_directory("run_lock");
  EXPECT_EQ(run_lock_path(scratch / "packed.h5", RunOutput::file), scratch / ".packed.h5.lock");
  const RunFolderLock packed(scratch / "packed.h5", RunOutput::file, "pack --out packed.h5");
  EXPECT_TRUE(fs::exists(scratch / ".packed.h5.lock"));
  // Another file in the same folder is another output.
  const RunFolderLock other(scratch / "other.h5", RunOutput::file, "pack --out other.h5");
  EXPECT_THAT(input_error_of([&] {
                const RunFolderLock again(scratch / "packed.h5", RunOutput::file, "again");
              }),
              HasSubstr("pack --out packed.h5"));
}

TEST(RunFolderLock, AHolderThatDiesReleasesItsLock) {
  const fs::path scratch = testing::fresh_directory("run_lock");
  const fs::path run = scratch / "run";
  int ready[2], release[2];
  ASSERT_EQ(::pipe(ready), 0);
  ASSERT_EQ(::pipe(release), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {  // holds the lock until told, then dies without its destructor (a crash)
    const RunFolderLock lock(run, RunOutput::folder, "the child");
    char c = 1;
    (void)!::write(ready[1], &c, 1);
    (void)!::read(release[0], &c, 1);
    ::_exit(9);
  }
  char c = 0;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  EXPECT_THAT(
      input_error_of([&] { const RunFolderLock second(run, RunOutput::folder, "the parent"); }),
      HasSubstr("the child"));
  ASSERT_EQ(::write(release[1], &c, 1), 1);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  // Its lock file is left (no destructor ran), but the lock went with the process.
  EXPECT_TRUE(fs::exists(run / ".shapepress.lock"));
  const RunFolderLock after(run, RunOutput::folder, "the parent");
  for (int fd : {ready[0], ready[1], release[0], release[1]})
    ::close(fd);
}

}  // namespace
}  // namespace shapepress
