// Energy conservation of the integrator and the contact loop, and determinism: 1 vs 2 threads
// and restart vs continuous run give the same bits (issue 3, Validation).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
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
using testing::full_validation;
using testing::one_material;
using testing::random_gas;

// Spheres of 0.8–1.2 mm at random in a periodic box between two plates, moving at random.
TEST(Energy, ElasticFrictionlessBoxConservesTotalEnergy) {
  // Issue size: 1000 spheres, 1e5 steps; CI: 1000 spheres, 1e4 steps. Step 0.05 Rayleigh
  // times: the energy error comes from where in a step each Hertz contact starts and ends and
  // random-walks over collisions; measured worst drift over 1e5 steps: 1.4e-4 at 0.1 t_R.
  const int steps = full_validation() ? 100000 : 10000;
  const MaterialTable table = one_material(1.0, 0.0);
  const double length = 12e-3, height = 16e-3;
  Engine engine(random_gas(1000, length, height, 0.5, 11), Box{length, length}, table,
                {PlaneWall{0.0, 1, 0.0, 0}, PlaneWall{height, -1, 0.0, 0}},
                EngineSettings{0.25 * default_time_step(table, 0.4e-3), {0, 0, 0}, 0.1e-3});
  const auto total = [&] {
    const EnergySummary e = engine.energy();
    return e.kinetic + e.elastic;
  };
  const double start = total();
  double worst = 0.0;
  std::int64_t collisions = 0;
  for (int k = 0; k < steps; ++k) {
    engine.step();
    collisions += engine.sphere_contacts();
    if (k % 100 == 99) worst = std::max(worst, std::abs(total() - start) / start);
  }
  std::printf("energy drift over %d steps: worst %.3g relative, final %.3g\n", steps, worst,
              (total() - start) / start);
  EXPECT_GT(collisions, 10 * steps);  // a gas that collides, not free flight
  EXPECT_LT(worst, 1e-4);             // issue tolerance
}

using Scene = testing::CompactionScene;
Scene compaction_scene() {
  return testing::compaction_scene(one_material(0.5, 0.5, 0.02));
}

const int compaction_steps = 2000;

TEST(Determinism, OneAndTwoThreadsGiveTheSameBits) {
  const testing::ThreadRuns runs =
      testing::run_on_one_and_two_threads(compaction_scene, compaction_steps);
  EXPECT_GT(runs.one.engine->sphere_contacts(), 1000);  // the bed is really being compacted
  EXPECT_GT(runs.one.engine->wall_load(1), 0.0);
  expect_same_bits(*runs.one.engine, *runs.two.engine);
}

TEST(Determinism, RestartFromSnapshotContinuesWithTheSameBits) {
  const testing::RestartRuns runs =
      testing::run_continuous_and_restarted(compaction_scene, compaction_steps, "compaction");
  expect_same_bits(*runs.continuous.engine, *runs.resumed);
}

}  // namespace
}  // namespace shapepress::scenarios
