// Energy conservation of the integrator and the contact loop, and determinism: 1 vs 2 threads
// and restart vs continuous run give the same bits (issue 3, Validation).
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include "simulate/compact.hpp"
#include "simulate/packing.hpp"
#include "simulate/snapshot.hpp"
#include "tests/validation/simulate/scenes.hpp"

namespace shapepress::simulate {
namespace {

using testing::default_time_step;
using testing::full_validation;
using testing::one_material;

// Spheres of 0.8–1.2 mm at random in a periodic box between two plates, moving at random.
SphereState random_gas(int count, double length, double height, double speed, std::uint64_t seed) {
  const Box box{length, length};
  SphereState s =
      make_state(insert_random_spheres(box, {count, 0.8e-3, 1.2e-3, 0.0, height, seed}), 1541.0, 0);
  std::mt19937_64 random(seed);
  std::normal_distribution<double> v(0.0, speed);
  for (std::size_t i = 0; i < s.size(); ++i) {
    s.velocity.x[i] = v(random);
    s.velocity.y[i] = v(random);
    s.velocity.z[i] = v(random);
  }
  return s;
}

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

// A small compaction: punch at 2 m/s into a loose bed, 2500 spheres, enough pairs that both
// the pair loop and the gather run multi-threaded.
struct Scene {
  std::unique_ptr<Engine> engine;
  CompactionSetup setup;
  PunchState punch;
};

Scene compaction_scene() {
  const MaterialTable table = one_material(0.5, 0.5, 0.02);
  const double length = 14e-3, height = 30e-3;
  Scene scene;
  scene.engine = std::make_unique<Engine>(
      random_gas(2500, length, height, 0.2, 5), Box{length, length}, table,
      std::vector<PlaneWall>{PlaneWall{0.0, 1, 0.0, 0}, PlaneWall{height, -1, 0.0, 0}},
      EngineSettings{default_time_step(table, 0.4e-3), {0, 0, -9.81}, 0.1e-3});
  scene.setup.program.speed = 2.0;
  scene.setup.die_area = length * length;
  scene.setup.reference_gap = height;
  scene.setup.record_every = 0;
  scene.punch.reference_gap = height;
  return scene;
}

void expect_same_bits(const Engine& a, const Engine& b) {
  EXPECT_EQ(a.step_index(), b.step_index());
  EXPECT_TRUE(a.state().position == b.state().position);
  EXPECT_TRUE(a.state().velocity == b.state().velocity);
  EXPECT_TRUE(a.state().angular_velocity == b.state().angular_velocity);
  EXPECT_TRUE(a.state().force == b.state().force);
  EXPECT_TRUE(a.state().torque == b.state().torque);
  EXPECT_EQ(a.wall_force(1), b.wall_force(1));
  const EngineCheckpoint ca = a.checkpoint(), cb = b.checkpoint();
  EXPECT_EQ(ca.first, cb.first);
  ASSERT_EQ(ca.history.size(), cb.history.size());
  for (std::size_t k = 0; k < ca.history.size(); ++k)
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(ca.history[k].tangential[c], cb.history[k].tangential[c]);
}

const int compaction_steps = 2000;

TEST(Determinism, OneAndTwoThreadsGiveTheSameBits) {
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  Scene one = compaction_scene();
  one.setup.max_steps = compaction_steps;
  run_compaction(*one.engine, one.setup, one.punch, {});
  omp_set_num_threads(2);
  Scene two = compaction_scene();
  two.setup.max_steps = compaction_steps;
  run_compaction(*two.engine, two.setup, two.punch, {});
  omp_set_num_threads(threads);
  EXPECT_GT(one.engine->sphere_contacts(), 1000);  // the bed is really being compacted
  EXPECT_GT(one.engine->wall_load(1), 0.0);
  expect_same_bits(*one.engine, *two.engine);
}

TEST(Determinism, RestartFromSnapshotContinuesWithTheSameBits) {
  // One thread: the thread count is the other test's subject, and a team of two on a loaded
  // machine spends its time in barriers.
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  Scene continuous = compaction_scene();
  continuous.setup.max_steps = compaction_steps;
  run_compaction(*continuous.engine, continuous.setup, continuous.punch, {});

  Scene first = compaction_scene();
  first.setup.max_steps = compaction_steps / 2 + 17;  // mid-way between list builds
  run_compaction(*first.engine, first.setup, first.punch, {});
  const auto file = std::filesystem::temp_directory_path() / "shapepress_restart_test.h5";
  write_snapshot(file, *first.engine, first.punch, Provenance{"test", "", std::nullopt});
  LoadedSnapshot loaded = read_snapshot(file);
  std::filesystem::remove(file);
  Engine resumed(std::move(loaded.state), loaded.box, first.engine->materials(),
                 first.engine->settings(), std::move(loaded.checkpoint));
  PunchState punch = loaded.punch;
  CompactionSetup setup = continuous.setup;
  run_compaction(resumed, setup, punch, {});
  omp_set_num_threads(threads);
  expect_same_bits(*continuous.engine, resumed);
}

}  // namespace
}  // namespace shapepress::simulate
