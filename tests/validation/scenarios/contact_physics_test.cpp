// The contact law against theory (issue 3, Validation): Hertz between plates, restitution of
// head-on impacts, sliding to rolling, CDT rolling deceleration, periodic contacts.
#include <gtest/gtest.h>

#include <numbers>

#include <cmath>
#include <cstdio>
#include <vector>

#include "common/error.hpp"
#include "scenarios/plate.hpp"
#include "simulate/engine.hpp"
#include "simulate/timestep.hpp"
#include "tests/validation/scenarios/scenes.hpp"

namespace shapepress::scenarios {
namespace {

using testing::default_time_step;
using testing::one_material;

constexpr double g = 9.81;

// Two material sets: the reference-scene powder between plates of itself, and the paper's
// rubber sphere (R = 10 mm, E = 18.5 MPa, ν = 0.46, Giannis 2023 §3.1) between steel plates.
struct PlateCase {
  Material sphere;
  Material plate;
  double radius;
};

TEST(Hertz, SphereBetweenPlatesWithinHalfAPercentUpToOnePercentDeformation) {
  const std::vector<PlateCase> cases = {
      {{"powder", 1e8, 0.3, 1541.0}, {"plate", 1e8, 0.3, 1541.0}, 0.5e-3},
      {{"rubber", 18.5e6, 0.46, 1100.0}, {"steel", 210e9, 0.3, 7800.0}, 10e-3}};
  for (const PlateCase& c : cases) {
    const MaterialTable table({c.sphere, c.plate}, {{c.sphere.name, c.plate.name, 0.9, 0.5, 0.0}});
    PlateSetup setup;
    setup.radius = c.radius;
    setup.sphere_material = 0;
    setup.plate_material = 1;
    // Quasi-static: the plate moves 1 % of the diameter in ~400 Rayleigh times.
    const double t_r =
        rayleigh_time(c.radius, c.sphere.density, c.sphere.youngs_modulus, c.sphere.poisson_ratio);
    setup.speed = 0.02 * c.radius / (400.0 * t_r);
    const EngineSettings engine{0.2 * t_r, {0.0, 0.0, 0.0}, 0.1 * c.radius};
    setup.max_deformation = 0.01;
    setup.records = 20;
    const std::vector<PlateRow> rows = run_plate(table, setup, engine);
    ASSERT_EQ(rows.size(), 20u);
    for (const PlateRow& row : rows) {
      if (row.deformation < 0.002) continue;  // below 0.2 % the force is tiny against damping
      // Issue tolerance 0.5 %: what remains is the damping force at the approach speed.
      EXPECT_NEAR(row.top_force / row.hertz_force, 1.0, 0.005)
          << c.sphere.name << " at deformation " << row.deformation;
      EXPECT_NEAR(row.bottom_force / row.hertz_force, 1.0, 0.005) << c.sphere.name;
    }
  }
}

TEST(Hertz, RampedSymmetricPlatesPressTheSameCurveInTheExpectedTime) {
  // [plate] ramp and symmetric: both plates approach at speed/2 after a sin² start. The curve
  // is Hertz's as with one plate, both plates carry it, and the run takes the ramp's extra time
  // (the ramp covers its deformation in twice the full-speed time).
  const Material rubber{"rubber", 18.5e6, 0.46, 1100.0}, steel{"steel", 210e9, 0.3, 7800.0};
  const MaterialTable table({rubber, steel}, {{"rubber", "steel", 0.9, 0.5, 0.0}});
  PlateSetup setup;
  setup.radius = 10e-3;
  setup.sphere_material = 0;
  setup.plate_material = 1;
  const double t_r =
      rayleigh_time(setup.radius, rubber.density, rubber.youngs_modulus, rubber.poisson_ratio);
  setup.speed = 0.02 * setup.radius / (400.0 * t_r);
  const EngineSettings engine{0.2 * t_r, {0.0, 0.0, 0.0}, 0.1 * setup.radius};
  setup.max_deformation = 0.01;
  setup.ramp = 0.004;
  setup.symmetric = true;
  setup.records = 20;
  const std::vector<PlateRow> rows = run_plate(table, setup, engine);
  ASSERT_EQ(rows.size(), 20u);
  for (const PlateRow& row : rows) {
    if (row.deformation < 0.002) continue;
    EXPECT_NEAR(row.top_force / row.hertz_force, 1.0, 0.005) << "at " << row.deformation;
    EXPECT_NEAR(row.bottom_force / row.hertz_force, 1.0, 0.005) << "at " << row.deformation;
  }
  const double expected = (setup.max_deformation + setup.ramp) * 2.0 * setup.radius / setup.speed;
  EXPECT_NEAR(rows.back().time, expected, 2.0 * engine.time_step);
  setup.ramp = setup.max_deformation;  // the ramp must end before the run does
  EXPECT_THROW(run_plate(table, setup, engine), InputError);
}

TEST(Hertz, StackOfSpheresBetweenPlatesFollowsTheSeriesOfItsContacts) {
  // [plate] stack: three rubber spheres one on another between steel plates. Every contact
  // carries the plates' force, so the approach is the sum of two sphere–plate and two
  // sphere–sphere Hertz overlaps (hertz_stack_force). A stack that lost a contact, or counted
  // the deformation on one sphere's diameter, misses it by tens of percent.
  const Material rubber{"rubber", 18.5e6, 0.46, 1100.0}, steel{"steel", 210e9, 0.3, 7800.0};
  const MaterialTable table(
      {rubber, steel}, {{"rubber", "steel", 0.9, 0.5, 0.0}, {"rubber", "rubber", 0.9, 0.5, 0.0}});
  PlateSetup setup;
  setup.radius = 10e-3;
  setup.sphere_material = 0;
  setup.plate_material = 1;
  setup.stack = 3;
  const double t_r =
      rayleigh_time(setup.radius, rubber.density, rubber.youngs_modulus, rubber.poisson_ratio);
  setup.speed = 0.02 * setup.radius / (400.0 * t_r);
  setup.symmetric = true;
  const EngineSettings engine{0.2 * t_r, {0.0, 0.0, 0.0}, 0.1 * setup.radius};
  setup.max_deformation = 0.01;
  setup.records = 20;
  const std::vector<PlateRow> rows = run_plate(table, setup, engine);
  ASSERT_EQ(rows.size(), 20u);
  EXPECT_NEAR(rows.back().approach / (setup.max_deformation * 6.0 * setup.radius), 1.0, 0.01);
  for (const PlateRow& row : rows) {
    if (row.deformation < 0.002) continue;
    EXPECT_NEAR(row.top_force / row.hertz_force, 1.0, 0.005) << "at " << row.deformation;
    EXPECT_NEAR(row.bottom_force / row.hertz_force, 1.0, 0.005) << "at " << row.deformation;
  }
  // One sphere: the stack's closed form is the single sphere's.
  const double e_star = table.pair(0, 1).effective_modulus,
               pair = table.pair(0, 0).effective_modulus;
  const double single = hertz_plate_force(e_star, 1e-3, 2e-5);
  EXPECT_NEAR(hertz_stack_force(e_star, pair, 1e-3, 1, 2e-5), single, 1e-12 * single);
}

// Measured restitution of a head-on impact: relative normal speed after / before.
// `fraction` of the default step (0.2 Rayleigh times). The discrete start and end of a contact
// make the restitution error first order in dt (and dependent on where in a step the contact
// starts): at 1 m/s, e = 0.35 measures 0.343 at the default step, 0.348 at a quarter of it,
// so the test resolves the impact with 0.05 t_R.
double sphere_sphere_restitution(double e, double fraction = 0.25) {
  const MaterialTable table = one_material(e, 0.5);
  const double r = 0.5e-3, v = 0.5;
  SphereState s;
  s.add_sphere(0.0, 0.0, 0.0, r, 1541.0, 0);
  s.add_sphere(2.0 * r + 1e-6, 0.0, 0.0, r, 1541.0, 0);
  s.velocity.x[0] = v;
  s.velocity.x[1] = -v;
  Engine engine(std::move(s), Box{}, table, {},
                EngineSettings{fraction * default_time_step(table, r), {0, 0, 0}, 0.1 * r});
  bool touched = false;
  for (int k = 0; k < 100000; ++k) {
    engine.step();
    if (engine.sphere_contacts() > 0) touched = true;
    if (touched && engine.sphere_contacts() == 0) break;
  }
  return (engine.state().velocity.x[1] - engine.state().velocity.x[0]) / (2.0 * v);
}

double sphere_wall_restitution(double e, double fraction = 0.25) {
  const MaterialTable table = one_material(e, 0.5);
  const double r = 0.5e-3, v = 0.5;
  SphereState s;
  s.add_sphere(0.0, 0.0, r + 1e-6, r, 1541.0, 0);
  s.velocity.z[0] = -v;
  Engine engine(std::move(s), Box{}, table, {PlaneWall{0.0, 1, 0.0, 0}},
                EngineSettings{fraction * default_time_step(table, r), {0, 0, 0}, 0.1 * r});
  bool touched = false;
  for (int k = 0; k < 100000; ++k) {
    engine.step();
    if (engine.wall_contacts() > 0) touched = true;
    if (touched && engine.wall_contacts() == 0) break;
  }
  return engine.state().velocity.z[0] / v;
}

TEST(Restitution, HeadOnImpactsGiveTheInputCoefficient) {
  for (double e : {0.35, 0.7, 0.9}) {
    // Issue tolerance 1 %; the law is exact in continuous time, the rest is the time step.
    std::printf(
        "e = %g measured at 0.2 t_R: sphere-sphere %.4f, sphere-wall %.4f; at 0.05 t_R "
        "(asserted): %.4f, %.4f\n",
        e, sphere_sphere_restitution(e, 1.0), sphere_wall_restitution(e, 1.0),
        sphere_sphere_restitution(e), sphere_wall_restitution(e));
    EXPECT_NEAR(sphere_sphere_restitution(e) / e, 1.0, 0.01) << "sphere-sphere, e = " << e;
    EXPECT_NEAR(sphere_wall_restitution(e) / e, 1.0, 0.01) << "sphere-wall, e = " << e;
  }
}

// Where the discrete law stops meeting the 1 % restitution target: the error against the number
// of steps that resolve the collision. It shrinks about linearly with dt (the damping force rises
// as δ^1/4 at the start of a contact, which a step samples late or early), so the time step, not
// the law, decides the accuracy; docs/stages.md ("compact", time step) quotes this table.
TEST(Restitution, ErrorShrinksWithTheStepsPerCollision) {
  const double e = 0.35, r = 0.5e-3, v = 0.5;
  const MaterialTable table = one_material(e, 0.5);
  const double mass = 1541.0 * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double collision =
      hertz_collision_time(0.5 * mass, 0.5 * r, table.pair(0, 0).effective_modulus, 2.0 * v);
  std::vector<double> errors;
  for (double fraction : {4.0, 2.0, 1.0, 0.5, 0.25}) {  // of 0.05 t_R; 4 = the default 0.2 t_R
    const double dt = 0.25 * fraction * default_time_step(table, r);
    const double error = std::fabs(sphere_sphere_restitution(e, 0.25 * fraction) / e - 1.0);
    std::printf("dt = %.3g t_R: %.1f steps per collision, restitution error %.2f %%\n",
                0.05 * fraction, collision / dt, 100.0 * error);
    errors.push_back(error);
  }
  EXPECT_GT(errors.front(), 4.0 * errors.back()) << "no convergence with the time step";
  for (std::size_t k = 2; k < errors.size(); ++k)  // ≥ 60 steps per collision
    EXPECT_LT(errors[k], 0.01);
}

// A sphere resting on a plate under gravity, settled first so the launch starts from rest.
Engine sphere_on_plate(double mu_s, double mu_r, double r) {
  const MaterialTable table = one_material(0.5, mu_s, mu_r);
  SphereState s;
  s.add_sphere(0.0, 0.0, r, r, 1541.0, 0);
  Engine engine(std::move(s), Box{}, table, {PlaneWall{0.0, 1, 0.0, 0}},
                EngineSettings{default_time_step(table, r), {0, 0, -g}, 0.1 * r});
  for (int k = 0; k < 5000; ++k)
    engine.step();
  return engine;
}

TEST(Friction, SlidingSphereReachesPureRollingAtFiveSeventhsOfItsSpeed) {
  const double r = 0.5e-3, v0 = 0.1, mu = 0.5;
  Engine engine = sphere_on_plate(mu, 0.0, r);
  engine.mutable_state().velocity.x[0] = v0;
  engine.rebase_energy();
  const double start = engine.time();
  const double expected_time = 2.0 * v0 / (7.0 * mu * g);
  double rolling_time = -1.0, rolling_speed = 0.0;
  for (int k = 0; k < 1000000 && rolling_time < 0.0; ++k) {
    engine.step();
    const SphereState& s = engine.state();
    const double slip = s.velocity.x[0] - r * s.angular_velocity.y[0];
    if (slip <= 0.0) rolling_time = engine.time() - start, rolling_speed = s.velocity.x[0];
  }
  // Issue tolerance 1 %: the tangential spring's stretch shifts the onset by a few steps.
  EXPECT_NEAR(rolling_time / expected_time, 1.0, 0.01);
  EXPECT_NEAR(rolling_speed / (5.0 / 7.0 * v0), 1.0, 0.01);
}

TEST(Friction, CdtRollingResistanceDeceleratesAtFiveSeventhsMuRG) {
  const double r = 0.5e-3, v0 = 0.05, mu_r = 0.05;
  Engine engine = sphere_on_plate(0.5, mu_r, r);
  engine.mutable_state().velocity.x[0] = v0;
  engine.mutable_state().angular_velocity.y[0] = v0 / r;  // pure rolling from the start
  engine.rebase_energy();
  const double expected = 5.0 / 7.0 * mu_r * g;  // rolling: (m + I/R²) a = μr R m g / R
  // Least-squares slope of v(t) while the sphere still rolls (v > v0/5).
  double st = 0, sv = 0, stt = 0, stv = 0;
  int n = 0;
  const double t0 = engine.time();
  while (engine.state().velocity.x[0] > 0.2 * v0) {
    engine.step();
    const double t = engine.time() - t0, v = engine.state().velocity.x[0];
    st += t, sv += v, stt += t * t, stv += t * v, ++n;
  }
  const double slope = (n * stv - st * sv) / (n * stt - st * st);
  EXPECT_NEAR(-slope / expected, 1.0, 0.02);  // issue tolerance 2 %
}

TEST(Periodic, ContactAcrossTheBoundaryEqualsTheSamePairInside) {
  const MaterialTable table = one_material(0.5, 0.5);
  const double r = 0.5e-3, length = 10e-3;
  const auto pair_at = [&](double x0) {
    SphereState s;
    s.add_sphere(x0, 5e-3, 5e-3, r, 1541.0, 0);
    s.add_sphere(x0 + 0.95e-3, 5.2e-3, 5e-3, r, 1541.0, 0);
    s.velocity.x[0] = 0.3;  // oblique approach with spin: normal, tangential and torque
    s.velocity.y[1] = -0.2;
    s.angular_velocity.z[0] = 50.0;
    return Engine(std::move(s), Box{length, length}, table, {},
                  EngineSettings{default_time_step(table, r), {0, 0, 0}, 0.1 * r});
  };
  Engine across = pair_at(length - 0.5e-3);  // the pair straddles x = L, and wraps while moving
  Engine inside = pair_at(4.0e-3);
  double largest = 0.0;
  for (int k = 0; k < 400; ++k) {
    across.step();
    inside.step();
    const double scale = std::abs(inside.state().force.x[0]) + std::abs(inside.state().force.y[0]);
    largest = std::max(largest, scale);
    for (int i = 0; i < 2; ++i) {
      // Same geometry up to the round-off of positions near 10 mm versus 4 mm.
      EXPECT_NEAR(across.state().force.x[i], inside.state().force.x[i], 1e-6 * scale + 1e-12);
      EXPECT_NEAR(across.state().force.y[i], inside.state().force.y[i], 1e-6 * scale + 1e-12);
      EXPECT_NEAR(across.state().torque.z[i], inside.state().torque.z[i], 1e-6 * scale * r + 1e-15);
    }
  }
  EXPECT_GT(largest, 1e-3);                         // the spheres did collide
  EXPECT_LT(across.state().position.x[0], length);  // and wrapped across x = L
}

}  // namespace
}  // namespace shapepress::scenarios
