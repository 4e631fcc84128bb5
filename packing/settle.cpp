#include "packing/settle.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace shapepress::packing {

std::optional<SphereState> settle(SphereState state, ClumpSet& clumps,
                                  std::vector<Material> materials,
                                  std::vector<Interaction> interactions,
                                  const SettleRequest& request, SettleCheckpoints checkpoints) {
  if (request.friction)  // a denser fill: settle with other friction, press with the real one
    for (Interaction& in : interactions)
      in.sliding_friction = in.rolling_friction = *request.friction;
  EngineSettings settings = request.settings;
  if (settings.gravity == std::array<double, 3>{0.0, 0.0, 0.0}) settings.gravity = {0, 0, -9.81};
  const MaterialTable table(materials, interactions);
  Engine engine = checkpoints.resume
                      ? Engine(std::move(checkpoints.resume->state), checkpoints.resume->box, table,
                               settings, std::move(checkpoints.resume->checkpoint))
                      : Engine(std::move(state), request.box, table, request.walls, settings, {},
                               std::move(clumps));
  const auto steps = static_cast<std::int64_t>(std::ceil(request.settle_time / settings.time_step));
  spdlog::info("settling {} spheres ({} in {} rigid clumps) under gravity for {} steps",
               engine.state().size(),
               engine.clumps().empty() ? 0 : engine.clumps().member_start.back(),
               engine.clumps().size(), steps);
  while (engine.step_index() < steps) {
    engine.step();
    if (checkpoints.after_step && !checkpoints.after_step(engine)) return std::nullopt;
  }
  SphereState settled = engine.state();
  settled.velocity.resize(settled.size());
  settled.angular_velocity.resize(settled.size());
  clumps = engine.clumps();  // at rest too: no velocity, no angular momentum
  clumps.velocity.resize(clumps.size());
  for (RigidRotation& r : clumps.rotation)
    r.body_angular_momentum = {0.0, 0.0, 0.0};
  return settled;
}

double bed_top(const SphereState& state, double floor) {
  double top = floor;
  for (std::size_t i = 0; i < state.size(); ++i)
    top = std::max(top, state.position.z[i] + state.radius[i]);
  return top;
}

}  // namespace shapepress::packing
