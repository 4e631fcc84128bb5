#pragma once
// What a run's stepping cost, counted instead of timed: per step, the spheres the integrator
// moved, the touching contacts the force loop evaluated and the bonds it evaluated (once per
// bond sub-step). The counts follow from the engine's state alone, which is the same bits on any
// number of threads, so they are too: a cost that a loaded machine cannot change (`advise` picks
// by it; CPU seconds are reported beside it).
#include <cstdint>
#include <string_view>
#include <utility>

#include "common/checkpoint.hpp"

namespace shapepress::simulate {

class Engine;

struct WorkCount {
  std::int64_t sphere_steps = 0;   // Σ over steps of the (sub-)spheres integrated
  std::int64_t contact_steps = 0;  // Σ of the touching sphere–sphere and sphere–wall contacts
  std::int64_t bond_steps = 0;     // Σ of the intact bonds × bond sub-steps
  // The cost: the three sums unweighted, each a unit of work of comparable size (one kick and
  // drift, one contact law, one bond law).
  std::int64_t total() const { return sphere_steps + contact_steps + bond_steps; }
  WorkCount& operator+=(const WorkCount& other) {
    sphere_steps += other.sphere_steps;
    contact_steps += other.contact_steps;
    bond_steps += other.bond_steps;
    return *this;
  }
  friend bool operator==(const WorkCount&, const WorkCount&) = default;
};

// The counts by the keys that run.json facts and checkpoints give them.
inline constexpr std::pair<std::string_view, std::int64_t WorkCount::*> work_count_fields[] = {
    {"sphere_steps", &WorkCount::sphere_steps},
    {"contact_steps", &WorkCount::contact_steps},
    {"bond_steps", &WorkCount::bond_steps}};

// A count into a checkpoint's state, and back (an InputError naming a missing or negative key).
CheckpointState& add_work_count(CheckpointState& state, const WorkCount& work);
WorkCount read_work_count(const CheckpointFields& state);

// The work of the step `engine` has just taken: its spheres, the contacts of its last force
// evaluation, its intact bonds (the bonds that broke in the step are not counted) times the
// bond sub-steps when it sub-steps them.
WorkCount step_work(const Engine& engine);

}  // namespace shapepress::simulate
