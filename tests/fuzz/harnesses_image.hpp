#pragma once
// The image loader (TIFF with SEM metadata, PNG, GIF, PGM) under the fuzzers
// (tests/fuzz/harnesses.hpp).
#include "imaging/load.hpp"
#include "imaging/sem_tiff.hpp"
#include "tests/fuzz/harnesses.hpp"

namespace shapepress::fuzz {

inline void image(const std::uint8_t* data, std::size_t size) {
  const std::string extension = pick_extension(data, size, {".tif", ".png", ".gif", ".pgm"});
  const InputFile file(data, size, "image" + extension);
  expect_input_error_only([&] { imaging::load_image(file.path()); });
  expect_input_error_only([&] { imaging::read_sem_metadata(file.path()); });
}

}  // namespace shapepress::fuzz
