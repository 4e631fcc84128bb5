// Rigid clumps (CMS) as a user runs them: `plate --particle cms --spheres N` writes the BMS
// plate's force.csv columns and ParaView's clump axes; `compact` with a [clumps] table inserts,
// settles and compacts clumps, snapshots them and restarts; bad clumps exit 2 naming the cause.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "common/csv.hpp"
#include "common/hdf5_file.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::read_text;
using shapepress::testing::run_shapepress;
using shapepress::testing::shell_quoted;
using shapepress::testing::test_data_text;
using shapepress::testing::write_text;
using ::testing::HasSubstr;

const std::filesystem::path repo = shapepress::testing::repository_root();
const std::filesystem::path shipped = repo / "pipelines/configs/rubber-sphere.toml";

TEST(CmsPlateCli, WritesTheBmsForceColumnsAndClumpAxes) {
  const auto dir = fresh_directory("cms_plate");
  const auto r =
      run_shapepress("--quiet plate --config " + shell_quoted(shipped) +
                     " --particle cms --spheres 50 --snapshot --out " + shell_quoted(dir / "run"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const CsvTable t = read_csv(dir / "run" / "force.csv");
  for (const char* column :
       {"time_s", "deformation", "approach_m", "top_force_N", "bottom_force_N", "hertz_force_N",
        "contacts", "intact_bonds", "kinetic_energy_J", "work_J", "cpu_s", "wall_s"})
    EXPECT_NO_THROW(t.column(column)) << column;
  // The run reaches 40 %: the plates passing through outer sub-spheres do not stop it.
  EXPECT_NEAR(t.column("deformation").back(), 0.40, 0.005);
  EXPECT_GT(t.column("top_force_N").back(), 0.0);
  EXPECT_GE(t.column("contacts").back(), 2.0);
  EXPECT_EQ(t.column("intact_bonds").back(), 0.0);
  const std::string csv = read_text(dir / "run" / "force.csv");
  EXPECT_THAT(csv, HasSubstr("particle = cms"));
  EXPECT_THAT(csv, HasSubstr("requested_spheres = 50"));
  const std::string xdmf = read_text(dir / "run" / "final.xdmf");
  EXPECT_THAT(xdmf, HasSubstr("clump_axes"));
  EXPECT_THAT(xdmf, HasSubstr("/clumps/axis_lines"));
  EXPECT_THAT(xdmf, HasSubstr("/particles/body"));
  H5Reader h5(dir / "run" / "final.h5");
  EXPECT_EQ(h5.doubles("/clumps/mass").size(), 1u);
  EXPECT_EQ(h5.int32s("/clumps/axis_lines").size(), 6u);
}

TEST(CmsPlateCli, SpheresIsForCmsOnly) {
  const auto dir = fresh_directory("cms_plate_usage");
  const auto r =
      run_shapepress("--quiet plate --config " + shell_quoted(shipped) +
                     " --particle sphere --spheres 50 --out " + shell_quoted(dir / "run"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--spheres"));
}

// A few clumps of three overlapping spheres (about 1 mm) with a handful of plain spheres.
std::string clump_compact_config(const std::string& spheres) {
  return test_data_text("scenarios/powder.toml") + R"(
[run]
record_every = 50
snapshot_every = 500
gravity = [0.0, 0.0, -9.81]

[box]
x = "5 mm"
y = "5 mm"
punch = "6 mm"
)" + test_data_text("scenarios/powder-die.toml") +
         R"(
[generate]
count = 40
diameter_min = "0.8 mm"
diameter_max = "1.0 mm"
seed = 3
settle_time = "80 ms"

[clumps]
count = 6
seed = 2
integration_cells = 48
spheres = )" +
         spheres + R"(

[punch]
speed = "0.5 m/s"
target_strain = 0.3
)";
}

const std::string three_spheres =
    "[0.0, 0.0, 0.0, 0.5e-3,  0.6e-3, 0.0, 0.0, 0.4e-3,  0.0, 0.5e-3, 0.0, 0.35e-3]";

// The clumps' config with its templates from a templates file instead of inline spheres.
std::string templates_compact_config(const std::filesystem::path& templates) {
  std::string config = clump_compact_config(three_spheres);
  const std::size_t key = config.find("spheres = ");
  config.replace(key, config.find('\n', key) - key, "templates = \"" + templates.string() + "\"");
  return config;
}

TEST(CmsCompactCli, CompactsClumpsSnapshotsAndRestarts) {
  const auto dir = fresh_directory("cms_compact");
  write_text(dir / "compact.toml", clump_compact_config(three_spheres));
  const auto r = run_shapepress("--quiet compact --config " + shell_quoted(dir / "compact.toml") +
                                " --out " + shell_quoted(dir / "run"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const CsvTable t = read_csv(dir / "run" / "punch.csv");
  EXPECT_GT(t.column("top_force_N").back(), 0.0);
  EXPECT_NEAR(t.column("strain").back(), 0.3, 0.01);
  // The solid fraction counts each clump's union once: below the sum of its sub-spheres'.
  const double fraction = t.column("solid_fraction").back();
  EXPECT_GT(fraction, 0.0);
  EXPECT_LT(fraction, 1.0);
  const std::string xdmf = read_text(dir / "run" / "snapshots.xdmf");
  EXPECT_THAT(xdmf, HasSubstr("clump_axes"));
  std::filesystem::path snapshot;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "run" / "snapshots"))
    if (entry.path().extension() == ".h5") snapshot = std::max(snapshot, entry.path());
  ASSERT_FALSE(snapshot.empty());
  H5Reader h5(snapshot);
  EXPECT_EQ(h5.doubles("/clumps/mass").size(), 6u);
  EXPECT_EQ(h5.int32s("/particles/body").size(), 40u + 6u * 3u);
  const auto again = run_shapepress(
      "--quiet compact --config " + shell_quoted(dir / "compact.toml") + " --restart " +
      shell_quoted(snapshot) + " --out " + shell_quoted(dir / "again"));
  ASSERT_EQ(again.exit_code, 0) << again.output;
  // The restarted run ends where the first one did (same bits: the validation tests).
  const CsvTable u = read_csv(dir / "again" / "punch.csv");
  EXPECT_EQ(u.column("top_force_N").back(), t.column("top_force_N").back());
}

TEST(CmsCompactCli, TakesClumpsFromATemplatesFile) {
  // `fill --kind cms` writes /cms/<name>; [clumps] templates = that file.
  const auto dir = fresh_directory("cms_compact_templates");
  auto r =
      run_shapepress("--quiet fill --ellipsoid 0.6mm,0.4mm,0.3mm --kind cms --count 20 --out " +
                     shell_quoted(dir / "templates.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string config = templates_compact_config(dir / "templates.h5");
  write_text(dir / "compact.toml", config);
  r = run_shapepress("--quiet compact --config " + shell_quoted(dir / "compact.toml") + " --out " +
                     shell_quoted(dir / "run"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const CsvTable t = read_csv(dir / "run" / "punch.csv");
  EXPECT_GT(t.column("top_force_N").back(), 0.0);
  EXPECT_NEAR(t.column("strain").back(), 0.3, 0.01);
  // A template the file does not hold is named with the file (pack's reader, the same words).
  const std::size_t at = config.find("templates = ");
  config.insert(at, "template = \"ellipsoid_nowhere\"\n");
  write_text(dir / "missing.toml", config);
  r = run_shapepress("--quiet compact --config " + shell_quoted(dir / "missing.toml") + " --out " +
                     shell_quoted(dir / "missing"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no template /cms/ellipsoid_nowhere in '" +
                                  (dir / "templates.h5").string() + "'"));
}

TEST(CmsCompactCli, ATemplatesFileWithoutCmsTemplatesIsExitTwoNamingIt) {
  const auto dir = fresh_directory("cms_compact_bms_file");
  auto r = run_shapepress(
      "--quiet fill --ellipsoid 150um,100um,80um --kind bms --count 60 --lattice random --out " +
      shell_quoted(dir / "templates.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  write_text(dir / "compact.toml", templates_compact_config(dir / "templates.h5"));
  r = run_shapepress("--quiet compact --config " + shell_quoted(dir / "compact.toml") + " --out " +
                     shell_quoted(dir / "run"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output,
              HasSubstr("'" + (dir / "templates.h5").string() + "' holds no template of kind cms"));
}

TEST(CmsCompactCli, BadClumpsExitTwoNamingTheCause) {
  const auto dir = fresh_directory("cms_compact_bad");
  // Zero volume: a sub-sphere of radius 0.
  write_text(dir / "zero.toml",
             clump_compact_config("[0.0, 0.0, 0.0, 0.5e-3,  0.6e-3, 0.0, 0.0, 0.0]"));
  auto r = run_shapepress("--quiet compact --config " + shell_quoted(dir / "zero.toml") +
                          " --out " + shell_quoted(dir / "a"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("zero volume"));
  // An overlapping fill that is not connected: the third sphere is 2 mm from the others.
  write_text(dir / "apart.toml",
             clump_compact_config(
                 "[0.0, 0.0, 0.0, 0.5e-3,  0.6e-3, 0.0, 0.0, 0.4e-3,  2.6e-3, 0.0, 0.0, 0.4e-3]"));
  r = run_shapepress("--quiet compact --config " + shell_quoted(dir / "apart.toml") + " --out " +
                     shell_quoted(dir / "b"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("separate groups"));
  // Neither a templates file nor inline spheres.
  std::string none = clump_compact_config(three_spheres);
  none.replace(none.find("spheres = "), std::string("spheres = ").size(), "sphere_list = ");
  write_text(dir / "none.toml", none);
  r = run_shapepress("--quiet compact --config " + shell_quoted(dir / "none.toml") + " --out " +
                     shell_quoted(dir / "c"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("[clumps]"));
}

}  // namespace
}  // namespace shapepress
