// The punch program's phases: displacement to a target gap, hold, unload until the force
// vanishes; the servo's bounded speed; and the time-step check against the Hertz time.
#include <gtest/gtest.h>

#include "common/error.hpp"
#include "scenarios/punch.hpp"
#include "simulate/bonds.hpp"
#include "simulate/timestep.hpp"

namespace shapepress::scenarios {
namespace {

TEST(Punch, DisplacementProgramLoadsHoldsAndUnloadsUntilTheForceVanishes) {
  PunchProgram p;
  p.speed = 1.0;
  p.target_gap = 0.01;
  p.hold_time = 0.5;
  p.unload_speed = 2.0;
  PunchState state;
  EXPECT_EQ(punch_velocity(p, state, 0.0, 0.02, 0.0), -1.0);
  EXPECT_EQ(state.phase, PunchPhase::load);
  EXPECT_EQ(punch_velocity(p, state, 1.0, 0.0099, 5e6), 0.0);  // target reached: hold
  EXPECT_EQ(state.phase, PunchPhase::hold);
  EXPECT_EQ(punch_velocity(p, state, 1.4, 0.0099, 4e6), 0.0);
  EXPECT_EQ(punch_velocity(p, state, 1.6, 0.0099, 4e6), 2.0);  // hold over: unload upwards
  EXPECT_EQ(state.phase, PunchPhase::unload);
  EXPECT_EQ(punch_velocity(p, state, 1.7, 0.0101, 1e3), 2.0);
  EXPECT_EQ(punch_velocity(p, state, 1.8, 0.0102, 0.0), 0.0);  // force gone: done
  EXPECT_EQ(state.phase, PunchPhase::done);
}

// relax_time: the punch stays put first; release_time: after the force has gone, the punch
// follows the bed's spring-back at 1 % of the peak stress (up when the bed pushes more, down at
// most at the unloading speed when it pushes less), and only then is the run done.
TEST(Punch, RelaxesBeforeLoadingAndFollowsTheSpringBackAfterUnloading) {
  PunchProgram p;
  p.speed = 1.0;
  p.target_gap = 0.01;
  p.unload_speed = 2.0;
  p.relax_time = 0.3;
  p.release_time = 0.5;
  p.release_stress_fraction = 0.01;
  PunchState state;
  state.phase = PunchPhase::relax;
  EXPECT_EQ(punch_velocity(p, state, 0.0, 0.02, 1e3), 0.0);
  EXPECT_EQ(punch_velocity(p, state, 0.29, 0.02, 1e3), 0.0);
  EXPECT_EQ(state.phase, PunchPhase::relax);
  EXPECT_EQ(punch_velocity(p, state, 0.31, 0.02, 1e3), -1.0);  // relaxed: loading
  EXPECT_EQ(state.phase, PunchPhase::load);
  EXPECT_EQ(punch_velocity(p, state, 0.9, 0.015, 4e6), -1.0);
  EXPECT_EQ(punch_velocity(p, state, 1.0, 0.0099, 5e6), 2.0);  // the target; no hold: unload
  EXPECT_EQ(state.peak_stress, 5e6);
  EXPECT_EQ(state.phase, PunchPhase::unload);
  EXPECT_EQ(punch_velocity(p, state, 1.1, 0.0101, 1e3), 2.0);
  // The force gone: release, at 1 % of the 5 MPa peak.
  EXPECT_EQ(punch_velocity(p, state, 1.2, 0.0102, 0.0), -2.0);  // no push: follow down at most
  EXPECT_EQ(state.phase, PunchPhase::release);
  EXPECT_EQ(punch_velocity(p, state, 1.3, 0.0102, 5e4), 0.0);  // at the held stress: still
  EXPECT_NEAR(punch_velocity(p, state, 1.4, 0.0102, 7.5e4), 1.0, 1e-12);  // half over: up
  EXPECT_EQ(punch_velocity(p, state, 1.5, 0.0102, 1e8), 200.0);  // at most 100 × the speed
  EXPECT_EQ(punch_velocity(p, state, 1.71, 0.0102, 5e4), 0.0);   // the release is over
  EXPECT_EQ(state.phase, PunchPhase::done);
  // The peak and the phase survive a checkpoint.
  const PunchState back = punch_state_from(punch_scenario_state(state));
  EXPECT_EQ(back.phase, PunchPhase::done);
  EXPECT_EQ(back.peak_stress, 5e6);
}

// compact's progress line for a displacement run: the relaxation left, the travel at the
// punch's speed, the hold, a quarter of the travel back at the unloading speed (then, while
// unloading, the stress's fall extrapolated to zero), the release.
TEST(Punch, RemainingStepsFollowThePhases) {
  PunchProgram p;
  p.speed = 0.1;
  p.target_gap = 1e-3;
  p.min_gap = 1.2e-3;  // the ceiling stops loading first
  p.hold_time = 1e-3;
  p.unload_speed = 0.2;
  p.relax_time = 2e-3;
  p.release_time = 3e-3;
  PunchState state;
  state.phase = PunchPhase::relax;
  const double dt = 1e-6;
  const double travel = 2e-3 - 1.2e-3;  // from a gap of 2 mm to the ceiling's
  EXPECT_NEAR(remaining_steps_estimate(p, state, 0.5e-3, 2e-3, 0.0, dt),
              (1.5e-3 + travel / 0.1 + 1e-3 + 0.25 * travel / 0.2 + 3e-3) / dt, 1e-6);
  // Unloading from a 5 MPa peak, begun at t = 10 ms, of a run that started at a 2 mm gap.
  state.phase = PunchPhase::unload;
  state.phase_start = 10e-3;
  state.peak_stress = 5e6;
  state.reference_gap = 2e-3;
  const double guess = 0.25 * travel / 0.2;
  // Hardly fallen yet (2 %): the guess less the time spent.
  EXPECT_NEAR(remaining_steps_estimate(p, state, 10.4e-3, 1.21e-3, 4.9e6, dt),
              (guess - 0.4e-3 + 3e-3) / dt, 1e-6);
  // Fallen by 3 MPa in 2 ms: 2 MPa more at that rate, 1.33 ms; never a negative time.
  EXPECT_NEAR(remaining_steps_estimate(p, state, 12e-3, 1.25e-3, 2e6, dt),
              (2e-3 * 2.0 / 3.0 + 3e-3) / dt, 1e-6);
  EXPECT_NEAR(remaining_steps_estimate(p, state, 20e-3, 1.4e-3, -1e3, dt), 3e-3 / dt, 1e-6);
  EXPECT_NEAR(remaining_steps_estimate(p, state, 30e-3, 1.4e-3, 4.9e6, dt), 3e-3 / dt, 1e-6);
  state.phase = PunchPhase::done;
  EXPECT_EQ(remaining_steps_estimate(p, state, 0.0, 1.3e-3, 0.0, dt), 0.0);
  p.mode = PunchProgram::Mode::servo;  // no target gap to travel to
  state.phase = PunchPhase::load;
  EXPECT_EQ(remaining_steps_estimate(p, state, 0.0, 2e-3, 0.0, dt), 0.0);
}

TEST(Punch, ServoSpeedIsBoundedAndProportionalNearTheTarget) {
  PunchProgram p;
  p.mode = PunchProgram::Mode::servo;
  p.target_stress = 1e6;
  p.max_speed = 0.1;
  p.hold_time = 1.0;
  PunchState state;
  EXPECT_EQ(punch_velocity(p, state, 0.0, 0.01, 0.0), -0.1);  // far below: full speed down
  EXPECT_EQ(punch_velocity(p, state, 0.0, 0.01, 3e6), 0.1);   // far above: full speed up
  EXPECT_NEAR(punch_velocity(p, state, 0.0, 0.01, 0.975e6), -0.05, 1e-12);  // half the band
  EXPECT_EQ(state.phase, PunchPhase::load);
  punch_velocity(p, state, 0.1, 0.01, 1.005e6);  // within 1 %: holds the stress
  EXPECT_EQ(state.phase, PunchPhase::hold);
  EXPECT_GT(punch_velocity(p, state, 0.2, 0.01, 1.03e6), 0.0);  // still servoing in the hold
}

TEST(TimeStep, StepTooCoarseForAHertzCollisionIsAnInputError) {
  const MaterialTable table({{"m", 1e8, 0.3, 1541.0}}, {{"m", "m", 0.5, 0.5}});
  SphereState s;
  s.add_sphere(0, 0, 0, 0.5e-3, 1541.0, 0);
  const TimeStepChoice ok = select_time_step(s, table, {0}, std::nullopt, 0.2, 2.5);
  EXPECT_NEAR(ok.time_step, 0.2 * ok.rayleigh_time, 1e-20);
  EXPECT_GT(ok.collision_time, minimum_steps_per_collision * ok.time_step);
  EXPECT_THROW(select_time_step(s, table, {0}, 1e-5, 0.2, 2.5), InputError);
}

TEST(TimeStep, AStiffStatedPairShortensTheRayleighStep) {
  // Soft spheres (E = 20 MPa) against a plate whose pair states E* = 1 GPa: the step is that of
  // a sphere with (1 − ν²) E* against a rigid wall, not of the soft material.
  const Material soft{"soft", 2e7, 0.46, 2000.0}, plate{"plate", 1e9, 0.3, 7800.0};
  Interaction against_plate{"soft", "plate", 0.7, 0.5};
  SphereState s;
  s.add_sphere(0, 0, 0, 1e-3, 2000.0, 0);
  const MaterialTable plain({soft, plate}, {{"soft", "soft", 0.7, 0.5}, against_plate});
  against_plate.effective_modulus = 1e9;
  const MaterialTable stated({soft, plate}, {{"soft", "soft", 0.7, 0.5}, against_plate});
  const TimeStepChoice a = select_time_step(s, plain, {1}, std::nullopt, 0.2, 0.01);
  const TimeStepChoice b = select_time_step(s, stated, {1}, std::nullopt, 0.2, 0.01);
  EXPECT_NEAR(a.rayleigh_time, rayleigh_time(1e-3, 2000.0, 2e7, 0.46), 1e-18);
  EXPECT_NEAR(b.rayleigh_time, rayleigh_time(1e-3, 2000.0, (1 - 0.46 * 0.46) * 1e9, 0.46), 1e-18);
  EXPECT_LT(b.time_step, a.time_step);
}

TEST(TimeStep, TheCollisionCheckSeesTheStepAfterTheBondBound) {
  // Stiff bonds between soft spheres: the Rayleigh step alone resolves a 5 m/s impact on the
  // stiff plate with fewer than 10 steps, the bond bound's shorter step does not; the check
  // judges the step the run takes. The fraction is 0.3, below the bonds' stability limit (at
  // least 0.9/π of the period bound) above which a step the bonds set is refused.
  const Material soft{"soft", 2e7, 0.46, 2000.0}, plate{"plate", 1e9, 0.3, 7800.0};
  Interaction against_plate{"soft", "plate", 0.7, 0.5};
  against_plate.effective_modulus = 1e9;
  const MaterialTable table({soft, plate}, {{"soft", "soft", 0.7, 0.5}, against_plate});
  SphereState s;
  s.add_sphere(0, 0, 0, 1e-3, 2000.0, 0);
  s.add_sphere(2e-3, 0, 0, 1e-3, 2000.0, 0);
  s.body = {0, 0};
  EXPECT_THROW(select_time_step(s, table, {1}, std::nullopt, 0.3, 5.0), InputError);
  BondParameters stiff;
  stiff.normal_stiffness = stiff.shear_stiffness = 1e14;
  const BondSet bonds = create_bonds(s, 1.15, stiff);
  const TimeStepChoice dt = select_time_step(s, table, {1}, std::nullopt, 0.3, 5.0, bonds);
  EXPECT_LT(dt.time_step, dt.rayleigh_time);
  EXPECT_GT(dt.collision_time, minimum_steps_per_collision * dt.time_step);
}

}  // namespace
}  // namespace shapepress::scenarios
