// The multi-contact law in a compacting bed: 1 vs 2 threads and restart from a snapshot give
// the same bits (the Love–Weber stress is read one step late, so its snapshot must restore it),
// and the plastic history is really exercised.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "packing/packing.hpp"
#include "scenarios/compact.hpp"
#include "simulate/snapshot.hpp"
#include "tests/validation/scenarios/scenes.hpp"

namespace shapepress::scenarios {
namespace {

using testing::default_time_step;
using testing::expect_same_bits;

MaterialTable multicontact_material() {
  MulticontactParameters m;
  m.plasticity_ratio = 0.4;
  m.adhesion_stiffness = 1e5;
  m.pull_off_force = -1e-5;
  m.prefactor = 1.3;
  return MaterialTable({{"m", 1e8, 0.3, 1541.0}}, {{"m", "m", 0.5, 0.5, 0.02, MulticontactLaw{m}}});
}

using Scene = testing::CompactionScene;
Scene scene() {
  return testing::compaction_scene(multicontact_material());
}

constexpr int steps = 1500;

TEST(MulticontactDeterminism, OneAndTwoThreadsGiveTheSameBits) {
  const testing::ThreadRuns runs = testing::run_on_one_and_two_threads(scene, steps);
  const Engine& one = *runs.one.engine;
  // The law is exercised: contacts with plastic overlap and spheres under pressure.
  int plastic = 0;
  for (const ContactHistory& h : one.checkpoint().history)
    plastic += plastic_force(h) > 0.0;
  EXPECT_GT(plastic, 500);
  double largest = 0.0;
  for (std::size_t i = 0; i < one.state().size(); ++i)
    largest = std::max(largest, one.particle_pressure(i));
  EXPECT_GT(largest, 0.0);
  expect_same_bits(one, *runs.two.engine);
}

TEST(MulticontactDeterminism, RestartFromSnapshotContinuesWithTheSameBits) {
  const testing::RestartRuns runs =
      testing::run_continuous_and_restarted(scene, steps, "multicontact");
  expect_same_bits(*runs.continuous.engine, *runs.resumed);
}

}  // namespace
}  // namespace shapepress::scenarios
