// The multi-contact law from the command line: `plate --model multicontact`, a compaction with a
// size distribution, H0 at the loose fill height and the solid-fraction ceiling, and exit 2 with
// the key named for bad multi-contact input.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/csv.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::run_shapepress;
using shapepress::testing::test_data_text;
using shapepress::testing::write_text;
using ::testing::HasSubstr;

std::string plate_config(const std::string& interaction_extra) {
  return test_data_text("scenarios/rubber.toml") + interaction_extra +
         R"(
[sphere]
radius = "1 mm"
material = "rubber"

[plate]
material = "rubber"
speed = "5 mm/s"
max_deformation = 0.1
records = 10
)";
}

TEST(MulticontactPlate, ModelFlagAddsTheMultiContactTermAboveHertz) {
  const auto dir = fresh_directory("mc_plate");
  write_text(dir / "plate.toml", plate_config("multicontact_prefactor = 1.71\n"));
  // The config's law is Hertz with multi-contact keys: an error unless --model multicontact.
  const auto refused = run_shapepress("plate --config " + (dir / "plate.toml").string() +
                                      " --out " + (dir / "hertz").string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("normal_law = \"multicontact\""));
  const auto result =
      run_shapepress("plate --model multicontact --config " + (dir / "plate.toml").string() +
                     " --out " + (dir / "mc").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const CsvTable table = read_csv(dir / "mc" / "force.csv");
  const auto top = table.column("top_force_N"), hertz = table.column("hertz_force_N");
  // At 10 % deformation (δ = 0.1 R at each plate) each plate contact adds β ν π R δ 3p with p
  // = 2 (R - δ) F / (3V) from the two plate contacts: x = 3/2 β ν (δ/R)(1 - δ/R) F = 0.106 F,
  // and with the feedback through p the force is F_Hertz / (1 - x) = 1.119 F_Hertz.
  EXPECT_GT(top.back() / hertz.back(), 1.10);
  EXPECT_LT(top.back() / hertz.back(), 1.14);
  std::ifstream csv(dir / "mc" / "force.csv");
  const std::string text((std::istreambuf_iterator<char>(csv)), {});
  EXPECT_THAT(text, HasSubstr("normal law: multicontact"));
}

TEST(MulticontactPlate, BadMultiContactInputExitsWithTwoNamingTheKey) {
  const auto dir = fresh_directory("mc_bad");
  write_text(dir / "lambda.toml",
             plate_config("normal_law = \"multicontact\"\nplasticity_ratio = 0.0\n"));
  auto r = run_shapepress("plate --config " + (dir / "lambda.toml").string() + " --out " +
                          (dir / "o1").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("plasticity_ratio"));
  write_text(dir / "f0.toml",
             plate_config("normal_law = \"multicontact\"\npull_off_force = \"1 mN\"\n"));
  r = run_shapepress("plate --config " + (dir / "f0.toml").string() + " --out " +
                     (dir / "o2").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("pull_off_force"));
  write_text(dir / "law.toml", plate_config("normal_law = \"eepa\"\n"));
  r = run_shapepress("plate --config " + (dir / "law.toml").string() + " --out " +
                     (dir / "o3").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("normal_law"));
  r = run_shapepress("plate --model eepa --config " + (dir / "law.toml").string() + " --out " +
                     (dir / "o4").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

std::string compact_config(const std::string& punch_extra) {
  return test_data_text("scenarios/powder.toml") + R"(normal_law = "multicontact"
plasticity_ratio = 0.3
multicontact_prefactor = 1.3

[run]
record_every = 50

[box]
x = "4 mm"
y = "4 mm"
punch = "12 mm"
)" + test_data_text("scenarios/powder-die.toml") +
         R"(
[generate]
count = 60
diameter_min = "0.7 mm"
diameter_max = "1.3 mm"
size_quantiles = ["0.6 mm", "0.9 mm", "1.2 mm"]
size_quantile_levels = [0.1, 0.5, 0.9]
seed = 4
height = "10 mm"
settle_time = "30 ms"

[punch]
speed = "0.5 m/s"
target_strain = 0.8
unload_speed = "0.5 m/s"
strain_reference = "fill"
)" + punch_extra;
}

TEST(MulticontactCompact, StrainFromFillHeightStopsAtTheSolidFractionCeiling) {
  const auto dir = fresh_directory("mc_compact");
  write_text(dir / "compact.toml", compact_config("max_solid_fraction = 0.6\n"));
  const auto result = run_shapepress("--quiet compact --config " + (dir / "compact.toml").string() +
                                     " --out " + (dir / "run").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_THAT(result.output, HasSubstr("h0_m=0.01\n"));  // H0 = generate.height
  std::ifstream csv(dir / "run" / "punch.csv");
  const std::string text((std::istreambuf_iterator<char>(csv)), {});
  EXPECT_THAT(text, HasSubstr("H0 is the loose fill height"));
  EXPECT_THAT(text, HasSubstr("loading stops at the solid fraction ceiling 0.6"));
  const CsvTable table = read_csv(dir / "run" / "punch.csv");
  const auto fraction = table.column("solid_fraction");
  const auto strain = table.column("strain");
  const double peak = *std::max_element(fraction.begin(), fraction.end());
  EXPECT_GT(peak, 0.59);
  EXPECT_LT(peak, 0.605);          // one step past the ceiling at most
  EXPECT_GT(strain.front(), 0.0);  // the settled bed lies below the loose fill height
  const auto phase = table.column("phase");
  EXPECT_EQ(phase.back(), 3.0);  // unloaded to the end
}

TEST(MulticontactCompact, BadCeilingOrReferenceExitsWithTwo) {
  const auto dir = fresh_directory("mc_compact_bad");
  write_text(dir / "c1.toml", compact_config("max_solid_fraction = 1.2\n"));
  auto r = run_shapepress("--quiet compact --config " + (dir / "c1.toml").string() + " --out " +
                          (dir / "o1").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("max_solid_fraction"));
  std::string bad_sizes = compact_config("");
  bad_sizes.replace(bad_sizes.find("[0.1, 0.5, 0.9]"), 15, "[0.5, 0.1, 0.9]");
  write_text(dir / "c2.toml", bad_sizes);
  r = run_shapepress("--quiet compact --config " + (dir / "c2.toml").string() + " --out " +
                     (dir / "o2").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("increase"));
}

}  // namespace
}  // namespace shapepress
