// The list rebuild test measures displacements against the strain the walls impose
// (Engine::list_affine_drift): a fast punch alone no longer forces builds, and only the spheres
// near a wall at a build are tested against it. The list must still hold every contact: a
// brute-force search over all pairs and walls finds no contact the engine missed.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdint>

#include "scenarios/compact.hpp"
#include "tests/validation/scenarios/scenes.hpp"

namespace shapepress::scenarios {
namespace {

// Overlapping pairs by brute force, nearest periodic image in x and y.
std::int64_t touching_pairs(const SphereState& s, const Box& box) {
  std::int64_t count = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j) {
      const double reach = s.radius[i] + s.radius[j];
      const double dz = s.position.z[j] - s.position.z[i];
      if (std::fabs(dz) >= reach) continue;  // z is not periodic
      double dx = s.position.x[j] - s.position.x[i];
      double dy = s.position.y[j] - s.position.y[i];
      dx -= box.length_x * std::nearbyint(dx / box.length_x);
      dy -= box.length_y * std::nearbyint(dy / box.length_y);
      count += dx * dx + dy * dy + dz * dz < reach * reach;
    }
  return count;
}

// Sphere–wall contacts by brute force.
std::int64_t wall_touches(const Engine& engine) {
  std::int64_t count = 0;
  const SphereState& s = engine.state();
  for (const PlaneWall& w : engine.walls())
    for (std::size_t i = 0; i < s.size(); ++i)
      count += w.facing * (s.position.z[i] - w.position) < s.radius[i];
  return count;
}

TEST(ListRebuild, NoContactIsMissedWhileAFastPunchStrainsTheBed) {
  // The determinism scene with the punch at 10 m/s, 10 µm per step: the strain term of the test
  // is large, and the spheres it hits fly off fast.
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);  // the list is the subject; a team of two on a loaded machine waits
  testing::CompactionScene scene = testing::compaction_scene(testing::one_material(0.5, 0.5, 0.02));
  scene.setup.program.speed = 10.0;
  std::int64_t checked = 0, most_contacts = 0, most_wall_contacts = 0;
  for (int block = 1; block <= 100; ++block) {
    scene.setup.max_steps = 10 * block;  // 1000 steps: the punch moves 10 mm
    run_compaction(*scene.engine, scene.setup, scene.punch, {});
    const std::int64_t brute = touching_pairs(scene.engine->state(), scene.engine->box());
    ASSERT_EQ(scene.engine->sphere_contacts(), brute) << "at step " << 10 * block;
    // Only spheres near a wall at the last build are tested against it (Engine::build_list).
    ASSERT_EQ(scene.engine->wall_contacts(), wall_touches(*scene.engine))
        << "at step " << 10 * block;
    most_wall_contacts = std::max(most_wall_contacts, scene.engine->wall_contacts());
    most_contacts = std::max(most_contacts, brute);
    ++checked;
  }
  omp_set_num_threads(threads);
  EXPECT_EQ(checked, 100);
  EXPECT_GT(most_contacts, 1000);      // the bed is compacted, not a gas
  EXPECT_GT(most_wall_contacts, 100);  // and pressed on both plates
}

}  // namespace
}  // namespace shapepress::scenarios
