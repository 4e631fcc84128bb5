#pragma once
// Scratch folders and files for end-to-end tests.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace shapepress::testing {

// SHAPEPRESS_FULL_VALIDATION=1 runs a study at the size its issue names; CI runs reduced ones.
inline bool full_validation() {
  const char* value = std::getenv("SHAPEPRESS_FULL_VALIDATION");
  return value != nullptr && std::string(value) == "1";
}

// The folders fresh_directory made in this process, removed when it ends if no test in it
// failed (ctest runs each test in a process of its own), kept for a look otherwise. Not by a
// forked child's exit: only the process that made them removes them.
class ScratchFolders {
 public:
  ScratchFolders() : owner_(::getpid()) {}
  ScratchFolders(const ScratchFolders&) = delete;
  ScratchFolders& operator=(const ScratchFolders&) = delete;
  ~ScratchFolders() {
    if (::getpid() != owner_) return;
    const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
    const bool failed = unit.failed_test_count() > 0 || unit.ad_hoc_test_result().Failed();
    for (const std::filesystem::path& folder : folders_) {
      if (failed) {
        std::printf("kept for a look: %s\n", folder.c_str());
        continue;
      }
      std::error_code ignored;
      std::filesystem::remove_all(folder, ignored);
    }
  }
  void add(std::filesystem::path folder) { folders_.push_back(std::move(folder)); }

 private:
  pid_t owner_;
  std::vector<std::filesystem::path> folders_;
};

inline ScratchFolders& scratch_folders() {
  static ScratchFolders folders;
  return folders;
}

// An empty folder shapepress_test_<name>_XXXXXX of its own in the system's temporary folder: a
// unique name (mkdtemp), so two runs of the suite, or tests under `ctest -j`, never share one;
// removed when the test process ends with every test passed (ScratchFolders).
inline std::filesystem::path fresh_directory(const std::string& name) {
  std::string pattern =
      (std::filesystem::temp_directory_path() / ("shapepress_test_" + name + "_XXXXXX")).string();
  if (::mkdtemp(pattern.data()) == nullptr) {
    ADD_FAILURE() << "cannot make a scratch folder " << pattern;
    return {};
  }
  scratch_folders().add(pattern);
  return pattern;
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

// Rows of a CSV of text cells, '#' lines skipped, each by column name (no quoted commas: the
// tables the stages write have none).
inline std::vector<std::map<std::string, std::string>> text_rows(
    const std::filesystem::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream split(line);
    for (std::string cell; std::getline(split, cell, ',');)
      cells.push_back(cell);
    if (header.empty()) {
      header = cells;
      continue;
    }
    auto& row = rows.emplace_back();
    for (std::size_t k = 0; k < std::min(cells.size(), header.size()); ++k)
      row[header[k]] = cells[k];
  }
  return rows;
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

// `text` (a TOML config) with `key = value` in its [table]: the key's line replaced, or added
// under the header. A missing table is a test failure (the config changed under the test).
inline std::string with_config_key(std::string text, const std::string& table,
                                   const std::string& key, const std::string& value) {
  const std::string header = "\n[" + table + "]\n";
  const std::size_t at = text.find(header);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no [" << table << "] to set " << key << " in: update the test";
    return text;
  }
  const std::size_t body = at + header.size();
  const std::size_t next = std::min(text.find("\n[", body), text.size());
  const std::size_t line = text.find("\n" + key + " = ", body - 1);
  if (line != std::string::npos && line < next) {
    const std::size_t end = text.find('\n', line + 1);
    text.replace(line + 1, end - line - 1, key + " = " + value);
  } else {
    text.insert(body, key + " = " + value + "\n");
  }
  return text;
}

}  // namespace shapepress::testing
