#pragma once
// Small scenes shared by the engine's validation tests.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "packing/packing.hpp"
#include "scenarios/compact.hpp"
#include "scenarios/compact_setup.hpp"
#include "simulate/engine.hpp"
#include "simulate/snapshot.hpp"
#include "simulate/timestep.hpp"
#include "tests/support/files.hpp"

namespace shapepress::scenarios::testing {

// SHAPEPRESS_FULL_VALIDATION=1 runs the sizes the issue names; CI runs reduced ones.
inline bool full_validation() {
  const char* value = std::getenv("SHAPEPRESS_FULL_VALIDATION");
  return value != nullptr && std::string(value) == "1";
}

inline MaterialTable one_material(double e, double mu_s, double mu_r = 0.0, double E = 1e8,
                                  double nu = 0.3, double rho = 1541.0) {
  return MaterialTable({{"m", E, nu, rho}}, {{"m", "m", e, mu_s, mu_r}});
}

// 0.2 × Rayleigh time of a sphere of material 0 (the engine's default rule).
inline double default_time_step(const MaterialTable& table, double radius) {
  const Material& m = table.material(0);
  return 0.2 * rayleigh_time(radius, m.density, m.youngs_modulus, m.poisson_ratio);
}

// `count` spheres of 0.8–1.2 mm at random in a periodic length × length box up to `height`, with
// Gaussian velocities of standard deviation `speed` (all from `seed`).
inline SphereState random_gas(int count, double length, double height, double speed,
                              std::uint64_t seed) {
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

// A small compaction for the determinism tests: 2500 spheres of material 0 poured at a punch
// moving down at 2 m/s, enough pairs and spheres that the pair loop and the gather both run on
// two threads.
struct CompactionScene {
  std::unique_ptr<Engine> engine;
  CompactionSetup setup;
  PunchState punch;
};
// A prepared compaction (prepare_compaction) as a scene, recording nothing.
inline CompactionScene scene_from(PreparedCompaction prepared) {
  CompactionScene scene;
  scene.engine = std::move(prepared.engine);
  scene.setup = prepared.setup;
  scene.setup.record_every = 0;
  scene.punch = prepared.punch;
  return scene;
}
// `engine` in a length × length die whose punch starts at `height` and moves down at 2 m/s.
inline CompactionScene punch_at_two_metres_per_second(std::unique_ptr<Engine> engine, double length,
                                                      double height) {
  CompactionScene scene;
  scene.engine = std::move(engine);
  scene.setup.program.speed = 2.0;
  scene.setup.die_area = length * length;
  scene.setup.record_every = 0;
  scene.punch.reference_gap = height;
  return scene;
}

inline CompactionScene compaction_scene(const MaterialTable& table) {
  const double length = 14e-3, height = 30e-3;
  return punch_at_two_metres_per_second(
      std::make_unique<Engine>(
          random_gas(2500, length, height, 0.2, 5), Box{length, length}, table,
          std::vector<PlaneWall>{PlaneWall{0.0, 1, 0.0, 0}, PlaneWall{height, -1, 0.0, 0}},
          EngineSettings{default_time_step(table, 0.4e-3), {0, 0, -9.81}, 0.1e-3}),
      length, height);
}

// The determinism checks (1 vs 2 threads, restart vs continuous run): every quantity a later
// step depends on, bit for bit — sphere state, wall forces, particle stress, and each contact's
// history (tangential spring and plastic force).
inline void expect_same_bits(const Engine& a, const Engine& b) {
  EXPECT_EQ(a.step_index(), b.step_index());
  EXPECT_TRUE(a.state().position == b.state().position);
  EXPECT_TRUE(a.state().velocity == b.state().velocity);
  EXPECT_TRUE(a.state().angular_velocity == b.state().angular_velocity);
  EXPECT_TRUE(a.state().force == b.state().force);
  EXPECT_TRUE(a.state().torque == b.state().torque);
  ASSERT_EQ(a.walls().size(), b.walls().size());
  for (std::size_t k = 0; k < a.walls().size(); ++k)
    EXPECT_EQ(a.wall_force(k), b.wall_force(k));
  EXPECT_TRUE(a.particle_stress() == b.particle_stress());
  const EngineCheckpoint ca = a.checkpoint(), cb = b.checkpoint();
  EXPECT_EQ(ca.first, cb.first);
  EXPECT_EQ(ca.second, cb.second);
  ASSERT_EQ(ca.history.size(), cb.history.size());
  for (std::size_t k = 0; k < ca.history.size(); ++k) {
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(ca.history[k].tangential[c], cb.history[k].tangential[c]);
    ASSERT_EQ(ca.history[k].normal, cb.history[k].normal);
  }
}

// The restart half of the determinism checks: `first` (stopped part-way, with its punch) goes
// through a snapshot file into a new engine, which then runs on to setup.max_steps.
inline std::unique_ptr<Engine> resume_through_snapshot(const Engine& first, const PunchState& punch,
                                                       CompactionSetup setup,
                                                       const std::string& name) {
  const auto file = shapepress::testing::fresh_directory(name + "_restart") / "snapshot.h5";
  write_snapshot(file, first, compaction_scenario_state(punch, setup),
                 Provenance{"test", "", std::nullopt});
  LoadedSnapshot loaded = read_snapshot(file);
  std::filesystem::remove(file);
  auto resumed = std::make_unique<Engine>(std::move(loaded.state), loaded.box, first.materials(),
                                          first.settings(), std::move(loaded.checkpoint));
  PunchState resumed_punch = punch_state_from(loaded.scenario);
  run_compaction(*resumed, setup, resumed_punch, {});
  return resumed;
}

// The determinism harness every engine feature's scene goes through: `make_scene()` (a
// CompactionScene) run for `steps` steps on one thread and on two. The caller compares the two
// with expect_same_bits (and its own checks, the summaries' work counts among them).
struct ThreadRuns {
  CompactionScene one, two;
  CompactionSummary one_summary, two_summary;
};
template <class MakeScene>
ThreadRuns run_on_one_and_two_threads(MakeScene make_scene, int steps) {
  const int threads = omp_get_max_threads();
  ThreadRuns runs;
  omp_set_num_threads(1);
  runs.one = make_scene();
  runs.one.setup.max_steps = steps;
  runs.one_summary = run_compaction(*runs.one.engine, runs.one.setup, runs.one.punch, {});
  omp_set_num_threads(2);
  runs.two = make_scene();
  runs.two.setup.max_steps = steps;
  runs.two_summary = run_compaction(*runs.two.engine, runs.two.setup, runs.two.punch, {});
  omp_set_num_threads(threads);
  return runs;
}

// The restart half: `continuous` runs `steps` steps; `first` stops mid-way between list builds
// (steps / 2 + 17) and goes through a snapshot file (named after `name`) into `resumed`, which
// runs on to `steps`. One thread: the thread count is the other half's subject, and a team of
// two on a loaded machine spends its time in barriers.
struct RestartRuns {
  CompactionScene continuous, first;
  std::unique_ptr<Engine> resumed;
};
template <class MakeScene>
RestartRuns run_continuous_and_restarted(MakeScene make_scene, int steps, const std::string& name) {
  const int threads = omp_get_max_threads();
  RestartRuns runs;
  omp_set_num_threads(1);
  runs.continuous = make_scene();
  runs.continuous.setup.max_steps = steps;
  run_compaction(*runs.continuous.engine, runs.continuous.setup, runs.continuous.punch, {});
  runs.first = make_scene();
  runs.first.setup.max_steps = steps / 2 + 17;
  run_compaction(*runs.first.engine, runs.first.setup, runs.first.punch, {});
  runs.resumed =
      resume_through_snapshot(*runs.first.engine, runs.first.punch, runs.continuous.setup, name);
  omp_set_num_threads(threads);
  return runs;
}

}  // namespace shapepress::scenarios::testing
