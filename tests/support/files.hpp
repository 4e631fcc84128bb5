#pragma once
// Scratch folders and files for end-to-end tests.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace shapepress::testing {

// SHAPEPRESS_FULL_VALIDATION=1 runs a study at the size its issue names; CI runs reduced ones.
inline bool full_validation() {
  const char* value = std::getenv("SHAPEPRESS_FULL_VALIDATION");
  return value != nullptr && std::string(value) == "1";
}

// An empty folder shapepress_e2e_<name> in the system's temporary folder (emptied if it exists).
// Names carry the test suite's prefix, so suites running in parallel never share one.
inline std::filesystem::path fresh_directory(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("shapepress_e2e_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The repository's root (SHAPEPRESS_TEST_DATA is its tests/data), for shipped configs and
// pipelines.
inline std::filesystem::path repository_root() {
  return std::filesystem::path(SHAPEPRESS_TEST_DATA).parent_path().parent_path();
}

// A path in single quotes, for a shell command line.
inline std::string shell_quoted(const std::filesystem::path& p) {
  // Appended rather than "'" + p.string() + "'", which GCC 12 at -O3 warns about (-Wrestrict,
  // a false positive) where the path is inlined.
  std::string quoted = "'";
  quoted += p.string();
  quoted += '\'';
  return quoted;
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// A whole file as text (empty when it cannot be read: the caller's expectations then fail).
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A file of tests/data as text, e.g. the TOML preludes the end-to-end tests share
// (tests/data/scenarios/powder.toml).
inline std::string test_data_text(const std::filesystem::path& relative) {
  return read_text(std::filesystem::path(SHAPEPRESS_TEST_DATA) / relative);
}

// Every file under `folder`, relative to it, sorted (hidden temporaries included).
inline std::vector<std::filesystem::path> files_under(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) files.push_back(std::filesystem::relative(entry.path(), folder));
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace shapepress::testing
