// The engine on small scenes: momentum in a collision, thread-count independence, divergence
// reported with sphere and step, the time-step formulas.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "common/error.hpp"
#include "packing/packing.hpp"
#include "simulate/engine.hpp"
#include "simulate/timestep.hpp"

namespace shapepress::packing {
namespace {

MaterialTable powder(double e = 0.35, double mu = 0.5, double mu_r = 0.0) {
  return MaterialTable({{"powder", 1e8, 0.3, 1541.0}}, {{"powder", "powder", e, mu, mu_r}});
}

Engine random_box(std::uint64_t seed, int count = 1200) {
  const Box box{16e-3, 16e-3};
  InsertionRequest request{count, 0.8e-3, 1.2e-3, 0.0, 12e-3, seed};
  SphereState s = make_state(insert_random_spheres(box, request), 1541.0, 0);
  std::mt19937_64 random(seed);
  std::normal_distribution<double> speed(0.0, 0.5);
  for (std::size_t i = 0; i < s.size(); ++i) {
    s.velocity.x[i] = speed(random);
    s.velocity.y[i] = speed(random);
    s.velocity.z[i] = speed(random);
  }
  EngineSettings settings{1e-6, {0, 0, -9.81}, 0.1e-3};
  return Engine(std::move(s), box, powder(),
                {PlaneWall{0.0, 1, 0.0, 0}, PlaneWall{12e-3, -1, -0.5, 0}}, settings);
}

TEST(Engine, HeadOnCollisionConservesMomentum) {
  SphereState s;
  s.add_sphere(0.0, 0.0, 0.0, 0.5e-3, 1541.0, 0);
  s.add_sphere(1.05e-3, 0.0, 0.0, 0.5e-3, 1541.0, 0);
  s.velocity.x[0] = 1.0;
  s.velocity.y[0] = 0.2;  // oblique, so friction and spin take part
  Engine engine(std::move(s), Box{}, powder(), {}, EngineSettings{1e-7, {0, 0, 0}, 1e-4});
  for (int k = 0; k < 2000; ++k)
    engine.step();
  const SphereState& out = engine.state();
  const double m = out.mass[0];
  EXPECT_NEAR(m * (out.velocity.x[0] + out.velocity.x[1]), m * 1.0, 1e-12 * m);
  EXPECT_NEAR(m * (out.velocity.y[0] + out.velocity.y[1]), m * 0.2, 1e-12 * m);
  EXPECT_LT(out.velocity.x[0], out.velocity.x[1]);  // they bounced apart
  EXPECT_EQ(engine.sphere_contacts(), 0);
}

TEST(Engine, SameBitsForOneAndTwoThreads) {
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  Engine one = random_box(3);
  for (int k = 0; k < 300; ++k)
    one.step();
  omp_set_num_threads(2);
  Engine two = random_box(3);
  for (int k = 0; k < 300; ++k)
    two.step();
  omp_set_num_threads(threads);
  EXPECT_GT(one.sphere_contacts(), 50);  // the scene really collides
  EXPECT_TRUE(one.state().position == two.state().position);
  EXPECT_TRUE(one.state().velocity == two.state().velocity);
  EXPECT_TRUE(one.state().angular_velocity == two.state().angular_velocity);
  EXPECT_EQ(one.wall_force(1), two.wall_force(1));
}

TEST(Engine, TooLargeTimeStepStopsNamingSphereAndStep) {
  SphereState s;
  s.add_sphere(0.0, 0.0, 0.49e-3, 0.5e-3, 1541.0, 0);
  s.velocity.z[0] = -20.0;
  EngineSettings settings{1e-4, {0, 0, 0}, 1e-4, 0.5, 1};
  Engine engine(std::move(s), Box{}, powder(1.0), {PlaneWall{0.0, 1, 0.0, 0}}, settings);
  try {
    for (int k = 0; k < 100; ++k)
      engine.step();
    FAIL() << "no divergence detected";
  } catch (const ComputationError& error) {
    EXPECT_THAT(error.what(), ::testing::HasSubstr("sphere 0"));
    EXPECT_THAT(error.what(), ::testing::HasSubstr("step 1"));
  }
}

TEST(Engine, MissingInteractionIsAnInputError) {
  SphereState s;
  s.add_sphere(0.0, 0.0, 1e-3, 0.5e-3, 1541.0, 0);
  MaterialTable table({{"powder", 1e8, 0.3, 1541.0}, {"steel", 2e11, 0.3, 7800.0}},
                      {{"powder", "powder", 0.5, 0.5, 0.0}});
  EXPECT_THROW(Engine(std::move(s), Box{}, table, {PlaneWall{0.0, 1, 0.0, 1}},
                      EngineSettings{1e-7, {0, 0, 0}, 1e-4}),
               InputError);
}

TEST(TimeStep, RayleighAndHertzTimesOfTheReferenceScene) {
  // d = 1 mm, ρ = 1541, E = 1e8, ν = 0.3: t_R = π r √(ρ/G) / 0.92553 = 1.0747e-5 s.
  EXPECT_NEAR(rayleigh_time(0.5e-3, 1541.0, 1e8, 0.3), 1.0747e-5, 1e-8);
  // Hertz time falls with speed as v^(-1/5).
  const double slow = hertz_collision_time(4e-7, 2.5e-4, 5.5e7, 1.0);
  const double fast = hertz_collision_time(4e-7, 2.5e-4, 5.5e7, 32.0);
  EXPECT_NEAR(slow / fast, 2.0, 1e-12);
}

}  // namespace
}  // namespace shapepress::packing

namespace shapepress::packing {
namespace {

TEST(Packing, CellOrderKeepsTheSpheresAndNumbersThemLayerByLayer) {
  const Box box{16e-3, 16e-3};
  const SphereList inserted =
      insert_random_spheres(box, InsertionRequest{1200, 0.8e-3, 1.2e-3, 0.0, 12e-3, 3});
  const double cell = 1.2e-3;
  const SphereList ordered = in_cell_order(inserted, cell);
  ASSERT_EQ(ordered.size(), inserted.size());
  // The same spheres: every (x, y, z, r) once.
  const auto rows = [](const SphereList& l) {
    std::vector<std::array<double, 4>> r;
    for (std::size_t i = 0; i < l.size(); ++i)
      r.push_back({l.x[i], l.y[i], l.z[i], l.radius[i]});
    std::sort(r.begin(), r.end());
    return r;
  };
  EXPECT_EQ(rows(ordered), rows(inserted));
  // Layer by layer: the z cell never decreases along the numbering, and in random insertion
  // order it does about half the time.
  const double z0 = *std::min_element(inserted.z.begin(), inserted.z.end());
  const auto descents = [&](const SphereList& l) {
    int count = 0;
    for (std::size_t i = 1; i < l.size(); ++i)
      count += static_cast<int>((l.z[i] - z0) / cell) < static_cast<int>((l.z[i - 1] - z0) / cell);
    return count;
  };
  EXPECT_EQ(descents(ordered), 0);
  EXPECT_GT(descents(inserted), 300);
}

}  // namespace
}  // namespace shapepress::packing
