#pragma once
// One `shapepress fem-plate` run of a config text in `dir` (fem.toml, run/), for the FEM
// validation tests: its force.csv and run.json facts.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "common/csv.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress::testing {

struct FemRun {
  CsvTable force;
  nlohmann::json facts;
};

inline FemRun press(const std::filesystem::path& dir, const std::string& config_text) {
  std::filesystem::create_directories(dir);
  write_text(dir / "fem.toml", config_text);
  const auto result =
      run_shapepress("--quiet fem-plate --config " + shell_quoted(dir / "fem.toml") + " --out " +
                     shell_quoted(dir / "run"));
  EXPECT_EQ(result.exit_code, 0) << result.output;
  std::ifstream in(dir / "run" / "run.json");
  return {read_csv(dir / "run" / "force.csv"), nlohmann::json::parse(in)["facts"]};
}

}  // namespace shapepress::testing
