// libFuzzer target: tests/fuzz/harnesses.hpp (run by scripts/fuzz.sh).
#include "tests/fuzz/harnesses_image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  shapepress::fuzz::image(data, size);
  return 0;
}
