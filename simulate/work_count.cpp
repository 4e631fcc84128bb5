#include "simulate/work_count.hpp"

#include <algorithm>
#include <limits>

#include "simulate/engine.hpp"

namespace shapepress::simulate {

CheckpointState& add_work_count(CheckpointState& state, const WorkCount& work) {
  for (const auto& [key, field] : work_count_fields)
    state.whole(key, work.*field);
  return state;
}

WorkCount read_work_count(const CheckpointFields& state) {
  WorkCount work;
  for (const auto& [key, field] : work_count_fields)
    work.*field = state.whole(key, 0, std::numeric_limits<std::int64_t>::max());
  return work;
}

WorkCount step_work(const Engine& engine) {
  WorkCount w;
  w.sphere_steps = static_cast<std::int64_t>(engine.state().size());
  w.contact_steps = engine.sphere_contacts() + engine.wall_contacts();
  // Unbreakable bonds stay intact: no pass over them each step.
  const BondSet& bonds = engine.bonds();
  const std::int64_t intact =
      bonds.breakable ? bonds.intact_count() : static_cast<std::int64_t>(bonds.size());
  w.bond_steps = intact * std::max(1, engine.settings().bond_substeps);
  return w;
}

}  // namespace shapepress::simulate
