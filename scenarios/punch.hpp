#pragma once
// The punch program: what the top wall does over a compaction (docs/stages.md, "compact").
//   relax:        optionally, the punch stays put for `relax_time` while the bed settles under
//                 the compaction's contact law (a packing made with a softer law starts with
//                 overlaps that are a pre-stress under a stiffer one);
//   displacement: move down at `speed` to a target gap (or strain, or solid fraction), hold,
//                 then move up at `unload_speed` until the punch force vanishes;
//   servo:        move at up to `max_speed` so the punch stress reaches `target_stress`,
//                 hold it for `hold_time`, then unload the same way;
//   release:      optionally, after unloading the punch follows the bed's spring-back for
//                 `release_time`, holding a near-zero stress (`release_stress_fraction` of the
//                 peak), so the elastic recovery is read from a bed at rest, not from the first
//                 step without force.
// Without a target the load phase lasts until the run's step limit (the reference scene).
#include <optional>
#include <string>
#include "scenarios/namespaces.hpp"

#include "simulate/snapshot.hpp"

namespace shapepress::scenarios {

// The numbers are punch.csv's and the checkpoints'; release and relax came later, so they
// follow done (the order of the phases is relax, load, hold, unload, release, done).
enum class PunchPhase { load = 0, hold = 1, unload = 2, done = 3, release = 4, relax = 5 };
std::string phase_name(PunchPhase phase);

struct PunchProgram {
  enum class Mode { displacement, servo };
  Mode mode = Mode::displacement;
  double speed = 0.0;                     // m/s, downwards, > 0
  std::optional<double> target_gap;       // m (displacement mode)
  double hold_time = 0.0;                 // s
  double unload_speed = 0.0;              // m/s upwards; 0: end after the hold
  double target_stress = 0.0;             // Pa (servo)
  double max_speed = 0.0;                 // m/s (servo)
  double servo_band = 0.05;               // full speed when the stress error exceeds this fraction
  double servo_tolerance = 0.01;          // "reached" within this fraction of the target
  double relax_time = 0.0;                // s, the punch still before loading (0: none)
  double release_time = 0.0;              // s, the punch at near-zero stress after unloading
  double release_stress_fraction = 0.01;  // the stress held then, of the peak
  // The gap at which the solid fraction reaches the ceiling (compact's [punch]
  // max_solid_fraction): loading stops there in either mode, whatever the target.
  std::optional<double> min_gap;
};

// The controller's state, saved in snapshots so a restart continues the same program.
struct PunchState {
  PunchPhase phase = PunchPhase::load;
  double phase_start = 0.0;    // s
  double reference_gap = 0.0;  // m, H0 of the strain (the gap when the run began)
  double work = 0.0;           // J, done by the punch on the bed so far
  double peak_stress = 0.0;    // Pa, the largest punch stress of loading and hold
};

// Steps a displacement run still has to take from `state` at `time`, `gap` and punch `stress`,
// for a progress line's ETA: the relaxation left, the travel to the target (or the ceiling) at
// `speed`, the hold, the spring-back and the release. How far a bed springs back is known only
// once it does: before unloading it is guessed as a quarter of the loading travel at
// `unload_speed`; while unloading, the stress's fall so far is extrapolated to zero at its mean
// rate. 0 for a program without a target gap (servo; a load to the run's step limit).
double remaining_steps_estimate(const PunchProgram& p, const PunchState& state, double time,
                                double gap, double stress, double time_step);

// The controller's state as the snapshot's named numbers, and back (InputError when the
// snapshot lacks one).
ScenarioState punch_scenario_state(const PunchState& state);
PunchState punch_state_from(const ScenarioState& scenario);

// The punch velocity (m/s along z, < 0 moving down) for the next step, from the current time,
// gap and punch stress (> 0 compressive); advances the phase.
double punch_velocity(const PunchProgram& program, PunchState& state, double time, double gap,
                      double stress);

}  // namespace shapepress::scenarios
