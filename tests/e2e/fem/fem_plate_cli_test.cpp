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

// The solid's plasticity: a bad value or a material CalculiX cannot make plastic exits 2 naming
// the key, before CalculiX runs.
TEST(FemPlateCli, BadPlasticityExitsTwoNamingTheKey) {
  const fs::path dir = fresh_directory("fem_cli_plastic_keys");
  const std::string sphere = small_sphere(0.1, 4, 1e-4);
  const std::string section = "poisson_ratio = 0.46\n";
  const auto with = [&](const std::string& keys) {
    std::string text = sphere;
    text.replace(text.find(section), section.size(), section + keys);
    return text;
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"yield_stress = \"1 MPa\"\n", "sphere.material_model"},
      {"material_model = \"linear-elastic\"\nyield_stress = \"-1 MPa\"\n", "sphere.yield_stress"},
      {"material_model = \"linear-elastic\"\nhardening_modulus = \"1 MPa\"\n",
       "sphere.hardening_modulus"}};
  for (const auto& [keys, named] : cases) {
    testing::write_text(dir / "fem.toml", with(keys));
    const auto run = run_shapepress("fem-plate --config " + shell_quoted(dir / "fem.toml") +
                                    " --out " + shell_quoted(dir / "run"));
    EXPECT_EQ(run.exit_code, 2) << keys << run.output;
    EXPECT_THAT(run.output, HasSubstr(named)) << keys;
  }
}

// calibrate --reference FEM_RUN: a BMS sphere's bonds fitted to the FEM curve of the same sphere
// (a coarse mesh and few runs: the mechanics, not the study).
TEST(FemPlateCli, CalibrateTakesAnFemRunAsItsReference) {
  const fs::path dir = fresh_directory("fem_cli_calibrate");
  testing::write_text(dir / "fem.toml", small_sphere(0.4, 8, 1e-4));
  auto r = run_shapepress("--quiet fem-plate --config " + shell_quoted(dir / "fem.toml") +
                          " --out " + shell_quoted(dir / "fem"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path bms = testing::repository_root() / "pipelines/configs/rubber-sphere.toml";
  r = run_shapepress("--quiet calibrate --config " + shell_quoted(bms) + " --reference " +
                     shell_quoted(dir / "fem") +
                     " --count 60 --fit modulus --start modulus=1.9e7 --max-evaluations 4 --out " +
                     shell_quoted(dir / "cal"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const CsvTable evaluations = read_csv(dir / "cal" / "evaluations.csv");
  EXPECT_GE(evaluations.column("rms_relative").size(), 4u);
  std::ifstream record(dir / "cal" / "run.json");
  const nlohmann::json inputs = nlohmann::json::parse(record)["inputs"];
  EXPECT_THAT(inputs.dump(), HasSubstr("fem/force.csv"));

  // A folder that is not an FEM run, and an FEM sphere of another radius: exit 2.
  r = run_shapepress("--quiet calibrate --config " + shell_quoted(bms) + " --reference " +
                     shell_quoted(dir / "cal") + " --count 60 --out " + shell_quoted(dir / "x"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("fem-plate"));
  std::string other = small_sphere(0.4, 8, 1e-4);
  other.replace(other.find("10 mm"), 5, "5 mm");
  testing::write_text(dir / "other.toml", other);
  ASSERT_EQ(run_shapepress("--quiet fem-plate --config " + shell_quoted(dir / "other.toml") +
                           " --out " + shell_quoted(dir / "other"))
                .exit_code,
            0);
  r = run_shapepress("--quiet calibrate --config " + shell_quoted(bms) + " --reference " +
                     shell_quoted(dir / "other") + " --count 60 --out " + shell_quoted(dir / "y"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("radius"));
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
  // A curve that stops short is no calibration reference.
  const auto calibrate = run_shapepress(
      "--quiet calibrate --config " +
      shell_quoted(testing::repository_root() / "pipelines/configs/rubber-sphere.toml") +
      " --reference " + shell_quoted(dir / "run") + " --out " + shell_quoted(dir / "cal"));
  EXPECT_EQ(calibrate.exit_code, 2) << calibrate.output;
  EXPECT_THAT(calibrate.output, HasSubstr("completed = false"));
}

}  // namespace
}  // namespace shapepress
