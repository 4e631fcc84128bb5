#pragma once
// Runs the shapepress binary (or any command) for end-to-end tests and captures what a user
// would see: the exit code and stdout+stderr together.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace shapepress::testing {

struct CommandResult {
  int exit_code = -1;
  std::string output;
};

inline CommandResult run_command(const std::string& command_line) {
  CommandResult result;
  FILE* pipe = ::popen((command_line + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr)
    result.output += buffer.data();
  int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

#ifdef SHAPEPRESS_BINARY
// `arguments` after the binary's path, e.g. "plate --config x.toml --out dir".
inline CommandResult run_shapepress(const std::string& arguments) {
  return run_command(std::string(SHAPEPRESS_BINARY) + " " + arguments);
}
#endif

}  // namespace shapepress::testing
