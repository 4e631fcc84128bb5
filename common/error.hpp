#pragma once
// Errors and the exit codes they map to (docs/architecture.md, "Exit codes and errors"):
// 0 success, 1 the computation failed, 2 bad input or usage.
#include <stdexcept>
#include <string>

namespace shapepress {

enum class ExitCode : int { ok = 0, computation_failed = 1, bad_input = 2 };

// Bad input or usage: the message names the file, the key or the value, and what was expected.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The computation could not finish (diverged, did not converge, an output could not be written
// after the inputs were accepted).
class ComputationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The exit code a caught exception stands for; anything we did not anticipate is a failed
// computation, never a silent success.
ExitCode exit_code_for(const std::exception& error) noexcept;

}  // namespace shapepress
