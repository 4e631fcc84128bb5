// Beds of bodies as a user presses them: `compact --packing packed.h5` with bonded BMS clusters
// (and rigid CMS ones) loads and unloads, keeps its bonds within the bodies, states the solid
// fraction by shape volume beside the sub-spheres', judges whether the run was quasi-static, and
// refuses a config whose die is not the packing's.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
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
                                       "target_strain = 0.3\nunload_speed = \"0.1 m/s\"\n"
                                       "release_time = \"0.2 ms\"\n");
  return dir / "compact.toml";
}

// `compact` of the bed bonded_bed wrote, on two threads, into dir/run.
shapepress::testing::CommandResult compact_bed(const std::filesystem::path& dir,
                                               const std::filesystem::path& config,
                                               const std::string& extra = "") {
  return run_shapepress("--quiet --threads 2 compact --config " + shell_quoted(config) +
                        " --packing " + shell_quoted(dir / "packed.h5") + " --out " +
                        shell_quoted(dir / "run") + extra);
}

TEST(BodyBedCli, PressesAndUnloadsABondedBed) {
  const auto dir = fresh_directory("body_bed_bms");
  const auto config = bonded_bed(dir, packing::BodyKind::bms);
  const auto r = compact_bed(dir, config);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const CsvTable t = read_csv(dir / "run" / "punch.csv");
  const std::vector<double>& stress = t.column("stress_Pa");
  const double peak = *std::max_element(stress.begin(), stress.end());
  EXPECT_GT(peak, 1e3);
  EXPECT_NEAR(t.column("strain").front(), 0.0, 1e-12);
  EXPECT_EQ(t.column("phase").back(), 3.0);  // done: unloaded, then released
  const std::vector<double>& phase = t.column("phase");
  EXPECT_NE(std::find(phase.begin(), phase.end(), 4.0), phase.end());
  // The punch followed the bed's spring-back at 1 % of the peak stress.
  EXPECT_LT(stress.back(), 0.05 * peak);
  // 27 × 36 bonds, unbreakable: all intact from the first row to the last.
  EXPECT_EQ(t.column("intact_bonds").front(), 972.0);
  EXPECT_EQ(t.column("intact_bonds").back(), 972.0);
  // By shape volume (the circumscribed spheres) and by the 13 sub-spheres: 13/27 of it; by body
  // volume (their union closed by a ball of their radius), between the two.
  for (std::size_t i = 0; i < stress.size(); i += 7) {
    const double shape = t.column("solid_fraction_shape")[i];
    EXPECT_NEAR(t.column("solid_fraction_spheres")[i] / shape, 13.0 / 27.0, 1e-9);
    EXPECT_GT(t.column("solid_fraction")[i], t.column("solid_fraction_spheres")[i]);
    EXPECT_LT(t.column("solid_fraction")[i], shape);
  }
  EXPECT_GT(t.column("punch_work_J").back(), 0.0);
  const std::string csv = read_text(dir / "run" / "punch.csv");
  EXPECT_THAT(csv, HasSubstr("solid_fraction is by the bodies' volume in the bed"));
  const std::string meta = read_text(dir / "run" / "run.json");
  EXPECT_THAT(meta, HasSubstr("\"quasi_static\""));
  EXPECT_THAT(meta, HasSubstr("\"max_kinetic_to_work\""));
  EXPECT_THAT(meta, HasSubstr("\"particle_kind\": \"bms\""));
  // The punch started at the packing's top (no box.punch given): the effective config says so.
  EXPECT_THAT(read_text(dir / "run" / "effective.toml"), HasSubstr("punch = "));
  // Snapshots show bodies and bonds.
  EXPECT_THAT(read_text(dir / "run" / "snapshots.xdmf"), HasSubstr("/bonds/pairs"));
}

// A study that states its solid fractions by the shapes' volume (punch.solid_fraction_volume):
// punch.csv's solid_fraction is solid_fraction_shape, its target and ceiling are by it, and its
// header and run.json say so; the bodies' volume in the bed is still stated beside it.
TEST(BodyBedCli, StatesTheSolidFractionByTheShapesVolumeWhenAsked) {
  const auto dir = fresh_directory("body_bed_shape_volume");
  const auto config = bonded_bed(dir, packing::BodyKind::bms);
  std::string text = read_text(config);
  const auto strain = text.find("target_strain = 0.3");
  ASSERT_NE(strain, std::string::npos);
  // [punch] is the file's last table: 0.6 by the shapes' volume lies within the 30 % the
  // bodies' run is pressed (their sub-spheres are 13/27 of the circumscribed spheres).
  text.replace(strain, std::string("target_strain = 0.3").size(),
               "target_solid_fraction = 0.6\nsolid_fraction_volume = \"shape\"");
  write_text(config, text);
  const auto r = compact_bed(dir, config);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const CsvTable t = read_csv(dir / "run" / "punch.csv");
  const std::vector<double>& solid = t.column("solid_fraction");
  ASSERT_FALSE(solid.empty());
  for (std::size_t i = 0; i < solid.size(); ++i)
    EXPECT_DOUBLE_EQ(solid[i], t.column("solid_fraction_shape")[i]);
  // Loading ends at the target by the shapes' volume: the densest record is within a record's
  // travel below 0.6 and never past it.
  const double densest = *std::max_element(solid.begin(), solid.end());
  EXPECT_LE(densest, 0.6 + 1e-9);
  EXPECT_GT(densest, 0.58);
  const std::string csv = read_text(dir / "run" / "punch.csv");
  EXPECT_THAT(csv, HasSubstr("solid_fraction is by the bodies' shapes' (meshes') volume"));
  EXPECT_THAT(read_text(dir / "run" / "run.json"),
              HasSubstr("\"solid_fraction_volume\": \"shape\""));
  EXPECT_THAT(read_text(dir / "run" / "effective.toml"),
              HasSubstr("solid_fraction_volume = \"shape\""));
}

// A face-centred cubic stack of equal spheres: square layers of per_side × per_side touching
// spheres, each layer over the hollows of the one below (d/√2 apart), in a periodic die of
// per_side diameters. It is the densest stack and has no collapse mode: pressed, it deforms
// homogeneously, with no rearrangement whose path could branch, so what mass scaling changes is
// the bed's inertia alone. (A simple cubic stack buckles at 2 % strain; a random bed of 60
// spheres jumps by ~13 % between paths that a 10 % change of mass selects; docs/measurements.md,
// "Mass scaling".)
packing::BodyPacking sphere_stack(double diameter, int per_side, int layers) {
  packing::BodyPacking p;
  packing::BodyTemplate t;
  t.name = "sphere";
  t.kind = packing::BodyKind::sphere;
  t.centres = {{0.0, 0.0, 0.0}};
  t.radii = {0.5};
  t.shape_volume = t.sphere_volume = std::numbers::pi / 6.0;
  const double moment = 0.4 * t.shape_volume * 0.25;
  t.principal_inertia = {moment, moment, moment};
  p.templates.push_back(t);
  p.box = {per_side * diameter, per_side * diameter};
  p.floor = 0.0;
  const double spacing = diameter / std::numbers::sqrt2;
  p.top = (layers - 1) * spacing + diameter;
  const double volume = diameter * diameter * diameter * t.shape_volume;
  for (int k = 0; k < layers; ++k)
    for (int j = 0; j < per_side; ++j)
      for (int i = 0; i < per_side; ++i) {
        const double offset = k % 2 == 0 ? 0.25 : 0.75;
        packing::PackedBody b;
        b.scale = diameter;
        b.centre = {(i + offset) * diameter, (j + offset) * diameter, 0.5 * diameter + k * spacing};
        b.shape_volume = b.sphere_volume = volume;
        p.bodies.push_back(b);
      }
  packing::place_bodies(p);
  return p;
}

// Mass scaling (run.density_scale) on a small bed pressed by 2 %, before its contacts slide:
// 10 times the mass lengthens the step √10 times and takes 1/√10 of the steps, and the loading
// curve moves by less than 2 % of its peak (RMS over the loading records from a tenth of the
// peak; measured 0.7 %, and 1.3 % at 30, 2.2 % at 100: the bed's inertia, growing with s, and
// its inertial number with it, 0.7e-3 at 10 and 1.25e-3 at 30); both runs are quasi-static by
// compact's own figures, the inertial number's limit of 1e-3 included. Scaled 10⁴ times (the
// unscaled bed at 0.5 m/s), the same punch is far from quasi-static, and compact says so.
TEST(BodyBedCli, MassScalingMovesTheCurveByLessThanTwoPercent) {
  struct Curve {
    std::vector<double> strain, stress;
    double steps = 0.0;
    std::string meta;
  };
  const auto press = [](const std::string& name, double scale) {
    const auto dir = fresh_directory(name);
    write_packing(dir / "packed.h5", sphere_stack(200e-6, 3, 6), Provenance{"test", "", 7});
    write_text(dir / "compact.toml",
               test_data_text("scenarios/bonded-bed.toml") +
                   "\n[box]\nx = \"600 um\"\ny = \"600 um\"\n\n[run]\nrecord_every = 100\n"
                   "snapshot_every = 0\ndensity_scale = " +
                   std::to_string(scale) +
                   "\n\n[punch]\nmode = \"displacement\"\nspeed = \"0.005 m/s\"\n"
                   "target_strain = 0.02\nunload_speed = \"0.005 m/s\"\n");
    const auto r = run_shapepress(
        "--quiet --threads 2 compact --config " + shell_quoted(dir / "compact.toml") +
        " --packing " + shell_quoted(dir / "packed.h5") + " --out " + shell_quoted(dir / "run"));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const CsvTable t = read_csv(dir / "run" / "punch.csv");
    const std::vector<double> phase = t.column("phase"), strain = t.column("strain"),
                              stress = t.column("stress_Pa");
    Curve c;
    for (std::size_t i = 0; i < phase.size(); ++i)
      if (phase[i] == 0.0) {
        c.strain.push_back(strain[i]);
        c.stress.push_back(stress[i]);
      }
    c.steps = t.column("step").back();
    c.meta = read_text(dir / "run" / "run.json");
    return c;
  };
  const Curve unscaled = press("mass_scaling_1", 1.0);
  const Curve scaled = press("mass_scaling_10", 10.0);
  EXPECT_THAT(unscaled.meta, HasSubstr("\"quasi_static\": true"));
  EXPECT_THAT(scaled.meta, HasSubstr("\"quasi_static\": true"));
  EXPECT_THAT(scaled.meta, HasSubstr("\"density_scale\": 10.0"));
  ASSERT_GT(unscaled.strain.size(), 10u);
  ASSERT_GT(scaled.strain.size(), 3u);
  EXPECT_NEAR(unscaled.steps / scaled.steps, std::sqrt(10.0), 0.3);
  const double peak = *std::max_element(unscaled.stress.begin(), unscaled.stress.end());
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < unscaled.strain.size(); ++i) {
    if (unscaled.stress[i] < 0.1 * peak) continue;
    const double e = unscaled.strain[i];
    const auto after = std::upper_bound(scaled.strain.begin(), scaled.strain.end(), e);
    if (after == scaled.strain.begin() || after == scaled.strain.end()) continue;
    const auto k = static_cast<std::size_t>(after - scaled.strain.begin());
    const double w = (e - scaled.strain[k - 1]) / (scaled.strain[k] - scaled.strain[k - 1]);
    const double s = scaled.stress[k - 1] + w * (scaled.stress[k] - scaled.stress[k - 1]);
    sum += (s - unscaled.stress[i]) * (s - unscaled.stress[i]);
    ++n;
  }
  ASSERT_GT(n, 5);
  EXPECT_LT(std::sqrt(sum / n) / peak, 0.02);
  const Curve far = press("mass_scaling_1e4", 1e4);
  EXPECT_THAT(far.meta, HasSubstr("\"quasi_static\": false"));
}

TEST(BodyBedCli, PressesABedOfRigidClumps) {
  const auto dir = fresh_directory("body_bed_cms");
  const auto config = bonded_bed(dir, packing::BodyKind::cms);
  const auto r = compact_bed(dir, config, " --steps 50000");
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
