#include "simulate/engine.hpp"

#include <cmath>
#include <string>

#include "common/error.hpp"

namespace shapepress::simulate {

namespace {

// 1 for the pairs of `list` that appear in `touching` (both sorted by (first, second)).
std::vector<std::uint8_t> touching_flags(const PairList& list, const PairList& touching) {
  std::vector<std::uint8_t> flags(list.size(), 0);
  std::size_t a = 0;
  for (std::size_t b = 0; b < list.size() && a < touching.size(); ++b) {
    const auto key = [](const PairList& l, std::size_t k) {
      return (static_cast<std::int64_t>(l.first[k]) << 32) | l.second[k];
    };
    while (a < touching.size() && key(touching, a) < key(list, b))
      ++a;
    if (a < touching.size() && key(touching, a) == key(list, b)) flags[b] = 1;
  }
  return flags;
}

}  // namespace

Engine::Engine(SphereState state, Box box, MaterialTable materials, std::vector<PlaneWall> walls,
               EngineSettings settings)
    : state_(std::move(state)),
      box_(box),
      materials_(std::move(materials)),
      walls_(std::move(walls)),
      settings_(settings) {
  if (!(settings_.time_step > 0.0)) throw InputError("time step must be > 0");
  if (!(settings_.skin >= 0.0)) throw InputError("neighbour skin must be >= 0");
  require_material_pairs();
  wall_history_.assign(walls_.size(), std::vector<ContactHistory>(state_.size()));
  build_list(true);
  compute_forces();
  energy_reference_ = energy().kinetic + energy().elastic;
}

Engine::Engine(SphereState state, Box box, MaterialTable materials, EngineSettings settings,
               EngineCheckpoint checkpoint)
    : state_(std::move(state)),
      box_(box),
      materials_(std::move(materials)),
      walls_(std::move(checkpoint.walls)),
      settings_(settings),
      step_(checkpoint.step),
      time_(checkpoint.time) {
  require_material_pairs();
  if (checkpoint.wall_history.size() != walls_.size())
    throw InputError("checkpoint: wall history does not match the walls");
  wall_history_ = std::move(checkpoint.wall_history);
  wall_force_ = std::move(checkpoint.wall_force);
  // Rebuild without wrapping: the continuous run wraps only at its own builds, and the shifts
  // come from the current (possibly unwrapped) positions, so the same pairs see the same
  // geometry. Non-touching pairs add exact zeros, so the list's extra pairs change no sum.
  build_list(false);
  build_reference_ = std::move(checkpoint.build_reference);
  PairList touching;
  touching.first = std::move(checkpoint.first);
  touching.second = std::move(checkpoint.second);
  history_ = carry_history(touching, checkpoint.history, pairs_);
  pair_results_.assign(pairs_.size(), PairResult{});
  pair_touching_ = touching_flags(pairs_, touching);
  energy_reference_ = checkpoint.energy_reference;
  work_in_ = checkpoint.work_in;
}

void Engine::require_material_pairs() const {
  std::vector<char> used(static_cast<std::size_t>(materials_.count()), 0);
  for (std::int32_t m : state_.material) {
    if (m < 0 || m >= materials_.count())
      throw InputError("sphere material index " + std::to_string(m) + " is not a material");
    used[m] = 1;
  }
  for (int a = 0; a < materials_.count(); ++a) {
    if (!used[a]) continue;
    for (int b = a; b < materials_.count() && state_.size() > 1; ++b)
      if (used[b]) materials_.require_pair(a, b);
    for (const PlaneWall& w : walls_)
      materials_.require_pair(a, w.material);
  }
}

void Engine::build_list(bool wrap) {
  if (wrap) wrap_positions(state_, box_);
  PairList next = build_pair_list(state_, box_, settings_.skin);
  history_ = carry_history(pairs_, history_, next);
  // Touching flags follow the pairs like the history does (a contact that stays closed must
  // not be taken as newly opened and lose its spring).
  PairList was_touching;
  for (std::size_t p = 0; p < pairs_.size(); ++p)
    if (pair_touching_[p]) {
      was_touching.first.push_back(pairs_.first[p]);
      was_touching.second.push_back(pairs_.second[p]);
    }
  pair_touching_ = touching_flags(next, was_touching);
  pairs_ = std::move(next);
  pair_results_.resize(pairs_.size());
  build_reference_ = state_.position;
  ++list_builds_;
}

void Engine::step() {
  const double dt = settings_.time_step;
  const double half = 0.5 * dt;
  SphereState& s = state_;
  const std::size_t n = s.size();
  const auto& g = settings_.gravity;
  double gravity_power = 0.0;  // Σ m g·v at mid-step, diagnostics only
#pragma omp parallel for schedule(static) reduction(+ : gravity_power) \
    if (static_cast<std::int64_t>(n) >= parallel_min_spheres)
  for (std::size_t i = 0; i < n; ++i) {
    const double im = s.inverse_mass[i], ii = s.inverse_inertia[i];
    s.velocity.x[i] += half * s.force.x[i] * im;
    s.velocity.y[i] += half * s.force.y[i] * im;
    s.velocity.z[i] += half * s.force.z[i] * im;
    s.angular_velocity.x[i] += half * s.torque.x[i] * ii;
    s.angular_velocity.y[i] += half * s.torque.y[i] * ii;
    s.angular_velocity.z[i] += half * s.torque.z[i] * ii;
    s.position.x[i] += dt * s.velocity.x[i];
    s.position.y[i] += dt * s.velocity.y[i];
    s.position.z[i] += dt * s.velocity.z[i];
    gravity_power +=
        s.mass[i] * (g[0] * s.velocity.x[i] + g[1] * s.velocity.y[i] + g[2] * s.velocity.z[i]);
  }
  for (PlaneWall& w : walls_)
    w.position += w.velocity * dt;
  time_ += dt;
  ++step_;
  const double half_skin = 0.5 * settings_.skin;
  if (max_displacement_squared(s.position, build_reference_) > half_skin * half_skin)
    build_list(true);
  compute_forces();
#pragma omp parallel for schedule(static) if (static_cast <std::int64_t>(n) >= parallel_min_spheres)
  for (std::size_t i = 0; i < n; ++i) {
    const double im = s.inverse_mass[i], ii = s.inverse_inertia[i];
    s.velocity.x[i] += half * s.force.x[i] * im;
    s.velocity.y[i] += half * s.force.y[i] * im;
    s.velocity.z[i] += half * s.force.z[i] * im;
    s.angular_velocity.x[i] += half * s.torque.x[i] * ii;
    s.angular_velocity.y[i] += half * s.torque.y[i] * ii;
    s.angular_velocity.z[i] += half * s.torque.z[i] * ii;
  }
  // Work of the walls on the spheres: the spheres' force on a wall is -(the wall's on them).
  for (std::size_t k = 0; k < walls_.size(); ++k)
    work_in_ += -wall_force_[k] * walls_[k].velocity * dt;
  work_in_ += gravity_power * dt;
  if (settings_.check_every > 0 && step_ % settings_.check_every == 0) check_divergence();
}

void Engine::compute_forces() {
  pair_forces();
  gather_forces();
}

}  // namespace shapepress::simulate
