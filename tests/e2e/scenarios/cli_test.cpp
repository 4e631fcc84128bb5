// `shapepress plate` and `shapepress compact` as a user runs them: outputs, exit codes,
// restart from a snapshot, errors naming the key.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <regex>
#include <string>
#include <vector>

#include "common/csv.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::read_text;
using shapepress::testing::run_shapepress;
using shapepress::testing::write_text;
using ::testing::HasSubstr;

const std::string materials = shapepress::testing::test_data_text("scenarios/powder.toml");

// The bed a compaction pours when no --packing is given.
const std::string generated_bed = R"(
[generate]
count = 150
diameter_min = "0.8 mm"
diameter_max = "1.2 mm"
seed = 3
settle_time = "20 ms"
)";

std::string compact_config(const std::string& extra_run = "",
                           const std::string& bed = generated_bed) {
  return materials + R"(
[run]
record_every = 50
snapshot_every = 1000
gravity = [0.0, 0.0, -9.81]
)" + extra_run +
         R"(
[box]
x = "6 mm"
y = "6 mm"
punch = "20 mm"
)" + shapepress::testing::test_data_text("scenarios/powder-die.toml") +
         bed + R"(
[punch]
speed = "0.5 m/s"
target_strain = 0.1
hold_time = "0.5 ms"
unload_speed = "0.5 m/s"
)";
}

TEST(Plate, WritesForceCsvFollowingHertz) {
  const auto dir = fresh_directory("simulate_plate");
  write_text(dir / "plate.toml", materials + R"(
[sphere]
radius = "0.5 mm"
material = "powder"

[plate]
material = "powder"
speed = "0.005 m/s"
max_deformation = 0.01
records = 10
)");
  const auto result = run_shapepress("plate --config " + (dir / "plate.toml").string() + " --out " +
                                     (dir / "out").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const CsvTable table = read_csv(dir / "out" / "force.csv");
  const auto top = table.column("top_force_N");
  const auto hertz = table.column("hertz_force_N");
  ASSERT_EQ(top.size(), 10u);
  EXPECT_NEAR(top.back() / hertz.back(), 1.0, 0.01);  // quasi-static at 1 % deformation
  EXPECT_EQ(table.column("bottom_force_N").size(), 10u);
}

TEST(Plate, ShippedRubberSphereConfigRuns) {
  const auto dir = fresh_directory("simulate_plate_shipped");
  const std::filesystem::path config = std::filesystem::path(SHAPEPRESS_TEST_DATA) / ".." / ".." /
                                       "pipelines" / "configs" / "plate-rubber-sphere.toml";
  const auto result =
      run_shapepress("plate --config " + config.string() + " --out " + dir.string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const CsvTable table = read_csv(dir / "force.csv");
  // The paper's rubber sphere at 1 % deformation: Hertz within the validation tolerance.
  EXPECT_NEAR(table.column("top_force_N").back() / table.column("hertz_force_N").back(), 1.0,
              0.005);
}

TEST(Plate, RunKeyTheRigDoesNotUseIsExitTwoNamingIt) {
  const auto dir = fresh_directory("simulate_plate_unused");
  for (const std::string& key :
       std::vector<std::string>{"gravity = [0.0, 0.0, -9.81]", "steps = 1000"}) {
    write_text(dir / "plate.toml", materials + "\n[run]\n" + key + R"(
[sphere]
radius = "0.5 mm"
material = "powder"

[plate]
material = "powder"
speed = "0.005 m/s"
)");
    const auto result = run_shapepress("plate --config " + (dir / "plate.toml").string() +
                                       " --out " + (dir / "out").string());
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_THAT(result.output, HasSubstr("'run." + key.substr(0, key.find(' ')) + "' is not used"));
  }
}

TEST(Plate, SkinTakesEffectAndTheEffectiveConfigRunsTheSameCurve) {
  const auto dir = fresh_directory("simulate_plate_effective");
  write_text(dir / "plate.toml", materials + R"(
[run]
skin = "0.02 mm"

[sphere]
radius = "0.5 mm"
material = "powder"

[plate]
material = "powder"
speed = "0.005 m/s"
records = 10
)");
  auto result = run_shapepress("plate --config " + (dir / "plate.toml").string() + " --out " +
                               (dir / "a").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string effective = read_text(dir / "a" / "effective.toml");
  EXPECT_THAT(effective, HasSubstr("skin = 2e-05\n"));
  EXPECT_THAT(effective, HasSubstr("max_deformation = 0.01\n"));  // defaults written too
  result = run_shapepress("plate --config " + (dir / "a" / "effective.toml").string() + " --out " +
                          (dir / "b").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(read_csv(dir / "b" / "force.csv").column("top_force_N"),
            read_csv(dir / "a" / "force.csv").column("top_force_N"));
  const std::string again = read_text(dir / "b" / "effective.toml");
  EXPECT_EQ(again.substr(again.find("[[material]]")),
            effective.substr(effective.find("[[material]]")));
}

TEST(Compact, LoadHoldUnloadWithSnapshotsAndRestart) {
  const auto dir = fresh_directory("simulate_compact");
  write_text(dir / "compact.toml", compact_config());
  const auto result = run_shapepress("--quiet compact --config " + (dir / "compact.toml").string() +
                                     " --out " + (dir / "run").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_THAT(result.output, HasSubstr("SUMMARY"));
  const CsvTable punch = read_csv(dir / "run" / "punch.csv");
  const auto phase = punch.column("phase");
  const auto stress = punch.column("stress_Pa");
  const auto strain = punch.column("strain");
  EXPECT_EQ(phase.front(), 0.0);
  EXPECT_EQ(phase.back(), 3.0);  // done: unloaded until the punch force vanished
  EXPECT_GT(*std::max_element(stress.begin(), stress.end()), 0.0);
  EXPECT_GE(*std::max_element(strain.begin(), strain.end()), 0.1);
  EXPECT_EQ(stress.back(), 0.0);
  std::ifstream xdmf(dir / "run" / "snapshots.xdmf");
  const std::string index((std::istreambuf_iterator<char>(xdmf)), std::istreambuf_iterator<char>());
  EXPECT_THAT(index, HasSubstr("Polyvertex"));  // spheres as points for ParaView's glyphs
  EXPECT_THAT(index, HasSubstr("snapshots/step_0000001000.h5:/particles/radius"));
  EXPECT_THAT(index, HasSubstr("Quadrilateral"));  // the punch and the bottom plate
  const auto snapshot = dir / "run" / "snapshots" / "step_0000001000.h5";
  ASSERT_TRUE(std::filesystem::exists(snapshot));

  const auto resumed =
      run_shapepress("--quiet compact --config " + (dir / "compact.toml").string() + " --restart " +
                     snapshot.string() + " --out " + (dir / "resumed").string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const CsvTable again = read_csv(dir / "resumed" / "punch.csv");
  // The resumed run ends on the same row, bit for bit (10 significant digits in the CSV).
  EXPECT_EQ(again.rows.back(), punch.rows.back());
}

TEST(Compact, ReadsAPlainTextPacking) {
  const auto dir = fresh_directory("simulate_packing");
  write_text(dir / "packing.txt",
             "# x y z r\n0.001 0.001 0.0006 0.0005\n0.003 0.003 0.0006 0.0005\n");
  // No [generate]: without the packing the run has no spheres and exits 2.
  write_text(dir / "compact.toml", compact_config("", ""));
  const auto result = run_shapepress("--quiet compact --config " + (dir / "compact.toml").string() +
                                     " --packing " + (dir / "packing.txt").string() +
                                     " --steps 200 --out " + (dir / "run").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_THAT(result.output, HasSubstr("steps=200"));
  // The run's spheres are the file's: two of radius 0.5 mm (punch.csv states their volume).
  const std::string punch = read_text(dir / "run" / "punch.csv");
  std::smatch volume;
  ASSERT_TRUE(std::regex_search(punch, volume, std::regex(R"(solid volume (\S+) m\^3)"))) << punch;
  EXPECT_NEAR(
      std::stod(volume[1]) / (2.0 * 4.0 / 3.0 * std::numbers::pi * 0.5e-3 * 0.5e-3 * 0.5e-3), 1.0,
      1e-9);
  // The effective config (with --steps as run.steps) runs the same rows.
  const std::string effective = read_text(dir / "run" / "effective.toml");
  EXPECT_THAT(effective, HasSubstr("steps = 200\n"));
  const auto again = run_shapepress(
      "--quiet compact --config " + (dir / "run" / "effective.toml").string() + " --packing " +
      (dir / "packing.txt").string() + " --out " + (dir / "again").string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(read_csv(dir / "again" / "punch.csv").rows, read_csv(dir / "run" / "punch.csv").rows);
}

TEST(Compact, UnknownKeyIsExitTwoNamingIt) {
  const auto dir = fresh_directory("simulate_badkey");
  write_text(dir / "compact.toml", compact_config("skinn = \"0.1 mm\"\n"));
  const auto result = run_shapepress("compact --config " + (dir / "compact.toml").string() +
                                     " --out " + (dir / "run").string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_THAT(result.output, HasSubstr("skinn"));
}

TEST(Compact, DivergenceIsExitOneNamingSphereAndStep) {
  const auto dir = fresh_directory("simulate_diverge");
  // An overlap limit no real contact stays under: the run must stop, not write a NaN curve.
  write_text(dir / "compact.toml", compact_config("max_overlap_fraction = 1e-9\n"));
  const auto result = run_shapepress("--quiet compact --config " + (dir / "compact.toml").string() +
                                     " --out " + (dir / "run").string());
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_THAT(result.output, HasSubstr("diverged at step"));
  EXPECT_THAT(result.output, HasSubstr("spheres"));
}

}  // namespace
}  // namespace shapepress
