#include "common/error.hpp"

namespace shapepress {

ExitCode exit_code_for(const std::exception& error) noexcept {
  if (dynamic_cast<const InputError*>(&error) != nullptr) return ExitCode::bad_input;
  return ExitCode::computation_failed;
}

}  // namespace shapepress
