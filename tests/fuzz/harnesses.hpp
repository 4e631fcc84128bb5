#pragma once
// What each fuzzer does with one input (issue 23, "Fuzzing"): hand the bytes to a reader of
// user files as a file or a string, and accept only an InputError (exit 2 naming the file) or
// success. Any other exception, a crash or a sanitizer report is a finding. The libFuzzer
// targets (tests/fuzz/fuzz_*.cpp, CMake option SHAPEPRESS_FUZZ) and the replay of the kept
// findings in the default suite (tests/unit/app/fuzz_regressions_test.cpp) both call
// these, so a finding fixed stays fixed without clang.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "common/checkpoint.hpp"
#include "common/config.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/units.hpp"

namespace shapepress::fuzz {

// The input as a file named `name` in a folder of this process (readers take paths).
class InputFile {
 public:
  InputFile(const std::uint8_t* data, std::size_t size, const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("shapepress_fuzz_" + std::to_string(::getpid())) / name) {
    std::filesystem::create_directories(path_.parent_path());
    std::ofstream(path_, std::ios::binary)
        .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;
  ~InputFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
    std::filesystem::remove(path_.parent_path(), ignored);  // when no other input is in it
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Runs `read`; an InputError is the reader's answer to a bad file, anything else a finding.
template <class Read>
void expect_input_error_only(Read&& read) {
  try {
    read();
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "not an InputError: %s\n", e.what());
    std::abort();
  }
}

// The extension chosen by the first byte, the rest the file's content: one fuzzer reaches every
// format a reader tells apart by extension.
inline std::string pick_extension(const std::uint8_t*& data, std::size_t& size,
                                  std::initializer_list<const char*> extensions) {
  if (size == 0) return *extensions.begin();
  const std::size_t k = data[0] % extensions.size();
  ++data, --size;
  return *(extensions.begin() + static_cast<std::ptrdiff_t>(k));
}

// A TOML config read as the stages read theirs: typed getters on fixed keys (numbers, integers,
// quantities with units, lists, sub-tables), then the unknown-key check; and the text as a
// quantity with a unit.
inline void config(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  expect_input_error_only([&] { parse_quantity(text, "fuzz"); });
  expect_input_error_only([&] { parse_quantity(text, dim::pressure, "fuzz"); });
  expect_input_error_only([&] {
    const ConfigTable root = ConfigTable::parse(text, "fuzz.toml");
    for (const char* section : {"a", "run", "material"}) {
      if (!root.has(section)) continue;
      const ConfigTable t = root.table(section);
      expect_input_error_only([&] { t.number("x", 0.0, Range::positive()); });
      expect_input_error_only([&] { t.integer("n", 1, Range::at_least(0)); });
      expect_input_error_only([&] { t.quantity("l", dim::length, 1.0); });
      expect_input_error_only([&] { t.quantity("e", dim::pressure, std::nullopt); });
      expect_input_error_only([&] { t.quantities("q", dim::length); });
      expect_input_error_only([&] { t.numbers("v"); });
      expect_input_error_only([&] { t.boolean("b", false); });
      expect_input_error_only([&] { t.choice("c", {"one", "two"}, "one"); });
    }
    if (root.has("m"))
      for (const ConfigTable& t : root.tables("m"))
        expect_input_error_only([&] { t.quantity("density", dim::density); });
    root.check_unknown_keys();
  });
}

// A CSV table of numbers with a header, as reference curves and punch.csv are read.
inline void csv(const std::uint8_t* data, std::size_t size) {
  const InputFile file(data, size, "table.csv");
  expect_input_error_only([&] {
    const CsvTable table = read_csv(file.path());
    for (const std::string& name : table.columns)
      table.column(name);
  });
}

// A checkpoint record (common/checkpoint.hpp) a killed run left, read as a stage reads its
// state: the record's keys, then typed fields of the state and of the items of its lists.
inline void checkpoint(const std::uint8_t* data, std::size_t size) {
  const InputFile file(data, size, "step_0000000001.json");
  expect_input_error_only([&] {
    const CheckpointRecord record = read_checkpoint_record(file.path(), "compact");
    const CheckpointFields state = record.state();
    state.whole("steps", 0, 1000000);
    state.number("loop_s");
    state.unsigned_whole("seed");
    state.flag("settled");
    state.text("description");
    state.numbers("axes");
    state.wholes("bins");
    for (const CheckpointFields& item : state.list("records")) {
      item.number("gap");
      item.whole("phase");
    }
  });
}

}  // namespace shapepress::fuzz
