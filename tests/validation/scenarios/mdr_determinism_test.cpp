// The MDR law in a compacting bed: 1 vs 2 threads and restart from a snapshot give the same bits
// (its history, the largest overlap and the yield strain, goes through the snapshot as every
// law's fields), and the plastic branch is really exercised.
#include <gtest/gtest.h>

#include "simulate/snapshot.hpp"
#include "tests/validation/scenarios/scenes.hpp"

namespace shapepress::scenarios {
namespace {

using testing::expect_same_bits;

// E = 100 MPa, Y = 1 MPa: a side yields at δ/R ≈ 0.35 %, which the punch's 2 m/s reaches.
MaterialTable mdr_material() {
  return MaterialTable({{"m", 1e8, 0.3, 1541.0}}, {{"m", "m", 0.5, 0.5, 0.02, MdrLaw{1e6}}});
}

testing::CompactionScene scene() {
  return testing::compaction_scene(mdr_material());
}

constexpr int steps = 1500;

TEST(MdrDeterminism, OneAndTwoThreadsGiveTheSameBits) {
  const testing::ThreadRuns runs = testing::run_on_one_and_two_threads(scene, steps);
  const Engine& one = *runs.one.engine;
  // The law is exercised: contacts past yield.
  int yielded = 0;
  for (const ContactHistory& h : one.checkpoint().history)
    yielded += law_history<MdrLaw>(h)[1] > 0.0;
  EXPECT_GT(yielded, 100);
  expect_same_bits(one, *runs.two.engine);
}

TEST(MdrDeterminism, RestartFromSnapshotContinuesWithTheSameBits) {
  const testing::RestartRuns runs = testing::run_continuous_and_restarted(scene, steps, "mdr");
  expect_same_bits(*runs.continuous.engine, *runs.resumed);
}

}  // namespace
}  // namespace shapepress::scenarios
