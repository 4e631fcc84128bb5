#pragma once
// The mesh readers (STL binary and ASCII, OFF, PLY) under the fuzzers (tests/fuzz/harnesses.hpp).
#include "geometry/mesh.hpp"
#include "tests/fuzz/harnesses.hpp"

namespace shapepress::fuzz {

inline void mesh(const std::uint8_t* data, std::size_t size) {
  const std::string extension = pick_extension(data, size, {".stl", ".off", ".ply"});
  const InputFile file(data, size, "mesh" + extension);
  expect_input_error_only([&] { geometry::read_mesh(file.path()); });
}

}  // namespace shapepress::fuzz
