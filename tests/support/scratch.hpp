#pragma once
// A folder of one test's own: a unique name (mkdtemp), so two runs of the suite, or two tests
// under `ctest -j`, never share one; removed when the test passed, kept with its path printed
// when it failed, for a look at what the run left.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

namespace shapepress::testing {

class ScratchFolder {
 public:
  explicit ScratchFolder(const std::string& name) {
    std::string pattern =
        (std::filesystem::temp_directory_path() / ("shapepress_" + name + "_XXXXXX")).string();
    if (::mkdtemp(pattern.data()) == nullptr)
      ADD_FAILURE() << "cannot make a scratch folder " << pattern;
    path_ = pattern;
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  ~ScratchFolder() {
    if (::testing::Test::HasFailure()) {
      std::printf("kept for a look: %s\n", path_.c_str());
      return;
    }
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& relative) const {
    return path_ / relative;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace shapepress::testing
