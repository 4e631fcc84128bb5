#pragma once
// The HDF5 reading layer every HDF5 reader goes through (templates files, packings, snapshots:
// common/hdf5_file.hpp) under the fuzzers (tests/fuzz/harnesses.hpp): the file opened, its
// groups listed, and each dataset found there or at the paths the readers use read as the
// readers read them (numbers, strings, attributes). Its seed corpus holds one file of each kind
// as the writer makes them now (layout 2: fixed-length strings, checksummed); files of layout 1,
// whose variable-length strings HDF5 1.10.8 itself fails on (tests/fuzz/library-crashes), are
// kept out of it (tests/data/packing/README.md).
#include <vector>

#include "common/hdf5_file.hpp"
#include "tests/fuzz/harnesses.hpp"

namespace shapepress::fuzz {

inline void hdf5(const std::uint8_t* data, std::size_t size) {
  const InputFile file(data, size, "file.h5");
  expect_input_error_only([&] {
    const H5Reader reader(file.path());
    std::vector<std::string> datasets = {
        "/particles/position", "/particles/radius", "/bodies/centre", "/bonds/pairs",
        "/templates/name",     "/templates/source", "/scenario/names"};
    for (const char* group : {"/bms", "/cms", "/particles", "/bodies"})
      for (const std::string& member : reader.members(group)) {
        datasets.push_back(std::string(group) + "/" + member);
        for (const std::string& inner : reader.members(datasets.back()))
          datasets.push_back(datasets.back() + "/" + inner);
      }
    for (const std::string& dataset : datasets) {
      expect_input_error_only([&] { reader.doubles(dataset); });
      expect_input_error_only([&] { reader.int32s(dataset); });
      expect_input_error_only([&] { reader.strings(dataset); });
      expect_input_error_only([&] { reader.attribute_string(dataset, "unit"); });
    }
    expect_input_error_only([&] { reader.attribute_string("/", "command_line"); });
    expect_input_error_only([&] { reader.attribute_string("/", "format"); });
    expect_input_error_only([&] { reader.attribute_int64("/", "seed"); });
    expect_input_error_only([&] { reader.attribute_double("/", "box_x"); });
  });
}

}  // namespace shapepress::fuzz
