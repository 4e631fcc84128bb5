// `shapepress plate --particle bms` and `shapepress calibrate` as a user runs them: force.csv
// with the columns, ParaView output with bonds as lines, a real calibration run, and
// exit 2 naming the cause for bad input (m_b <= 1, negative stiffness, too few sub-spheres,
// unbonded sub-spheres are refused by the engine: unit tests).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "common/csv.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::run_shapepress;
using shapepress::testing::shell_quoted;
using shapepress::testing::write_text;
using ::testing::HasSubstr;

const std::filesystem::path repo = shapepress::testing::repository_root();
const std::filesystem::path shipped = repo / "pipelines/configs/rubber-sphere.toml";

std::string shipped_text() {
  std::ifstream in(shipped);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The shipped config with one line replaced (the key must be there).
std::filesystem::path variant(const std::filesystem::path& dir, const std::string& pattern,
                              const std::string& replacement) {
  const std::string text = shipped_text();
  const std::string changed = std::regex_replace(text, std::regex(pattern), replacement);
  EXPECT_NE(text, changed) << pattern;
  const auto path = dir / "config.toml";
  std::ofstream(path) << changed;
  return path;
}

TEST(BmsPlateCli, WritesForceCsvWithBondsAndParaViewLines) {
  const auto dir = fresh_directory("bms_plate");
  // 40 % with 100 sub-spheres: a second of work.
  const auto r =
      run_shapepress("--quiet plate --config " + shell_quoted(shipped) +
                     " --particle bms --count 100 --snapshot --out " + shell_quoted(dir / "run"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const CsvTable t = read_csv(dir / "run" / "force.csv");
  for (const char* column : {"deformation", "approach_m", "top_force_N", "bottom_force_N",
                             "contacts", "intact_bonds", "cpu_s", "kinetic_energy_J", "work_J"})
    EXPECT_NO_THROW(t.column(column)) << column;
  const auto bonds = t.column("intact_bonds");
  EXPECT_GT(bonds.front(), 100);  // a connected lattice of 100 spheres has more bonds than spheres
  EXPECT_EQ(bonds.front(), bonds.back());
  EXPECT_NEAR(t.column("deformation").back(), 0.40, 0.005);
  const auto cpu = t.column("cpu_s");
  EXPECT_GE(cpu.back(), cpu.front());
  std::ifstream xdmf(dir / "run" / "final.xdmf");
  std::stringstream text;
  text << xdmf.rdbuf();
  EXPECT_THAT(text.str(), HasSubstr("TopologyType=\"Polyline\" NodesPerElement=\"2\""));
  EXPECT_THAT(text.str(), HasSubstr("/bonds/pairs"));
}

TEST(BmsPlateCli, BadInputExitsTwoNamingTheCause) {
  const auto dir = fresh_directory("bms_bad");
  auto r = run_shapepress(
      "--quiet plate --particle bms --count 100 --out " + shell_quoted(dir / "a") + " --config " +
      shell_quoted(variant(dir, "bond_multiplier = 1.15", "bond_multiplier = 1.0")));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("m_b = 1 must be > 1"));
  r = run_shapepress("--quiet plate --particle bms --count 100 --out " + shell_quoted(dir / "b") +
                     " --config " +
                     shell_quoted(variant(dir, "\nmodulus = \"", "\nmodulus = \"-")));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("bond modulus"));
  r = run_shapepress(
      "--quiet plate --particle bms --count 100 --out " + shell_quoted(dir / "b2") + " --config " +
      shell_quoted(
          variant(dir, "\nmodulus = \"[^\"]*\"\nshear_ratio = [^\n]*\n",
                  "\nnormal_stiffness = \"-1.15e6 N/m^3\"\nshear_stiffness = \"1.25e6 N/m^3\"\n")));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("normal stiffness"));
  r = run_shapepress("--quiet plate --config " + shell_quoted(shipped) +
                     " --particle bms --count 4 --out " + shell_quoted(dir / "c"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("too few"));
  r = run_shapepress("--quiet plate --config " + shell_quoted(shipped) + " --count 100 --out " +
                     shell_quoted(dir / "d"));
  EXPECT_EQ(r.exit_code, 2) << r.output;  // --count without --particle bms
  r = run_shapepress("--quiet plate --config " + shell_quoted(shipped) + " --fills 2 --out " +
                     shell_quoted(dir / "e"));
  EXPECT_EQ(r.exit_code, 2) << r.output;  // fills of a single Hertz sphere
  EXPECT_THAT(r.output, HasSubstr("--particle bms"));
  r = run_shapepress("--quiet plate --particle bms --count 100 --out " + shell_quoted(dir / "f") +
                     " --config " +
                     shell_quoted(variant(dir, "\nseed = 1\n", "\nseed = 1\nfills = 0\n")));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("fills"));
}

TEST(CalibrateCli, FitsTheBondModulusAndWritesAConfigThatRuns) {
  const auto dir = fresh_directory("bms_calibrate");
  const auto reference = std::filesystem::path(SHAPEPRESS_TEST_DATA) / "analysis" /
                         "tatara_hertz_R10mm_E18.5MPa_nu0.46.csv";
  // Few sub-spheres and runs: the mechanics of calibrate, not the study (validation does that).
  // The start is half the shipped modulus, which is near the optimum at N = 60 too.
  auto r = run_shapepress("--quiet calibrate --config " + shell_quoted(shipped) + " --reference " +
                          shell_quoted(reference) +
                          " --count 60 --fit modulus --start modulus=1.9e7 --max-evaluations 12"
                          " --out " +
                          shell_quoted(dir / "cal"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("Table 1, rubber 1.15e+06, 1.25e+06; Table 4, Avicel 8e+08"));
  const CsvTable evaluations = read_csv(dir / "cal" / "evaluations.csv");
  const auto rms = evaluations.column("rms_relative");
  EXPECT_GE(rms.size(), 5u);
  const double best = *std::min_element(rms.begin(), rms.end());
  EXPECT_LT(best, rms.front());  // the optimiser improved on the start
  r = run_shapepress("--quiet plate --config " + shell_quoted(dir / "cal" / "calibrated.toml") +
                     " --particle bms --out " + shell_quoted(dir / "run"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // calibrated.toml is complete: read and written again it is the same text, key for key.
  const std::string calibrated = shapepress::testing::read_text(dir / "cal" / "calibrated.toml");
  const std::string effective = shapepress::testing::read_text(dir / "run" / "effective.toml");
  EXPECT_EQ(effective.substr(effective.find("[[material]]")),
            calibrated.substr(calibrated.find("[[material]]")));
  for (const char* key : {"time_step_fraction = ", "max_overlap_fraction = ", "local_damping = ",
                          "max_deformation = ", "records = ", "bond_multiplier = ", "modulus = "})
    EXPECT_THAT(calibrated, HasSubstr(key));
  r = run_shapepress("--quiet calibrate --config " + shell_quoted(shipped) + " --reference " +
                     shell_quoted(reference) + " --fit stiffness --out " +
                     shell_quoted(dir / "bad"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("unknown parameter 'stiffness'"));
}

}  // namespace
}  // namespace shapepress
