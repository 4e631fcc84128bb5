#include "simulate/work_count.hpp"

#include <algorithm>

#include "simulate/engine.hpp"

namespace shapepress::simulate {

WorkCount step_work(const Engine& engine) {
  WorkCount w;
  w.sphere_steps = static_cast<std::int64_t>(engine.state().size());
  w.contact_steps = engine.sphere_contacts() + engine.wall_contacts();
  const std::int64_t intact = engine.bonds().empty() ? 0 : engine.bonds().intact_count();
  w.bond_steps = intact * std::max(1, engine.settings().bond_substeps);
  return w;
}

}  // namespace shapepress::simulate
