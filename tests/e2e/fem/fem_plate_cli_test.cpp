// `shapepress fem-plate` from the command line (issue 26): what a user sees on a small mesh, the
// report reading its run, and the bad inputs: no CalculiX (exit 2 naming it) and an increment
// that does not converge (exit 1 naming the increment and the deformation reached, the converged
// part of the curve kept).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/csv.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using testing::fresh_directory;
using ::testing::HasSubstr;
using testing::run_shapepress;
using testing::shell_quoted;

// A coarse rubber sphere: seconds of CalculiX.
std::string small_sphere(double max_deformation, int increments, double minimum_increment) {
  return fmt::format(R"(
[sphere]
radius = "10 mm"
youngs_modulus = "18.5 MPa"
poisson_ratio = 0.46
[plate]
max_deformation = {}
[fem]
arc_elements = 6
coarse_arc_elements = 0
increments = {}
minimum_increment = {}
)",
                     max_deformation, increments, minimum_increment);
}

nlohmann::json facts_of(const fs::path& run) {
  std::ifstream in(run / "run.json");
  return nlohmann::json::parse(in)["facts"];
}

TEST(FemPlateCli, WritesPlateColumnsTheReportReads) {
  const fs::path dir = fresh_directory("fem_cli_run");
  testing::write_text(dir / "fem.toml", small_sphere(0.1, 4, 1e-4));
  const auto run = run_shapepress("fem-plate --config " + shell_quoted(dir / "fem.toml") +
                                  " --out " + shell_quoted(dir / "run"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("increment 4 converged, deformation 0.1"));
  for (const char* kept : {"sphere.inp", "sphere.dat", "sphere.frd", "sphere.log", "force.csv",
                           "effective.toml", "run.json"})
    EXPECT_TRUE(fs::exists(dir / "run" / kept)) << kept;
  const CsvTable force = read_csv(dir / "run" / "force.csv");
  ASSERT_EQ(force.column("deformation").size(), 5u);  // the undeformed row and 4 increments
  EXPECT_DOUBLE_EQ(force.column("deformation").back(), 0.1);
  EXPECT_GT(force.column("top_force_N").back(), force.column("hertz_force_N").back());
  EXPECT_GT(force.column("cpu_s").back(), 0.0);
  const nlohmann::json facts = facts_of(dir / "run");
  EXPECT_EQ(facts["particle_kind"], "fem");
  EXPECT_TRUE(facts["completed"].get<bool>());
  EXPECT_EQ(facts["elements"].get<int>(), 6 * 6 + 2 * 6 * 4);

  const auto report = run_shapepress("--quiet report " + shell_quoted(dir / "run") +
                                     " --poisson-ratio 0.46 --out " + shell_quoted(dir / "report"));
  ASSERT_EQ(report.exit_code, 0) << report.output;
  EXPECT_TRUE(fs::exists(dir / "report" / "report.html"));
}

TEST(FemPlateCli, MissingSolverExitsTwoNamingIt) {
  const fs::path dir = fresh_directory("fem_cli_no_ccx");
  testing::write_text(dir / "fem.toml", small_sphere(0.1, 4, 1e-4));
  const auto run =
      run_shapepress("fem-plate --config " + shell_quoted(dir / "fem.toml") +
                     " --ccx /nonexistent/ccx-not-here --out " + shell_quoted(dir / "run"));
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_THAT(run.output, HasSubstr("/nonexistent/ccx-not-here"));
  EXPECT_THAT(run.output, HasSubstr("calculix-ccx"));
}

TEST(FemPlateCli, UnknownKeyExitsTwo) {
  const fs::path dir = fresh_directory("fem_cli_key");
  testing::write_text(dir / "fem.toml", small_sphere(0.1, 4, 1e-4) + "elements = 3\n");
  const auto run = run_shapepress("fem-plate --config " + shell_quoted(dir / "fem.toml") +
                                  " --out " + shell_quoted(dir / "run"));
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_THAT(run.output, HasSubstr("fem.elements"));
}

// From 40 % to 80 % in one increment, with no cut-back allowed (the minimum increment is the
// increment): Newton does not converge in CalculiX's second increment.
TEST(FemPlateCli, NonConvergingIncrementExitsOneKeepingTheConvergedCurve) {
  const fs::path dir = fresh_directory("fem_cli_diverge");
  testing::write_text(dir / "fem.toml", small_sphere(0.8, 2, 0.5));
  const auto run = run_shapepress("fem-plate --config " + shell_quoted(dir / "fem.toml") +
                                  " --out " + shell_quoted(dir / "run"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_THAT(run.output, HasSubstr("did not converge in increment 2 (deformation 0.4 reached"));
  const CsvTable force = read_csv(dir / "run" / "force.csv");
  ASSERT_EQ(force.column("deformation").size(), 2u);
  EXPECT_DOUBLE_EQ(force.column("deformation").back(), 0.4);
  EXPECT_GT(force.column("top_force_N").back(), 0.0);
  const nlohmann::json facts = facts_of(dir / "run");
  EXPECT_FALSE(facts["completed"].get<bool>());
  EXPECT_DOUBLE_EQ(facts["deformation_reached"].get<double>(), 0.4);
  EXPECT_THAT(facts["failure"].get<std::string>(), HasSubstr("ERROR"));
}

}  // namespace
}  // namespace shapepress
