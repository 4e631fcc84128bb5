// `shapepress advise --bed-runs` as a user runs it on a bed-size ladder (issue 40, point 3): a
// tiny bed packed at two sizes with two seeds each and pressed, the runs made from inside their
// bed's folder (relative packing paths, as a study's scripts make them), then judged: the table,
// the charts with the seeds' scatter, the pick with its seeds and predicted cost in run.json; a
// packing given twice is refused, naming the run.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/csv.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::run_command;
using shapepress::testing::run_shapepress;
using shapepress::testing::shell_quoted;
using shapepress::testing::test_data_text;
using shapepress::testing::write_text;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

TEST(AdviseBedSizeCli, JudgesFinishedBedsOfTwoSizesAndSeedsAndNamesThePick) {
  const fs::path dir = fresh_directory("advise_bed_size");
  const auto fill = run_shapepress(
      "--quiet fill --ellipsoid 150um,125um,110um --kind bms --count 20 --lattice random --out " +
      shell_quoted(dir / "templates.h5"));
  ASSERT_EQ(fill.exit_code, 0) << fill.output;
  // tests/e2e/scenarios/advise_compaction_cli_test.cpp's tiny bed: Avicel-like ellipsoids of
  // 250-350 µm in a 0.8 mm die, Table 4's bonded bodies pressed by 30 % at mass scaling 100.
  write_text(dir / "pack.toml",
             "[pack]\ncount = 6\nbox_x = 0.8e-3\nbox_y = 0.8e-3\n"
             "[[template]]\nname = \"bms/ellipsoid\"\n"
             "[sizes]\nsize_quantiles = [82.9e-6, 224.6e-6, 379.3e-6]\n"
             "size_quantile_levels = [0.1, 0.5, 0.9]\n"
             "diameter_min = 250e-6\ndiameter_max = 350e-6\n"
             "[settle]\nkinetic_energy_ratio = 1e-4\n");
  write_text(dir / "compact.toml",
             test_data_text("scenarios/bonded-bed.toml") +
                 "\n[box]\nx = \"0.8 mm\"\ny = \"0.8 mm\"\nbottom = \"0 mm\"\n"
                 "\n[run]\nrecord_every = 100\ndensity_scale = 100\n"
                 "\n[punch]\nmode = \"displacement\"\nspeed = \"0.05 m/s\"\n"
                 "target_strain = 0.3\nunload_speed = \"0.05 m/s\"\n");
  std::string runs;
  for (int bodies : {6, 12})
    for (int seed : {1, 2}) {
      const fs::path bed = dir / fmt::format("b{}-s{}", bodies, seed);
      fs::create_directories(bed);
      const std::string in_bed =
          fmt::format("cd {} && {} --quiet --threads 2 ", shell_quoted(bed), SHAPEPRESS_BINARY);
      const auto pack = run_command(fmt::format(
          "{}pack ../templates.h5 --config ../pack.toml --count {} --seed {} --out packed.h5",
          in_bed, bodies, seed));
      ASSERT_EQ(pack.exit_code, 0) << pack.output;
      const auto pressed =
          run_command(in_bed + "compact --config ../compact.toml --packing packed.h5 --out run");
      ASSERT_EQ(pressed.exit_code, 0) << pressed.output;
      runs += fmt::format("{}{}", runs.empty() ? "" : ",", (bed / "run").string());
    }
  const fs::path out = dir / "advice";
  const auto advised = run_shapepress("--quiet advise --tolerance 0.9 --bed-runs " +
                                      shell_quoted(runs) + " --out " + shell_quoted(out));
  ASSERT_EQ(advised.exit_code, 0) << advised.output;
  const CsvTable table = read_csv(out / "bed_size.csv");
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.column("bodies"), (std::vector<double>{6, 12}));
  EXPECT_EQ(table.column("sub_spheres"), (std::vector<double>{20, 20}));
  EXPECT_EQ(table.column("seeds"), (std::vector<double>{2, 2}));
  EXPECT_EQ(table.column("reference"), (std::vector<double>{0, 1}));
  for (double sd : table.column("peak_stress_sd"))
    EXPECT_GT(sd, 0.0);  // two packings differ
  std::ifstream in(out / "run.json");
  const nlohmann::json facts = nlohmann::json::parse(in).at("facts");
  EXPECT_EQ(facts.at("reference_bodies").get<int>(), 12);
  EXPECT_EQ(facts.at("runs").get<int>(), 4);
  EXPECT_GE(facts.at("pick_seeds_needed").get<int>(), 1);
  EXPECT_GT(facts.at("predicted_counted_cost").get<double>(), 0.0);
  for (const char* chart : {"bed_size_peak_stress.svg", "bed_size_elastic_recovery.svg",
                            "bed_size_yield_pressure.svg", "bed_speed_accuracy.svg"})
    EXPECT_TRUE(fs::exists(out / chart)) << chart;

  // One packing twice is one seed counted twice: refused, naming it.
  const std::string first = runs.substr(0, runs.find(','));
  const auto twice =
      run_shapepress("--quiet advise --bed-runs " + shell_quoted(runs + "," + first) + " --out " +
                     shell_quoted(dir / "twice"));
  EXPECT_EQ(twice.exit_code, 2) << twice.output;
  EXPECT_THAT(twice.output, HasSubstr("one run per packing"));
  // Neither a ladder to run nor runs to judge.
  const auto neither = run_shapepress("--quiet advise --out " + shell_quoted(dir / "neither"));
  EXPECT_EQ(neither.exit_code, 2) << neither.output;
  EXPECT_THAT(neither.output, HasSubstr("--bed-runs"));
}

}  // namespace
}  // namespace shapepress
