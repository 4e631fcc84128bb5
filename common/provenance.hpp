#pragma once
// What made a file: written as root attributes of every HDF5 file and into JSON outputs, so a
// result can be traced to the binary, the command and the config that produced it.
#include <cstdint>
#include <optional>
#include <string>

namespace shapepress {

struct Provenance {
  std::string command_line;
  std::string config_text;
  std::optional<std::uint64_t> seed;
};

std::string shapepress_version();       // "0.1.0"
std::string shapepress_git_revision();  // "3f2a9c1e0b7d" or "…-dirty"

}  // namespace shapepress
