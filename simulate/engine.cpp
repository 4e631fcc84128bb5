#include "simulate/engine.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <omp.h>

#include "common/error.hpp"
#include "simulate/verlet.hpp"

namespace shapepress::simulate {

namespace {

// Chunks of the pair loop (engine.hpp, SphereSums): a power of two, so that two or four threads
// share them evenly, of at least 1024 spheres, so that few contacts cross a chunk boundary in a
// bed ordered in space, at most 16.
std::int64_t force_chunk_count(std::size_t spheres) {
  std::int64_t chunks = 1;
  while (chunks < 16 && static_cast<std::int64_t>(spheres) >= 2 * 1024 * chunks)
    chunks *= 2;
  return chunks;
}

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

// α = 1 would cancel every force moving a sphere away from balance, and more would push it on.
void require_local_damping(double alpha) {
  if (!(alpha >= 0.0 && alpha < 1.0))
    throw InputError(fmt::format("local damping must be in [0, 1), got {}", alpha));
}

}  // namespace

Engine::Engine(SphereState state, Box box, MaterialTable materials, std::vector<PlaneWall> walls,
               EngineSettings settings, BondSet bonds, ClumpSet clumps)
    : state_(std::move(state)),
      box_(box),
      materials_(std::move(materials)),
      walls_(std::move(walls)),
      settings_(settings),
      bonds_(std::move(bonds)),
      clumps_(std::move(clumps)) {
  if (!(settings_.time_step > 0.0)) throw InputError("time step must be > 0");
  if (!(settings_.skin >= 0.0)) throw InputError("neighbour skin must be >= 0");
  require_local_damping(settings_.local_damping);
  require_material_pairs();
  enable_particle_stress();
  wall_history_.assign(walls_.size(), std::vector<ContactHistory>(state_.size()));
  force_chunks_ = force_chunk_count(state_.size());
  if (!bonds_.empty()) bonds_.index(state_);
  require_bond_substeps();
  const double half = 0.5 * settings_.time_step;
  if (!clumps_.empty()) {
    index_clumps();
    // Sub-spheres where their bodies put them before the first list build.
    geometry_.resize(4 * state_.size());
    motion_.resize(8 * state_.size());
    place_clump_spheres(clumps_, state_, geometry_.data(), motion_.data(), half, state_.position);
  }
  build_list(true);
  pack_spheres();
  if (!clumps_.empty())  // the packed motion of sub-spheres is the body's
    place_clump_spheres(clumps_, state_, geometry_.data(), motion_.data(), half, state_.position);
  compute_forces(0.0);
  bond_increments_ = true;
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
      time_(checkpoint.time),
      bonds_(std::move(checkpoint.bonds)),
      bond_increments_(true),
      clumps_(std::move(checkpoint.clumps)) {
  require_local_damping(settings_.local_damping);
  require_material_pairs();
  enable_particle_stress();
  force_chunks_ = force_chunk_count(state_.size());
  if (!clumps_.empty()) index_clumps();
  if (particle_stress_on_ && !checkpoint.particle_pressure.empty()) {
    // The next pair loop reads p of the step the checkpoint was taken at: restore it bit for bit.
    if (checkpoint.particle_pressure.size() != pressure_.size())
      throw InputError("checkpoint: particle pressure does not match the spheres");
    pressure_ = std::move(checkpoint.particle_pressure);
  }
  if (!bonds_.empty()) bonds_.index(state_);
  require_bond_substeps();
  if (substeps_bonds()) {
    // The two shares of the force are not recoverable from their sum to the bit.
    if (checkpoint.bond_force.size() != bond_force_.size() ||
        checkpoint.slow_force.size() != slow_force_.size())
      throw InputError(
          "checkpoint: taken without bond sub-steps (run.bond_substeps); resume it with "
          "bond_substeps = 1");
    bond_force_ = std::move(checkpoint.bond_force);
    slow_force_ = std::move(checkpoint.slow_force);
  }
  if (checkpoint.wall_history.size() != walls_.size())
    throw InputError("checkpoint: wall history does not match the walls");
  wall_history_ = std::move(checkpoint.wall_history);
  // "May be touching" for every sphere: the first gather then releases the spring of any wall
  // contact that opens, as the continuous run does (a spring is non-zero only while touching).
  wall_touching_.assign(walls_.size(), std::vector<std::uint8_t>(state_.size(), 1));
  wall_force_ = std::move(checkpoint.wall_force);
  // The continuous run's list and wall candidates: built, without wrapping, from the positions
  // of its last build (and the walls then), so the rebuild test, which measures from there,
  // holds for them exactly as it does in the continuous run. Snapshots without the walls'
  // build positions use the current ones (the test still holds: it needs the list's positions,
  // whichever they are).
  if (checkpoint.build_reference.size() != state_.size())
    throw InputError("checkpoint: build reference does not match the spheres");
  const Vec3Array current = state_.position;
  std::vector<double> current_walls(walls_.size());
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    current_walls[k] = walls_[k].position;
    if (checkpoint.build_wall_position.size() == walls_.size())
      walls_[k].position = checkpoint.build_wall_position[k];
  }
  state_.position = checkpoint.build_reference;
  build_list(false);
  state_.position = current;
  for (std::size_t k = 0; k < walls_.size(); ++k)
    walls_[k].position = current_walls[k];
  PairList touching;
  touching.first = std::move(checkpoint.first);
  touching.second = std::move(checkpoint.second);
  history_ = carry_history(touching, checkpoint.history, pairs_);
  // Slot 0 is the zero result; the others are written by the pair loop before any is read.
  pair_results_.resize(pairs_.size() + 1);
  pair_results_[0] = PairResult{};
  pair_slot_.assign(pairs_.size(), 0);
  if (particle_stress_on_) pair_virial_.assign(2 * pairs_.size(), 0.0);
  pair_touching_ = touching_flags(pairs_, touching);
  energy_reference_ = checkpoint.energy_reference;
  work_in_ = checkpoint.work_in;
  pack_spheres();  // radius, mass and 1/I; step() rewrites the rest
}

void Engine::require_bond_substeps() {
  if (settings_.bond_substeps < 1)
    throw InputError(fmt::format("bond sub-steps must be >= 1, got {}", settings_.bond_substeps));
  if (!substeps_bonds()) return;
  if (settings_.local_damping > 0.0)
    throw InputError("bond sub-steps (run.bond_substeps > 1) do not take local damping");
  if (!clumps_.empty())
    throw InputError("bond sub-steps (run.bond_substeps > 1) do not take rigid clumps");
  bond_force_.assign(6 * state_.size(), 0.0);
  slow_force_.assign(6 * state_.size(), 0.0);
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

void Engine::index_clumps() {
  clumps_.index(state_.size());
  for (std::size_t b = 0; b < bonds_.size(); ++b)
    if (clumps_.clump_of[bonds_.first[b]] >= 0 || clumps_.clump_of[bonds_.second[b]] >= 0)
      throw InputError("bond " + std::to_string(b) + " joins sphere " +
                       std::to_string(bonds_.first[b]) + " and " +
                       std::to_string(bonds_.second[b]) +
                       ", one of them a sub-sphere of a rigid clump (clumps are rigid; bonds "
                       "join the sub-spheres of BMS particles)");
  for (std::size_t c = 0; c < clumps_.size(); ++c)
    if (!(clumps_.mass[c] > 0.0)) throw InputError("clump " + std::to_string(c) + " has no mass");
}

void Engine::enable_particle_stress() {
  bool needed = settings_.particle_stress;
  for (int a = 0; a < materials_.count(); ++a)
    for (int b = 0; b < materials_.count(); ++b)
      needed = needed ||
               (materials_.has_pair(a, b) && normal_law_needs_pair_pressure(materials_.pair(a, b)));
  particle_stress_on_ = needed;
  if (!needed) return;
  pressure_.assign(state_.size(), 0.0);
  wall_tangential_.assign(walls_.size(), std::vector<double>(2 * state_.size(), 0.0));
}

void Engine::build_list(bool wrap) {
  if (wrap) wrap_positions(state_, box_);
  if (wrap && !clumps_.empty()) wrap_clumps(clumps_, state_, box_);
  PairList next;
  if (clumps_.size() == 1 && clumps_.member_start.back() == static_cast<int>(state_.size())) {
    // One clump and nothing else (the plate rig): no pair can exist, and the cell search over
    // thousands of mutually overlapping sub-spheres would cost O(n²) per build.
    next.first_offset.assign(state_.size() + 1, 0);
    next.second_offset.assign(state_.size() + 1, 0);
  } else {
    next = build_pair_list(state_, box_, settings_.skin, clumps_.clump_of);
  }
  // History and touching flags follow their pairs into the new list (a contact that stays
  // closed must not be taken as newly opened and lose its spring): one merge of the two sorted
  // lists, split by first sphere over the threads (a copy, the same for any split).
  std::vector<ContactHistory> history(next.size());
  std::vector<std::uint8_t> touching(next.size(), 0);
  const auto n = static_cast<std::int64_t>(state_.size());
  const bool had_list = pairs_.first_offset.size() == static_cast<std::size_t>(n) + 1;
  const bool split = had_list && next.size() >= static_cast<std::size_t>(parallel_min_pairs);
#pragma omp parallel if (split)
  {
    const std::int64_t team = omp_get_num_threads(), rank = omp_get_thread_num();
    const std::int64_t sphere_begin = n * rank / team, sphere_end = n * (rank + 1) / team;
    const auto key = [](const PairList& l, std::size_t k) {
      return (static_cast<std::int64_t>(l.first[k]) << 32) | l.second[k];
    };
    std::size_t a = had_list ? static_cast<std::size_t>(pairs_.first_offset[sphere_begin]) : 0;
    const std::size_t a_end =
        had_list ? static_cast<std::size_t>(pairs_.first_offset[sphere_end]) : 0;
    for (auto b = static_cast<std::size_t>(next.first_offset[sphere_begin]);
         b < static_cast<std::size_t>(next.first_offset[sphere_end]); ++b) {
      const std::int64_t wanted = key(next, b);
      while (a < a_end && key(pairs_, a) < wanted)
        ++a;
      if (a < a_end && key(pairs_, a) == wanted) {
        history[b] = history_[a];
        touching[b] = pair_touching_[a];
      }
    }
  }
  history_ = std::move(history);
  pair_touching_ = std::move(touching);
  pairs_ = std::move(next);
  // Zero for every pair: the force pass rewrites the touching ones before they are gathered.
  // Slot 0 is the zero result; the others are written by the pair loop before any is read.
  pair_results_.resize(pairs_.size() + 1);
  pair_results_[0] = PairResult{};
  pair_slot_.assign(pairs_.size(), 0);
  if (particle_stress_on_) pair_virial_.assign(2 * pairs_.size(), 0.0);
  index_bonded_pairs();
  index_cross_chunk_pairs();
  find_wall_candidates();
  build_reference_ = state_.position;
  build_wall_position_.resize(walls_.size());
  for (std::size_t k = 0; k < walls_.size(); ++k)
    build_wall_position_[k] = walls_[k].position;
  const double largest_radius =
      state_.size() == 0 ? 0.0 : *std::max_element(state_.radius.begin(), state_.radius.end());
  list_reach_ = 2.0 * largest_radius + settings_.skin;
  ++list_builds_;
}

template <bool damped>
double Engine::kick_drift(const AffineDrift& drift, double dt, const double* const force[6]) {
  SphereState& s = state_;
  const std::int64_t n = static_cast<std::int64_t>(s.size());
  // Half kick and drift, fused with the largest displacement since the last list build and with
  // the packed copies the pair loop reads (pack_spheres(): the predicted end-of-step velocity
  // v(t+dt/2) + dt/2 F(t)/m is the half-step velocity plus the same half kick once more).
  // Radius, mass and 1/I stay in the packed copies from pack_spheres(): every array this loop
  // streams is one more memory stream, and it streams two dozen.
  const VerletArrays arrays{s.velocity.x.data(),
                            s.velocity.y.data(),
                            s.velocity.z.data(),
                            s.angular_velocity.x.data(),
                            s.angular_velocity.y.data(),
                            s.angular_velocity.z.data(),
                            s.position.x.data(),
                            s.position.y.data(),
                            s.position.z.data(),
                            force[0],
                            force[1],
                            force[2],
                            force[3],
                            force[4],
                            force[5],
                            s.inverse_mass.data(),
                            build_reference_.x.data(),
                            build_reference_.y.data(),
                            build_reference_.z.data(),
                            geometry_.data(),
                            motion_.data()};
  const DriftField field{drift.offset, drift.strain, drift.origin};
  const double alpha = damped ? settings_.local_damping : 0.0;
  double largest = 0.0;
  const int threads = n >= parallel_min_spheres ? omp_get_max_threads() : 1;
#pragma omp parallel num_threads(threads) reduction(max : largest)
  {
    const std::int64_t team = omp_get_num_threads(), rank = omp_get_thread_num();
    largest = kick_drift_range(arrays, n * rank / team, n * (rank + 1) / team, dt, alpha, field);
  }
  return largest;
}

void Engine::step() {
  if (substeps_bonds()) {
    step_with_bond_substeps();
    return;
  }
  const double dt = settings_.time_step;
  const double half = 0.5 * dt;
  SphereState& s = state_;
  const std::int64_t n = static_cast<std::int64_t>(s.size());
  for (PlaneWall& w : walls_)
    w.position += w.velocity * dt;
  // Displacements since the last build are measured against the displacement the walls impose
  // on a uniformly strained bed (list_affine_drift()), so a moving punch alone forces no build.
  const AffineDrift drift = list_affine_drift();
  // Local damping is a template argument: its signs and compares, computed with α = 0, cost the
  // bench scene's step a third more instructions (callgrind).
  const double* const force[6] = {s.force.x.data(),  s.force.y.data(),  s.force.z.data(),
                                  s.torque.x.data(), s.torque.y.data(), s.torque.z.data()};
  double largest = settings_.local_damping > 0.0 ? kick_drift<true>(drift, dt, force)
                                                 : kick_drift<false>(drift, dt, force);
  double* geometry = geometry_.data();
  double* motion = motion_.data();
  if (!clumps_.empty()) {
    // Clumps move as bodies; their sub-spheres (no own mass, left alone above) follow.
    advance_clumps(clumps_, dt);
    const double moved = place_clump_spheres(clumps_, s, geometry, motion, half, build_reference_);
    largest = std::max(largest, moved);
  }
  const auto& g = settings_.gravity;
  if (g[0] != 0.0 || g[1] != 0.0 || g[2] != 0.0) {
    double gravity_power = 0.0;  // Σ m g·v at mid-step, for the energy budget only
    for (std::int64_t i = 0; i < n; ++i)
      gravity_power +=
          s.mass[i] * (g[0] * s.velocity.x[i] + g[1] * s.velocity.y[i] + g[2] * s.velocity.z[i]);
    for (std::size_t c = 0; c < clumps_.size(); ++c)
      gravity_power +=
          clumps_.mass[c] * (g[0] * clumps_.velocity.x[c] + g[1] * clumps_.velocity.y[c] +
                             g[2] * clumps_.velocity.z[c]);
    work_in_ += gravity_power * dt;
  }
  time_ += dt;
  ++step_;
  rebuild_list_if_needed(largest, drift);
  compute_forces(half);  // and the second half kick, fused into the gather
  // Work of the walls on the spheres: the spheres' force on a wall is -(the wall's on them).
  for (std::size_t k = 0; k < walls_.size(); ++k)
    work_in_ += -wall_force_[k] * walls_[k].velocity * dt;
  if (settings_.check_every > 0 && step_ % settings_.check_every == 0) check_divergence();
}

void Engine::rebuild_list_if_needed(double largest, const AffineDrift& drift) {
  // The walls' own test (list_affine_drift()): a sphere outside its wall's candidates cannot
  // reach it while e + σ + |strain| (r_max + skin) < skin, σ the wall's offset from the field.
  double wall_slack = 0.0;
  for (std::size_t k = 0; k < walls_.size() && k < build_wall_position_.size(); ++k) {
    const double field = drift.offset + drift.strain * (build_wall_position_[k] - drift.origin);
    wall_slack =
        std::max(wall_slack, std::fabs(walls_[k].position - build_wall_position_[k] - field));
  }
  const double deviation = std::sqrt(largest);
  const double strain_reach = std::fabs(drift.strain) * list_reach_;
  const double wall_reach = std::fabs(drift.strain) * (0.5 * (list_reach_ + settings_.skin));
  if (2.0 * deviation + strain_reach > settings_.skin ||
      (!walls_.empty() && deviation + wall_slack + wall_reach > settings_.skin)) {
    build_list(true);
    const std::int64_t n = static_cast<std::int64_t>(state_.size());
    double* geometry = geometry_.data();
    for (std::int64_t i = 0; i < n; ++i)  // the build wrapped positions into the box
      geometry[4 * i] = state_.position.x[i], geometry[4 * i + 1] = state_.position.y[i];
  }
}

// r-RESPA (Tuckerman, Berne & Martyna 1992) with the bonds as the fast forces: a half kick of
// the slow forces (contacts, walls, gravity) of the step's start, the bonds' velocity Verlet
// over n sub-steps, the slow forces at the step's end and their second half kick. Contacts and
// walls see the positions once per step, so the list and its rebuild test are per step too.
void Engine::step_with_bond_substeps() {
  const double dt = settings_.time_step;
  const int substeps = settings_.bond_substeps;
  const double h = dt / substeps;
  SphereState& s = state_;
  const std::int64_t n = static_cast<std::int64_t>(s.size());
  for (PlaneWall& w : walls_)
    w.position += w.velocity * dt;
  const AffineDrift drift = list_affine_drift();
  const double half = 0.5 * dt;
  const double* slow = slow_force_.data();
  const auto& g = settings_.gravity;
  double gravity_power = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : gravity_power) if (n >= parallel_min_spheres)
  for (std::int64_t i = 0; i < n; ++i) {
    const double im = half * s.inverse_mass[i], ii = half * s.inverse_inertia[i];
    s.velocity.x[i] += slow[i] * im, s.velocity.y[i] += slow[n + i] * im;
    s.velocity.z[i] += slow[2 * n + i] * im;
    s.angular_velocity.x[i] += slow[3 * n + i] * ii;
    s.angular_velocity.y[i] += slow[4 * n + i] * ii;
    s.angular_velocity.z[i] += slow[5 * n + i] * ii;
    gravity_power +=
        s.mass[i] * (g[0] * s.velocity.x[i] + g[1] * s.velocity.y[i] + g[2] * s.velocity.z[i]);
  }
  work_in_ += gravity_power * dt;
  const double* fast = bond_force_.data();
  const double* const fast_force[6] = {fast,         fast + n,     fast + 2 * n,
                                       fast + 3 * n, fast + 4 * n, fast + 5 * n};
  double largest = 0.0;
  for (int k = 0; k < substeps; ++k) {
    largest = kick_drift<false>(drift, h, fast_force);
    bond_substep_forces(h, 0.5 * h);
  }
  // The contacts' dampers read the predicted end-of-step motion: the slow half kick to come as
  // well as the bonds' (kick_drift packed that one).
  double* motion = motion_.data();
#pragma omp parallel for schedule(static) if (n >= parallel_min_spheres)
  for (std::int64_t i = 0; i < n; ++i) {
    const double im = half * s.inverse_mass[i], ii = half * s.inverse_inertia[i];
    double* mi = motion + 8 * i;
    for (int c = 0; c < 3; ++c) {
      mi[c] += slow[c * n + i] * im;
      mi[3 + c] += slow[(3 + c) * n + i] * ii;
    }
  }
  time_ += dt;
  ++step_;
  rebuild_list_if_needed(largest, drift);
  pair_forces();
  slow_forces(half);
  for (std::size_t k = 0; k < walls_.size(); ++k)
    work_in_ += -wall_force_[k] * walls_[k].velocity * dt;
  if (settings_.check_every > 0 && step_ % settings_.check_every == 0) check_divergence();
}

void Engine::bond_substep_forces(double dt, double kick) {
  compute_bond_forces(bonds_, state_, motion_.data(), box_, dt, !bond_increments_);
  SphereState& s = state_;
  const std::int64_t n = static_cast<std::int64_t>(s.size());
  double* fast = bond_force_.data();
  // Each sphere sums its own bonds in fixed order: the same bits on any number of threads.
  const BondGather bond_gather(bonds_);
#pragma omp parallel for schedule(static) if (n >= parallel_min_spheres)
  for (std::int64_t i = 0; i < n; ++i) {
    double f[3] = {0.0, 0.0, 0.0}, t[3] = {0.0, 0.0, 0.0};
    gather_bond_forces(bond_gather, i, f, t);
    for (int c = 0; c < 3; ++c)
      fast[c * n + i] = f[c], fast[(3 + c) * n + i] = t[c];
    if (kick > 0.0) {
      const double im = kick * s.inverse_mass[i], ii = kick * s.inverse_inertia[i];
      s.velocity.x[i] += f[0] * im, s.velocity.y[i] += f[1] * im, s.velocity.z[i] += f[2] * im;
      s.angular_velocity.x[i] += t[0] * ii, s.angular_velocity.y[i] += t[1] * ii;
      s.angular_velocity.z[i] += t[2] * ii;
    }
  }
}

void Engine::slow_forces(double kick) {
  gather_forces(kick, false);  // the bonds have their own kicks
  SphereState& s = state_;
  const std::int64_t n = static_cast<std::int64_t>(s.size());
  double* slow = slow_force_.data();
  const double* fast = bond_force_.data();
  double* const total[6] = {s.force.x.data(),  s.force.y.data(),  s.force.z.data(),
                            s.torque.x.data(), s.torque.y.data(), s.torque.z.data()};
  // The state's force is the whole force, as in a single-rate run (snapshots, imbalance).
  for (int c = 0; c < 6; ++c)
    for (std::int64_t i = 0; i < n; ++i) {
      slow[c * n + i] = total[c][i];
      total[c][i] += fast[c * n + i];
    }
}

// The rebuild test. A pair (i, j) missing from the list was at least ri + rj + skin apart at
// the build. For any displacement field a(x) with Lipschitz constant Λ and e = max |u - a(x_build)|
// over the spheres, |ui - uj| <= 2e + Λ dij, so such a pair cannot touch while
// 2e + Λ (2 r_max + skin) < skin: the list stays exact for any choice of a. a = 0 is the usual
// "half the skin" test; here a is the uniform strain in z between the bottom plate and the punch
// since the build, so a moving punch alone does not force builds (half as many in the engine
// bench, tests/bench/hertz-compaction).
Engine::AffineDrift Engine::list_affine_drift() const {
  AffineDrift drift;
  // Clump sub-spheres report their plain displacement (place_clump_spheres): keep a = 0.
  if (!clumps_.empty() || build_wall_position_.size() != walls_.size()) return drift;
  int bottom = -1, top = -1;  // -2: more than one
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    if (walls_[k].facing > 0) bottom = bottom == -1 ? static_cast<int>(k) : -2;
    if (walls_[k].facing < 0) top = top == -1 ? static_cast<int>(k) : -2;
  }
  if (bottom < 0 || top < 0) return drift;
  const double bottom0 = build_wall_position_[bottom], top0 = build_wall_position_[top];
  if (!(top0 > bottom0)) return drift;
  const double bottom_moved = walls_[bottom].position - bottom0;
  const double top_moved = walls_[top].position - top0;
  drift.offset = bottom_moved;
  drift.origin = bottom0;
  drift.strain = (top_moved - bottom_moved) / (top0 - bottom0);
  return drift;
}

void Engine::compute_forces(double kick) {
  if (substeps_bonds()) {
    pair_forces();
    bond_substep_forces(settings_.time_step / settings_.bond_substeps, kick);
    slow_forces(kick);
    return;
  }
  if (!clumps_.empty()) share_clump_damping_mass();
  pair_forces();
  if (!bonds_.empty())
    compute_bond_forces(bonds_, state_, motion_.data(), box_, settings_.time_step,
                        !bond_increments_);
  gather_forces(kick);
  if (!clumps_.empty())
    gather_clump_forces(clumps_, state_, motion_.data(), settings_.gravity, kick);
}

void Engine::index_cross_chunk_pairs() {
  const std::int64_t n = static_cast<std::int64_t>(state_.size());
  cross_second_end_.resize(static_cast<std::size_t>(n));
  for (std::int64_t chunk = 0; chunk < force_chunks_; ++chunk) {
    const std::int64_t begin = chunk_start(chunk), end = chunk_start(chunk + 1);
    for (std::int64_t i = begin; i < end; ++i) {
      std::int32_t e = pairs_.second_offset[i];
      while (e < pairs_.second_offset[i + 1] && pairs_.first[pairs_.second_pairs[e]] < begin)
        ++e;
      cross_second_end_[i] = e;
    }
  }
}

void Engine::find_wall_candidates() {
  const std::size_t n = state_.size();
  wall_candidates_.resize(walls_.size());
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    const PlaneWall& w = walls_[k];
    std::vector<std::int32_t>& near = wall_candidates_[k];
    near.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const double gap = w.facing * (state_.position.z[i] - w.position);
      if (gap < state_.radius[i] + settings_.skin) {
        near.push_back(static_cast<std::int32_t>(i));
      } else if (k < wall_touching_.size() && i < wall_touching_[k].size() &&
                 wall_touching_[k][i]) {
        release_wall_contact(k, i);  // opened since the last evaluation, as the gather would
      }
    }
  }
}

void Engine::release_wall_contact(std::size_t wall, std::size_t sphere) {
  wall_history_[wall][sphere] = ContactHistory{};
  wall_touching_[wall][sphere] = 0;
  // (a restarted engine has no per-sphere wall forces until its first gather)
  if (wall < wall_force_per_sphere_.size() && sphere < wall_force_per_sphere_[wall].size())
    wall_force_per_sphere_[wall][sphere] = 0.0;
}

void Engine::index_bonded_pairs() {
  pair_bond_.clear();
  if (bonds_.empty() || bonds_.contact_when_bonded) return;
  // Both lists are sorted by (first, second): one merge.
  pair_bond_.assign(pairs_.size(), -1);
  std::size_t b = 0;
  const auto key = [](std::int32_t a, std::int32_t c) {
    return (static_cast<std::int64_t>(a) << 32) | c;
  };
  for (std::size_t p = 0; p < pairs_.size() && b < bonds_.size(); ++p) {
    const std::int64_t k = key(pairs_.first[p], pairs_.second[p]);
    while (b < bonds_.size() && key(bonds_.first[b], bonds_.second[b]) < k)
      ++b;
    if (b < bonds_.size() && key(bonds_.first[b], bonds_.second[b]) == k)
      pair_bond_[p] = static_cast<std::int32_t>(b);
  }
}

}  // namespace shapepress::simulate
