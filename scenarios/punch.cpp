#include "scenarios/punch.hpp"

#include <algorithm>
#include <string>

#include "common/error.hpp"

namespace shapepress::scenarios {

ScenarioState punch_scenario_state(const PunchState& state) {
  return {{"punch_phase", static_cast<double>(state.phase)},
          {"punch_phase_start", state.phase_start},
          {"punch_reference_gap", state.reference_gap},
          {"punch_work", state.work},
          {"punch_peak_stress", state.peak_stress}};
}

PunchState punch_state_from(const ScenarioState& scenario) {
  auto value = [&](const std::string& name) {
    for (const auto& [key, v] : scenario)
      if (key == name) return v;
    throw InputError("snapshot: /scenario has no '" + name + "' (not a compaction snapshot)");
  };
  PunchState state;
  state.phase = static_cast<PunchPhase>(static_cast<int>(value("punch_phase")));
  state.phase_start = value("punch_phase_start");
  state.reference_gap = value("punch_reference_gap");
  // Snapshots written before the punch's work was kept have none: it counts from the restart.
  // Nor the peak stress before the release phase: it is the one the run records from then on.
  for (const auto& [key, v] : scenario) {
    if (key == "punch_work") state.work = v;
    if (key == "punch_peak_stress") state.peak_stress = v;
  }
  if (static_cast<int>(state.phase) < 0 || static_cast<int>(state.phase) > 5)
    throw InputError("snapshot: /scenario punch_phase " +
                     std::to_string(static_cast<int>(state.phase)) + " is not a punch phase");
  return state;
}

std::string phase_name(PunchPhase phase) {
  switch (phase) {
    case PunchPhase::load:
      return "load";
    case PunchPhase::hold:
      return "hold";
    case PunchPhase::unload:
      return "unload";
    case PunchPhase::done:
      return "done";
    case PunchPhase::release:
      return "release";
    case PunchPhase::relax:
      return "relax";
  }
  return "done";
}

namespace {

void enter(PunchState& state, PunchPhase phase, double time) {
  state.phase = phase;
  state.phase_start = time;
}

double servo_velocity(const PunchProgram& p, double stress) {
  const double error = (p.target_stress - stress) / p.target_stress;  // > 0: press harder
  return -p.max_speed * std::clamp(error / p.servo_band, -1.0, 1.0);
}

// After unloading: up at the unloading speed per held stress of excess (so a bed that springs
// back faster than the unloading is followed, up to 100 times that speed), down to follow it at
// most at the unloading speed when it pushes less. The gain is small against a bed's stiffness:
// a step moves the punch by unload_speed × dt per held stress, a tiny fraction of the overlaps.
double release_velocity(const PunchProgram& p, const PunchState& state, double stress) {
  const double held = p.release_stress_fraction * state.peak_stress;
  if (!(held > 0.0)) return 0.0;
  return p.unload_speed * std::clamp((stress - held) / held, -1.0, 100.0);
}

}  // namespace

double remaining_steps_estimate(const PunchProgram& p, const PunchState& state, double time,
                                double gap, double stress, double time_step) {
  if (p.mode != PunchProgram::Mode::displacement || !p.target_gap || !(time_step > 0.0) ||
      !(p.speed > 0.0))
    return 0.0;
  const double end = std::max(*p.target_gap, p.min_gap.value_or(0.0));
  const double elapsed = time - state.phase_start;
  const double travel = std::max(0.0, gap - end);
  const double spring_back = p.unload_speed > 0.0 ? 0.25 * travel / p.unload_speed : 0.0;
  double seconds = 0.0;
  switch (state.phase) {
    case PunchPhase::relax:
      seconds = std::max(0.0, p.relax_time - elapsed) + travel / p.speed + p.hold_time +
                spring_back + p.release_time;
      break;
    case PunchPhase::load:
      seconds = travel / p.speed + p.hold_time + spring_back + p.release_time;
      break;
    case PunchPhase::hold:
      seconds = std::max(0.0, p.hold_time - elapsed) + p.release_time;
      break;
    case PunchPhase::unload: {
      // The stress fell from about the peak to `stress` in `elapsed`; at that mean rate it
      // reaches zero (where unloading ends) in elapsed × stress / fall. Until it has fallen
      // measurably, the guess of a quarter of the loading travel stands.
      const double fall = state.peak_stress - stress;
      const double guess = 0.25 * std::max(0.0, state.reference_gap - end) / p.unload_speed;
      const double left = fall > 0.05 * state.peak_stress && elapsed > 0.0
                              ? elapsed * std::max(0.0, stress) / fall
                              : std::max(0.0, guess - elapsed);
      seconds = left + p.release_time;
      break;
    }
    case PunchPhase::release:
      seconds = std::max(0.0, p.release_time - elapsed);
      break;
    case PunchPhase::done:
      break;
  }
  return seconds / time_step;
}

double punch_velocity(const PunchProgram& p, PunchState& state, double time, double gap,
                      double stress) {
  const bool servo = p.mode == PunchProgram::Mode::servo;
  if (state.phase == PunchPhase::relax) {
    if (time - state.phase_start < p.relax_time) return 0.0;
    enter(state, PunchPhase::load, time);
  }
  if (state.phase == PunchPhase::load || state.phase == PunchPhase::hold)
    state.peak_stress = std::max(state.peak_stress, stress);
  if (state.phase == PunchPhase::load) {
    if (p.min_gap && gap <= *p.min_gap) {
      enter(state, PunchPhase::hold, time);  // the solid-fraction ceiling
    } else if (servo) {
      if (std::abs(p.target_stress - stress) <= p.servo_tolerance * p.target_stress)
        enter(state, PunchPhase::hold, time);
      else
        return servo_velocity(p, stress);
    } else if (p.target_gap && gap <= *p.target_gap) {
      enter(state, PunchPhase::hold, time);
    } else {
      return -p.speed;
    }
  }
  if (state.phase == PunchPhase::hold) {
    if (time - state.phase_start < p.hold_time) return servo ? servo_velocity(p, stress) : 0.0;
    enter(state, p.unload_speed > 0.0 ? PunchPhase::unload : PunchPhase::done, time);
  }
  if (state.phase == PunchPhase::unload) {
    if (stress > 0.0) return p.unload_speed;
    enter(state, p.release_time > 0.0 ? PunchPhase::release : PunchPhase::done, time);
  }
  if (state.phase == PunchPhase::release) {
    if (time - state.phase_start < p.release_time) return release_velocity(p, state, stress);
    enter(state, PunchPhase::done, time);
  }
  return 0.0;
}

}  // namespace shapepress::scenarios
