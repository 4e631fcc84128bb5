// One elastic–perfectly plastic sphere (the MDR law, Avicel-like: E = 8 GPa, ν = 0.3,
// Y = 160 MPa) pressed between two rigid plates to 40 % of its diameter (each plate 0.4 R into it)
// and drawn back until it is free: the plates' force against the law's closed form of one
// sphere on a flat at half the approach (the law's own function at rest, whose values
// contact_law_reference_test.cpp checks against mdr.csv; docs/models.md, "Contact law: MDR"), on
// loading, past yield, on unloading along the elastic branch and at zero force. The run is the
// engine's own wall path (forces.cpp), the step the engine's rule (with the law's stiffness
// ratio), the plates slow against the sphere's contact period so that the run is quasi-static.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "packing/packing.hpp"
#include "scenarios/namespaces.hpp"
#include "simulate/contact_law.hpp"
#include "simulate/engine.hpp"
#include "simulate/timestep.hpp"

namespace shapepress::scenarios {
namespace {

constexpr double radius = 1e-3;  // m

MaterialTable mdr_table() {
  const MdrLaw law{1.6e8};
  // The plate is stiff enough to be rigid (its compliance moves E* by 1e-6).
  return MaterialTable(
      {{"avicel", 8e9, 0.3, 1560.0}, {"plate", 8e15, 0.3, 7800.0}},
      {{"avicel", "avicel", 0.5, 0.5, 0.0, law}, {"avicel", "plate", 0.5, 0.5, 0.0, law}});
}

// The law of one plate contact at rest, overlap δ, with the history of the largest δ so far.
double closed_form(const MaterialTable& table, double overlap, ContactHistory& history) {
  ContactKinematics c{};
  c.normal[2] = 1.0;
  c.overlap = overlap;
  c.effective_radius = radius;
  c.effective_mass = 1.0;
  c.radius_first = radius;
  c.radius_second = 0.0;
  const double root = std::sqrt(radius * overlap);
  return normal_force_of<MdrLaw>(table.pair(0, 1), c, root, std::sqrt(root), 0.0, history).force;
}

TEST(MdrSphere, PressedAndUnloadedBetweenPlatesFollowsTheClosedForm) {
  const MaterialTable table = mdr_table();
  packing::SphereList list;
  list.x = {0.0}, list.y = {0.0}, list.z = {radius}, list.radius = {radius};
  SphereState state = packing::make_state(list, 1560.0, 0);
  EngineSettings settings;
  settings.time_step = select_time_step(state, table, {1}, std::nullopt, 0.2, 0.1).time_step;
  settings.skin = 0.1 * radius;
  settings.max_overlap_fraction = 0.6;
  settings.check_every = 1000;
  // Both plates move, each at half the approach speed: the sphere's centre stays put.
  constexpr double speed = 0.1;  // m/s of approach
  Engine engine(std::move(state), Box{}, table,
                {PlaneWall{0.0, 1, 0.5 * speed, 1}, PlaneWall{2.0 * radius, -1, -0.5 * speed, 1}},
                settings);
  const double largest_approach = 0.8 * radius;
  ContactHistory history;  // of the closed form, the largest overlap walked like the run's
  double peak = 0.0, worst = 0.0;
  int compared = 0, unloading_rows = 0, free_rows = 0;
  bool unloading = false;
  std::int64_t step = 0;
  for (;;) {
    engine.step();
    ++step;
    const double approach =
        2.0 * radius - (engine.walls()[1].position - engine.walls()[0].position);
    if (!unloading && approach >= largest_approach) {
      unloading = true;
      // The sphere yielded: the contact's yield strain is set.
      EXPECT_GT(law_history<MdrLaw>(engine.checkpoint().wall_history[1][0])[1], 0.0);
      engine.walls()[0].velocity = -0.5 * speed;
      engine.walls()[1].velocity = 0.5 * speed;
    }
    // The closed form walks every step, so its largest overlap is the run's: the unloading branch
    // is so steep (the sphere gives back about 14 µm a plate from 400 µm) that a largest overlap
    // taken only at the compared steps would put it on another curve.
    const double expected = closed_form(table, std::max(0.5 * approach, 0.0), history);
    // Every 200th step on loading and after the sphere is free, every step while it unloads
    // (about 1100 steps at this speed).
    if (step % 200 != 0 && !(unloading && expected > 0.0)) continue;
    const double top = engine.wall_load(1), bottom = engine.wall_load(0);
    peak = std::max(peak, expected);
    // Within 0.2 % of the peak force everywhere (the damping of a plate at 0.05 m/s and the
    // sphere's inertia; both plates alike). Measured: 0.19 N of 410 N, on unloading.
    worst = std::max({worst, std::fabs(top - expected), std::fabs(bottom - expected)});
    ++compared;
    unloading_rows += unloading && expected > 0.0;
    if (unloading && expected == 0.0) {
      ++free_rows;
      EXPECT_EQ(top, 0.0) << "the sphere still pushes at approach " << approach;
      // It kept a plastic flat: it lets go of the plates long before the approach is 0.
      EXPECT_GT(approach, 0.5 * largest_approach);
      if (free_rows == 5) break;
    }
    ASSERT_LT(step, 10'000'000) << "the plates never let go";
  }
  engine.check_divergence();
  EXPECT_GT(compared, 100);
  EXPECT_GT(unloading_rows, 20) << "the unloading branch was not sampled";
  EXPECT_GT(peak, 0.0);
  EXPECT_LT(worst, 0.002 * peak) << "peak " << peak << " N";
  RecordProperty("peak_force_N", std::to_string(peak));
  RecordProperty("largest_error_N", std::to_string(worst));
}

}  // namespace
}  // namespace shapepress::scenarios
