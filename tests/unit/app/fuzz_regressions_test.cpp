// The fuzzers' seed corpora and kept findings (tests/fuzz/corpus, tests/fuzz/regressions)
// replayed through their harnesses in the default suite: every reader of user files answers
// each with its result or an InputError, nothing else (a finding aborts the test program).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "tests/fuzz/harnesses.hpp"
#include "tests/fuzz/harnesses_hdf5.hpp"
#include "tests/fuzz/harnesses_image.hpp"
#include "tests/fuzz/harnesses_mesh.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;

const fs::path fuzz_folder = fs::path(SHAPEPRESS_TEST_DATA).parent_path() / "fuzz";

// Replays every file of corpus/<target>/ and regressions/<target>/; returns how many.
int replay(const std::string& target,
           const std::function<void(const std::uint8_t*, std::size_t)>& harness) {
  int inputs = 0;
  for (const char* kind : {"corpus", "regressions"}) {
    const fs::path folder = fuzz_folder / kind / target;
    if (!fs::is_directory(folder)) continue;
    for (const auto& entry : fs::directory_iterator(folder)) {
      std::ifstream in(entry.path(), std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
      SCOPED_TRACE(entry.path().string());
      harness(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
      ++inputs;
    }
  }
  return inputs;
}

TEST(FuzzRegressions, ConfigAndUnits) {
  EXPECT_GE(replay("config", fuzz::config), 3);
}

TEST(FuzzRegressions, Csv) {
  EXPECT_GE(replay("csv", fuzz::csv), 2);
}

TEST(FuzzRegressions, CheckpointRecords) {
  EXPECT_GE(replay("checkpoint", fuzz::checkpoint), 3);
}

TEST(FuzzRegressions, Meshes) {
  EXPECT_GE(replay("mesh", fuzz::mesh), 4);
}

TEST(FuzzRegressions, Images) {
  EXPECT_GE(replay("image", fuzz::image), 4);
}

TEST(FuzzRegressions, Hdf5Files) {
  EXPECT_GE(replay("hdf5", fuzz::hdf5), 1);
}

}  // namespace
}  // namespace shapepress
