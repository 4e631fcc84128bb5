// A bed of bonded bodies (packed.h5's BMS clusters) under the punch: 1 vs 2 threads and a restart
// from a snapshot give the same bits, bonds and the multi-contact law's pressure included, and
// the bed's shape volume survives the restart. The same with elastic–plastic bonds, the snapshot
// taken while they yield.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/config.hpp"
#include "scenarios/compact_setup.hpp"
#include "tests/support/body_beds.hpp"
#include "tests/support/files.hpp"
#include "tests/validation/scenarios/scenes.hpp"

namespace shapepress::scenarios {
namespace {

using testing::expect_same_bits;

// 144 clusters of 13 sub-spheres (1872 sub-spheres, 5184 bonds: both loops run on two threads)
// touching on a lattice, pressed at 1 m/s.
testing::CompactionScene scene() {
  const double r = 20e-6;
  const BodyPacking bed = shapepress::testing::cluster_bed(BodyKind::bms, r, 6, 4, 11, 0.0, 6.0);
  const ConfigTable root = ConfigTable::parse(
      shapepress::testing::test_data_text("scenarios/bonded-bed.toml") +
          "\n[box]\nx = \"720 um\"\ny = \"720 um\"\n\n[punch]\nmode = \"displacement\"\n"
          "speed = \"1 m/s\"\ntarget_strain = 0.3\n",
      "bonded-bed");
  return testing::scene_from(prepare_compaction(read_compact_config(root), bed));
}

constexpr int steps = 1500;

// The bed with elastic–plastic bonds (bond_models.hpp) that the punch's load yields within the
// first half of the run: the elastic bed's bond stresses (|Fn|/A, |Fs|/A, |Mb| R̄/I) have a 90th
// percentile of 760–910 Pa and a largest of 2.8–3.0 kPa at step 767 (70–250 Pa at step 200).
testing::CompactionScene plastic_scene() {
  const double r = 20e-6;
  const BodyPacking bed = shapepress::testing::cluster_bed(BodyKind::bms, r, 6, 4, 11, 0.0, 6.0);
  std::string text = shapepress::testing::test_data_text("scenarios/bonded-bed.toml");
  text.replace(text.find("[bond]\n"), 7,
               "[bond]\nmodel = \"elastic_plastic\"\nyield_stress = \"200 Pa\"\n"
               "shear_yield_stress = \"200 Pa\"\nhardening_ratio = 0.1\n");
  const ConfigTable root = ConfigTable::parse(
      text +
          "\n[box]\nx = \"720 um\"\ny = \"720 um\"\n\n[punch]\nmode = \"displacement\"\n"
          "speed = \"1 m/s\"\ntarget_strain = 0.3\n",
      "plastic-bonded-bed");
  return testing::scene_from(prepare_compaction(read_compact_config(root), bed));
}

// Bonds with a plastic path in any mode.
int yielded_bonds(const Engine& engine) {
  const BondSet& b = engine.bonds();
  int n = 0;
  for (std::size_t k = 0; k < b.size(); ++k) {
    bool any = false;
    for (const auto& kappa : b.history.model_fields)
      any = any || kappa[k] > 0.0;
    n += any;
  }
  return n;
}

TEST(BodyBedDeterminism, OneAndTwoThreadsGiveTheSameBits) {
  const testing::ThreadRuns runs = testing::run_on_one_and_two_threads(scene, steps);
  const Engine& one = *runs.one.engine;
  // Loaded: the punch pushes, bonds carry force, sub-spheres of different bodies touch.
  EXPECT_GT(one.wall_load(1), 0.0);
  EXPECT_GT(one.sphere_contacts(), 1000);
  double largest_bond_force = 0.0;
  for (const double normal_force : one.bonds().history.normal_force)
    largest_bond_force = std::max(largest_bond_force, std::fabs(normal_force));
  EXPECT_GT(largest_bond_force, 0.0);
  expect_same_bits(one, *runs.two.engine);
  EXPECT_TRUE(one.bonds().history == runs.two.engine->bonds().history);
  // The counted work (advise's cost) too.
  EXPECT_EQ(runs.one_summary.work_count, runs.two_summary.work_count);
  EXPECT_GT(runs.one_summary.work_count.contact_steps, 1000);
  EXPECT_GT(runs.one_summary.work_count.bond_steps, 0);
}

TEST(BodyBedDeterminism, RestartFromSnapshotContinuesWithTheSameBits) {
  const testing::RestartRuns runs = testing::run_continuous_and_restarted(scene, steps, "body_bed");
  expect_same_bits(*runs.continuous.engine, *runs.resumed);
  EXPECT_TRUE(runs.continuous.engine->bonds().history == runs.resumed->bonds().history);
}

TEST(BodyBedDeterminism, PlasticBondsGiveTheSameBitsOnOneAndTwoThreads) {
  const testing::ThreadRuns runs = testing::run_on_one_and_two_threads(plastic_scene, steps);
  const Engine& one = *runs.one.engine;
  EXPECT_GT(yielded_bonds(one), static_cast<int>(one.bonds().size() / 10));
  expect_same_bits(one, *runs.two.engine);
  EXPECT_TRUE(one.bonds().history == runs.two.engine->bonds().history);
}

TEST(BodyBedDeterminism, PlasticBondsRestartFromASnapshotTakenWhileTheyYield) {
  const testing::RestartRuns runs =
      testing::run_continuous_and_restarted(plastic_scene, steps, "plastic_body_bed");
  // Yielding at the snapshot, and more after it.
  const int then = yielded_bonds(*runs.first.engine);
  EXPECT_GT(then, 0);
  EXPECT_GT(yielded_bonds(*runs.continuous.engine), then);
  expect_same_bits(*runs.continuous.engine, *runs.resumed);
  EXPECT_TRUE(runs.continuous.engine->bonds().history == runs.resumed->bonds().history);
}

TEST(BodyBedDeterminism, ARestartKeepsTheBedsBodyShapeAndSphereVolumes) {
  testing::CompactionScene first = scene();
  first.setup.max_steps = 10;
  run_compaction(*first.engine, first.setup, first.punch, {});
  const auto file = shapepress::testing::fresh_directory("body_bed_volume") / "snapshot.h5";
  write_snapshot(file, *first.engine, compaction_scenario_state(first.punch, first.setup),
                 Provenance{"test", "", std::nullopt});
  const ConfigTable root =
      ConfigTable::parse(shapepress::testing::test_data_text("scenarios/bonded-bed.toml") +
                             "\n[box]\nx = \"720 um\"\ny = \"720 um\"\npunch = \"1 mm\"\n[punch]\n"
                             "mode = \"displacement\"\nspeed = \"1 m/s\"\ntarget_strain = 0.3\n",
                         "bonded-bed");
  const PreparedCompaction resumed =
      resume_compaction(read_compact_config(root), read_snapshot(file));
  std::filesystem::remove(file);
  EXPECT_EQ(resumed.setup.solid_volume, first.setup.solid_volume);
  EXPECT_EQ(resumed.setup.shape_volume, first.setup.shape_volume);
  EXPECT_EQ(resumed.setup.sphere_volume, first.setup.sphere_volume);
  EXPECT_EQ(resumed.setup.inertial.diameter, first.setup.inertial.diameter);
  EXPECT_NEAR(first.setup.sphere_volume / first.setup.shape_volume, 13.0 / 27.0, 1e-12);
  // The body volume (the closed union of 13 touching spheres) lies between the two.
  EXPECT_GT(first.setup.solid_volume, first.setup.sphere_volume);
  EXPECT_LT(first.setup.solid_volume, first.setup.shape_volume);
}

}  // namespace
}  // namespace shapepress::scenarios
