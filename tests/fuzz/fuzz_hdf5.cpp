// libFuzzer target: tests/fuzz/harnesses.hpp (run by scripts/fuzz.sh).
#include "tests/fuzz/harnesses_hdf5.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  shapepress::fuzz::hdf5(data, size);
  return 0;
}
