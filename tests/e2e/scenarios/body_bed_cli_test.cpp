// Beds of bodies as a user presses them: `compact --packing packed.h5` with bonded BMS clusters
// (and rigid CMS ones) loads and unloads, keeps its bonds within the bodies, states the solid
// fraction by shape volume beside the sub-spheres', judges whether the run was quasi-static, and
// refuses a config whose die is not the packing's.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "common/csv.hpp"
#include "packing/body_packing.hpp"
#include "tests/support/body_beds.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using shapepress::testing::cluster_bed;
using shapepress::testing::fresh_directory;
using shapepress::testing::read_text;
using shapepress::testing::run_shapepress;
using shapepress::testing::shell_quoted;
using shapepress::testing::test_data_text;
using shapepress::testing::write_text;
using ::testing::HasSubstr;

constexpr double sub_sphere_radius = 20e-6;

// 27 clusters of 13 sub-spheres (351 sub-spheres, 972 bonds) 122 µm apart in a 366 µm die,
// pressed by 30 % of the bed's height and unloaded.
std::filesystem::path bonded_bed(const std::filesystem::path& dir, packing::BodyKind kind,
                                 const std::string& extra = "") {
  const packing::BodyPacking bed = cluster_bed(kind, sub_sphere_radius, 3, 3, 7, 0.2, 6.1);
  write_packing(dir / "packed.h5", bed, Provenance{"test", "", 7});
  write_text(dir / "compact.toml", test_data_text("scenarios/bonded-bed.toml") +
                                       "\n[box]\nx = \"366 um\"\ny = \"366 um\"\n\n"
                                       "[run]\nrecord_every = 500\nsnapshot_every = 20000\n" +
                                       extra +
                                       "\n[punch]\nmode = \"displacement\"\nspeed = \"0.1 m/s\"\n"
                                       "target_strain = 0.3\nunload_speed = \"0.1 m/s\"\n");
  return dir / "compact.toml";
}

TEST(BodyBedCli, PressesAndUnloadsABondedBed) {
  const auto dir = fresh_directory("body_bed_bms");
  const auto config = bonded_bed(dir, packing::BodyKind::bms);
  const auto r = run_shapepress("--quiet --threads 2 compact --config " + shell_quoted(config) +
                                " --packing " + shell_quoted(dir / "packed.h5") + " --out " +
                                shell_quoted(dir / "run"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const CsvTable t = read_csv(dir / "run" / "punch.csv");
  const std::vector<double>& stress = t.column("stress_Pa");
  const double peak = *std::max_element(stress.begin(), stress.end());
  EXPECT_GT(peak, 1e3);
  EXPECT_NEAR(t.column("strain").front(), 0.0, 1e-12);
  EXPECT_EQ(t.column("phase").back(), 3.0);  // done: unloaded
  EXPECT_LT(stress.back(), 0.05 * peak);
  // 27 × 36 bonds, unbreakable: all intact from the first row to the last.
  EXPECT_EQ(t.column("intact_bonds").front(), 972.0);
  EXPECT_EQ(t.column("intact_bonds").back(), 972.0);
  // By shape volume (the circumscribed spheres) and by the 13 sub-spheres: 13/27 of it.
  for (std::size_t i = 0; i < stress.size(); i += 7)
    EXPECT_NEAR(t.column("solid_fraction_spheres")[i] / t.column("solid_fraction")[i], 13.0 / 27.0,
                1e-9);
  EXPECT_GT(t.column("punch_work_J").back(), 0.0);
  const std::string csv = read_text(dir / "run" / "punch.csv");
  EXPECT_THAT(csv, HasSubstr("solid_fraction is by the bodies' shape volume"));
  const std::string meta = read_text(dir / "run" / "run.json");
  EXPECT_THAT(meta, HasSubstr("\"quasi_static\""));
  EXPECT_THAT(meta, HasSubstr("\"max_kinetic_to_work\""));
  EXPECT_THAT(meta, HasSubstr("\"particle_kind\": \"bms\""));
  // The punch started at the packing's top (no box.punch given): the effective config says so.
  EXPECT_THAT(read_text(dir / "run" / "effective.toml"), HasSubstr("punch = "));
  // Snapshots show bodies and bonds.
  EXPECT_THAT(read_text(dir / "run" / "snapshots.xdmf"), HasSubstr("/bonds/pairs"));
}

TEST(BodyBedCli, PressesABedOfRigidClumps) {
  const auto dir = fresh_directory("body_bed_cms");
  const auto config = bonded_bed(dir, packing::BodyKind::cms);
  const auto r = run_shapepress("--quiet --threads 2 compact --config " + shell_quoted(config) +
                                " --packing " + shell_quoted(dir / "packed.h5") + " --out " +
                                shell_quoted(dir / "run") + " --steps 50000");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const CsvTable t = read_csv(dir / "run" / "punch.csv");
  EXPECT_GT(t.column("stress_Pa").back(), 0.0);
  EXPECT_THAT(read_text(dir / "run" / "run.json"), HasSubstr("\"clumps\": 27"));
}

TEST(BodyBedCli, RefusesADieThatIsNotThePackings) {
  const auto dir = fresh_directory("body_bed_die");
  auto config = bonded_bed(dir, packing::BodyKind::bms);
  std::string text = read_text(config);
  text.replace(text.find("x = \"366 um\""), 12, "x = \"500 um\"");
  write_text(config, text);
  const auto r =
      run_shapepress("--quiet compact --config " + shell_quoted(config) + " --packing " +
                     shell_quoted(dir / "packed.h5") + " --out " + shell_quoted(dir / "run"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("not the packing's"));
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "punch.csv"));
}

TEST(BodyBedCli, RefusesBondedBodiesWithoutBondParameters) {
  const auto dir = fresh_directory("body_bed_no_bond");
  auto config = bonded_bed(dir, packing::BodyKind::bms);
  std::string text = read_text(config);
  text.erase(text.find("[bond]"), text.find("[particles]") - text.find("[bond]"));
  write_text(config, text);
  const auto r =
      run_shapepress("--quiet compact --config " + shell_quoted(config) + " --packing " +
                     shell_quoted(dir / "packed.h5") + " --out " + shell_quoted(dir / "run"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("[bond]"));
}

}  // namespace
}  // namespace shapepress
