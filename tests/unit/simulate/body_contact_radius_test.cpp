// Contacts between bodies with the bodies' curvature (Interaction::contact_radius = "body"): a
// pair of sub-spheres of two different bodies takes R* of the bodies' volume-equivalent radii in
// its normal law, on the vectorized block path and on the scalar one; within one body, with the
// default, and for plain spheres (to the bit), R* stays the spheres'; the time step's bound follows
// the stiffer contact, and a snapshot keeps the bodies' radii.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "simulate/engine.hpp"
#include "simulate/snapshot.hpp"
#include "simulate/timestep.hpp"
#include "tests/support/files.hpp"

namespace shapepress::simulate {
namespace {

constexpr double young = 1e8, poisson = 0.3, density = 1541.0;
constexpr double r = 1e-4, overlap = 1e-3 * r;

// Two equal spheres touching along x with `overlap`, at rest; `materials` {0, 0} selects the
// vectorized block (one sphere material), {0, 1} the scalar pair loop.
SphereState touching_pair(std::vector<int> materials, std::vector<std::int32_t> bodies,
                          std::vector<double> body_radii) {
  SphereState s;
  s.add_sphere(0.0, 0.0, 0.0, r, density, materials[0]);
  s.add_sphere(2.0 * r - overlap, 0.0, 0.0, r, density, materials[1]);
  s.body = to_sphere_array(bodies);
  s.body_radius = to_sphere_array(body_radii);
  return s;
}

MaterialTable table(bool body_contact_radius) {
  Interaction same{"p", "p", 1.0, 0.5, 0.0, HertzLaw{}};
  Interaction other{"p", "q", 1.0, 0.5, 0.0, HertzLaw{}};
  Interaction q{"q", "q", 1.0, 0.5, 0.0, HertzLaw{}};
  same.body_contact_radius = other.body_contact_radius = q.body_contact_radius =
      body_contact_radius;
  return MaterialTable({{"p", young, poisson, density}, {"q", young, poisson, density}},
                       {same, other, q});
}

double pair_force(const SphereState& s, bool body_contact_radius) {
  const Engine engine(SphereState(s), Box{}, table(body_contact_radius), {},
                      EngineSettings{1e-9, {0, 0, 0}, 0.1 * r});
  return engine.state().force.x[1];
}

double hertz(double effective_radius) {
  const double star = young / (2.0 * (1.0 - poisson * poisson));
  return 4.0 / 3.0 * star * std::sqrt(effective_radius) * overlap * std::sqrt(overlap);
}

TEST(BodyContactRadius, APairOfTwoBodiesTakesTheBodiesRadiiOnEitherPath) {
  const double bodies = 5.0 * r * 3.0 * r / (8.0 * r);
  for (const std::vector<int>& materials : {std::vector<int>{0, 0}, std::vector<int>{0, 1}}) {
    const SphereState s = touching_pair(materials, {0, 1}, {5.0 * r, 3.0 * r});
    EXPECT_NEAR(pair_force(s, true), hertz(bodies), 1e-12 * hertz(bodies)) << materials[1];
    EXPECT_NEAR(pair_force(s, false), hertz(0.5 * r), 1e-12 * hertz(0.5 * r)) << materials[1];
  }
  EXPECT_GT(hertz(bodies) / hertz(0.5 * r), 1.9);  // √3.75: the rule is not a no-op here
}

TEST(BodyContactRadius, WithinABodyAndBetweenPlainSpheresTheSpheresOwn) {
  for (const std::vector<int>& materials : {std::vector<int>{0, 0}, std::vector<int>{0, 1}}) {
    const SphereState one_body = touching_pair(materials, {0, 0}, {5.0 * r, 5.0 * r});
    EXPECT_NEAR(pair_force(one_body, true), hertz(0.5 * r), 1e-12 * hertz(0.5 * r));
    const SphereState plain = touching_pair(materials, {0, 1}, {r, r});
    EXPECT_EQ(pair_force(plain, true), pair_force(plain, false));  // to the bit
    EXPECT_NEAR(pair_force(plain, true), hertz(0.5 * r), 1e-12 * hertz(0.5 * r));
  }
}

// The Rayleigh bound reads the stiffer contact: its Hertz tangent is √(R*_b / R*) times the
// sub-spheres', the modulus a sphere stands against grows by that and the time by its -1/2 power.
// Sphere 0 meets the largest body (itself, 5r) at R*_b = 2.5 r against R* = r/2: √5.
TEST(BodyContactRadius, TheTimeStepFollowsTheStifferContact) {
  const SphereState s = touching_pair({0, 0}, {0, 1}, {5.0 * r, 3.0 * r});
  const TimeStepChoice spheres = select_time_step(s, table(false), {}, std::nullopt, 0.1, 0.01);
  const TimeStepChoice bodies = select_time_step(s, table(true), {}, std::nullopt, 0.1, 0.01);
  EXPECT_NEAR(bodies.rayleigh_time / spheres.rayleigh_time, std::pow(5.0, -0.25), 1e-12);
}

TEST(BodyContactRadius, ASnapshotKeepsTheBodiesRadii) {
  const SphereState s = touching_pair({0, 0}, {0, 1}, {5.0 * r, 3.0 * r});
  const Engine engine(SphereState(s), Box{}, table(true), {},
                      EngineSettings{1e-9, {0, 0, 0}, 0.1 * r});
  const std::filesystem::path file =
      shapepress::testing::fresh_directory("body_contact_radius") / "snapshot.h5";
  write_snapshot(file, engine, ScenarioState{}, Provenance{"test", "", std::nullopt});
  const LoadedSnapshot loaded = read_snapshot(file);
  std::filesystem::remove(file);
  EXPECT_EQ(std::vector<double>(loaded.state.body_radius.begin(), loaded.state.body_radius.end()),
            (std::vector<double>{5.0 * r, 3.0 * r}));
  const Engine resumed(SphereState(loaded.state), loaded.box, table(true), engine.settings(),
                       EngineCheckpoint(loaded.checkpoint));
  EXPECT_EQ(resumed.state().force.x[1], engine.state().force.x[1]);
}

}  // namespace
}  // namespace shapepress::simulate
