// Multiple time stepping of a bonded bed (EngineSettings::bond_substeps): the bonds on their own
// short step inside the contacts' longer one. The step chosen follows the contacts' bound; 1 and
// 2 threads and a restart through a snapshot give the same bits; against the single-rate run the
// curve moves by several per cent (the method's limit on a bed). Beside it, the single-rate run
// with a longer step for the bonds alone (run.bond_time_step_fraction).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/config.hpp"
#include "scenarios/compact_setup.hpp"
#include "tests/support/body_beds.hpp"
#include "tests/support/files.hpp"
#include "tests/validation/scenarios/scenes.hpp"

namespace shapepress::scenarios {
namespace {

using testing::expect_same_bits;

// Clusters of 13 sub-spheres touching on a lattice, `per_side` × `per_side` × `layers` of them,
// under the punch.
struct Bed {
  int per_side = 6, layers = 4;
};

testing::CompactionScene scene(int bond_substeps, const std::string& punch, Bed size,
                               const std::string& run_keys = "") {
  const double r = 20e-6, pitch = 6.0;
  const BodyPacking bed = shapepress::testing::cluster_bed(BodyKind::bms, r, size.per_side,
                                                           size.layers, 11, 0.0, pitch);
  const std::string side = std::to_string(size.per_side * pitch * r * 1e6) + " um";
  const ConfigTable root = ConfigTable::parse(
      shapepress::testing::test_data_text("scenarios/bonded-bed-one-material.toml") +
          "\n[box]\nx = \"" + side + "\"\ny = \"" + side +
          "\"\n\n[run]\nbond_substeps = " + std::to_string(bond_substeps) +
          "\ntime_step_fraction = 0.1\n" + run_keys + "\n[punch]\n" + punch,
      "bonded-bed-one-material");
  return testing::scene_from(prepare_compaction(read_compact_config(root), bed));
}

const std::string pressed = "mode = \"displacement\"\nspeed = \"1 m/s\"\ntarget_strain = 0.3\n";

// 144 clusters (1872 sub-spheres, 5184 bonds: both loops run on two threads).
testing::CompactionScene scene(int bond_substeps) {
  return scene(bond_substeps, pressed, Bed{});
}

TEST(BondSubsteps, TheContactsTakeTheirOwnBoundAndTheBondsTheirs) {
  const testing::CompactionScene single = scene(1), auto_substeps = scene(0);
  const TimeStepChoice& one = single.setup.time_step;
  const TimeStepChoice& many = auto_substeps.setup.time_step;
  EXPECT_EQ(one.bond_substeps, 1);
  EXPECT_EQ(single.engine->settings().bond_substeps, 1);
  EXPECT_DOUBLE_EQ(one.time_step, 0.1 * one.bond_period);  // the bonds bound the single rate
  EXPECT_GE(many.bond_substeps, 4);
  EXPECT_EQ(auto_substeps.engine->settings().bond_substeps, many.bond_substeps);
  EXPECT_DOUBLE_EQ(many.time_step, 0.1 * many.rayleigh_time);
  EXPECT_LE(many.time_step / many.bond_substeps, one.time_step * (1 + 1e-12));
  // A stated count is an upper bound: the step is no longer than n bond steps.
  const testing::CompactionScene two = scene(2);
  EXPECT_EQ(two.setup.time_step.bond_substeps, 2);
  EXPECT_DOUBLE_EQ(two.setup.time_step.time_step, 2 * one.time_step);
}

constexpr int steps = 200;

TEST(BondSubsteps, OneAndTwoThreadsGiveTheSameBits) {
  const testing::ThreadRuns runs =
      testing::run_on_one_and_two_threads([] { return scene(0); }, steps);
  const Engine& one = *runs.one.engine;
  EXPECT_GT(one.wall_load(1), 0.0);
  EXPECT_GT(one.sphere_contacts(), 1000);
  expect_same_bits(one, *runs.two.engine);
  EXPECT_TRUE(one.bonds().history == runs.two.engine->bonds().history);
  // The counted work (advise's cost) is the same on both: every step's sub-spheres, touching
  // contacts, and intact bonds once per bond sub-step.
  const WorkCount& work = runs.one_summary.work_count;
  EXPECT_EQ(work, runs.two_summary.work_count);
  EXPECT_EQ(work.sphere_steps, steps * static_cast<std::int64_t>(one.state().size()));
  EXPECT_GT(work.contact_steps, 0);
  const int substeps = one.settings().bond_substeps;
  EXPECT_GT(substeps, 1);
  EXPECT_EQ(work.bond_steps % substeps, 0);
  EXPECT_GE(work.bond_steps, steps * substeps * one.bonds().intact_count());
  EXPECT_EQ(work.total(), work.sphere_steps + work.contact_steps + work.bond_steps);
}

TEST(BondSubsteps, RestartFromSnapshotContinuesWithTheSameBits) {
  const testing::RestartRuns runs =
      testing::run_continuous_and_restarted([] { return scene(0); }, steps, "bond_substeps");
  expect_same_bits(*runs.continuous.engine, *runs.resumed);
  EXPECT_TRUE(runs.continuous.engine->bonds().history == runs.resumed->bonds().history);
}

struct Curve {
  std::vector<PunchRecord> records;
  double peak = 0.0;
  std::int64_t steps = 0;
};

// 48 clusters (624 sub-spheres) pressed to 20 % strain at 2 m/s and unloaded at the same speed.
// `run_keys`: more [run] keys.
Curve pressed_and_released_curve(int bond_substeps, const std::string& run_keys = "") {
  testing::CompactionScene s =
      scene(bond_substeps,
            "mode = \"displacement\"\nspeed = \"2 m/s\"\ntarget_strain = 0.2\n"
            "unload_speed = \"2 m/s\"\n",
            Bed{4, 3}, run_keys);
  s.setup.record_every = 1;
  Curve curve;
  CompactionHooks hooks;
  hooks.record = [&](const PunchRecord& r) { curve.records.push_back(r); };
  const CompactionSummary summary = run_compaction(*s.engine, s.setup, s.punch, hooks);
  curve.peak = summary.max_stress;
  curve.steps = summary.steps;
  return curve;
}

// The stress of `curve` at `strain` on its loading (or unloading) branch, linear between records.
double stress_at(const Curve& curve, double strain, bool loading) {
  const PunchRecord* before = nullptr;
  for (const PunchRecord& r : curve.records) {
    if (r.phase != (loading ? PunchPhase::load : PunchPhase::unload)) continue;
    if (before != nullptr && (r.strain - strain) * (before->strain - strain) <= 0.0 &&
        r.strain != before->strain)
      return before->stress +
             (r.stress - before->stress) * (strain - before->strain) / (r.strain - before->strain);
    before = &r;
  }
  return std::nan("");
}

double rms_apart(const Curve& single, const Curve& other, bool loading) {
  double sum = 0.0;
  int n = 0;
  for (const PunchRecord& r : single.records) {
    if (r.phase != (loading ? PunchPhase::load : PunchPhase::unload) ||
        r.stress < 0.1 * single.peak)
      continue;
    const double o = stress_at(other, r.strain, loading);
    if (std::isnan(o)) continue;
    sum += (o - r.stress) * (o - r.stress);
    ++n;
  }
  return std::sqrt(sum / n) / single.peak;
}

// Where the method stands on a bonded bed: the contacts between bodies are about as stiff as the
// bonds, so holding them over the long step moves the curve by several per cent (6 % RMS of the
// peak loading, 7 % unloading, peak +9 % at the automatic 9 sub-steps; 3 and 5 % at 3;
// docs/measurements.md, "Multiple time stepping"), far outside the 1 % the single-rate run holds
// against half its step (1.1 %). The bound below keeps that figure from growing unnoticed.
TEST(BondSubsteps, OnABondedBedTheCurveMovesBySeveralPerCent) {
  const Curve single = pressed_and_released_curve(1);
  const Curve substepped = pressed_and_released_curve(0);
  ASSERT_GT(single.peak, 0.0);
  EXPECT_LT(substepped.steps * 8, single.steps);
  const double loading = rms_apart(single, substepped, true);
  const double unloading = rms_apart(single, substepped, false);
  EXPECT_LT(loading, 0.08);
  EXPECT_LT(unloading, 0.09);
  EXPECT_NEAR(substepped.peak, single.peak, 0.12 * single.peak);
}

// The single-rate alternative: every force on one step, the bonds' bound taken at 0.3 of their
// period bound instead of the contacts' 0.1 (run.bond_time_step_fraction; velocity Verlet is
// stable to 1/π). On the study's quasi-static bed that holds the curve within 0.5 % at 4 to 6
// times the step; this bed is pressed at 2 m/s without mass scaling, an impact more than a
// compaction, and here the curve moves as it does with 3 bond sub-steps: about 4 % loading, 5 %
// unloading, peak +2.6 %. Its single-rate curve itself moves by 1.1 % at half the step, first order
// in the step (the contact damping's error on impacts), so the figure is the step error of a
// dynamic bed, not the bonds' (docs/measurements.md, "A longer step for the bonds"). The bounds
// keep it from growing unnoticed.
TEST(BondTimeStep, OnAFastBedALongerStepForTheBondsMovesTheCurveAsSubstepsDo) {
  const Curve single = pressed_and_released_curve(1);
  const Curve longer = pressed_and_released_curve(1, "bond_time_step_fraction = 0.3\n");
  ASSERT_GT(single.peak, 0.0);
  EXPECT_LT(longer.steps * 2.9, single.steps);
  EXPECT_LT(rms_apart(single, longer, true), 0.05);
  EXPECT_LT(rms_apart(single, longer, false), 0.07);
  EXPECT_NEAR(longer.peak, single.peak, 0.04 * single.peak);
}

}  // namespace
}  // namespace shapepress::scenarios
