// libFuzzer target: tests/fuzz/harnesses.hpp (run by scripts/fuzz.sh).
#include "tests/fuzz/harnesses.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  shapepress::fuzz::checkpoint(data, size);
  return 0;
}
