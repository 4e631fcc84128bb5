// The force evaluation, the engine's hot path: one pass over the pair list computing each
// contact once and adding it to both spheres' sums (a partner in another thread's chunk reads it
// from pair_results_ instead), then one pass over the spheres gathering those sums, the
// cross-chunk contacts, the bonds, the wall contacts and gravity. Both passes are written out long
// on purpose: splitting them into helpers that pass arrays around costs measurable speed. The
// Love–Weber pressure (engine.hpp) and the normal law are template switches: the Hertz path
// compiles without the other laws' branches.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <type_traits>
#include <utility>

#include "simulate/contact_block.hpp"
#include "simulate/engine.hpp"

namespace shapepress::simulate {

// Packed per-sphere copies for the pair loop, one cache line per sphere end instead of one per
// array: geometry (x, y, z, r) and motion (velocities at the end of the step, predicted from the
// half-step ones with the last force, v + dt/2 F/m, then m and 1/I). Predicting lets the damping
// act on the same instant as the elastic force: with half-step velocities the restitution error
// is first order in dt (4 % at e = 0.35 and 0.2 Rayleigh times, 2 % with the prediction;
// validation/simulate). step() fills them in its kick–drift loop; this is for the first
// evaluation.
void Engine::pack_spheres() {
  const SphereState& s = state_;
  const std::int64_t n = static_cast<std::int64_t>(s.size());
  const double half_dt = 0.5 * settings_.time_step;
  geometry_.resize(4 * static_cast<std::size_t>(n));
  motion_.resize(8 * static_cast<std::size_t>(n));
  double* __restrict geometry = geometry_.data();
  double* __restrict motion = motion_.data();
  sphere_material_ = n > 0 ? s.material[0] : -1;
  for (std::int64_t i = 1; i < n && sphere_material_ >= 0; ++i)
    if (s.material[i] != sphere_material_) sphere_material_ = -1;
#pragma omp parallel for schedule(static) if (n >= parallel_min_spheres)
  for (std::int64_t i = 0; i < n; ++i) {
    geometry[4 * i] = s.position.x[i];
    geometry[4 * i + 1] = s.position.y[i];
    geometry[4 * i + 2] = s.position.z[i];
    geometry[4 * i + 3] = s.radius[i];
    const double im = half_dt * s.inverse_mass[i], ii = half_dt * s.inverse_inertia[i];
    motion[8 * i] = s.velocity.x[i] + im * s.force.x[i];
    motion[8 * i + 1] = s.velocity.y[i] + im * s.force.y[i];
    motion[8 * i + 2] = s.velocity.z[i] + im * s.force.z[i];
    motion[8 * i + 3] = s.angular_velocity.x[i] + ii * s.torque.x[i];
    motion[8 * i + 4] = s.angular_velocity.y[i] + ii * s.torque.y[i];
    motion[8 * i + 5] = s.angular_velocity.z[i] + ii * s.torque.z[i];
    motion[8 * i + 6] = s.mass[i];
    motion[8 * i + 7] = s.inverse_inertia[i];
  }
}

namespace {

// f.template operator()<Law>() with the scene's one normal law, or AnyNormalLaw when its pairs
// mix laws: the law is chosen here, once per force evaluation, not per contact.
template <class F>
void with_scene_law(const MaterialTable& materials, F&& f) {
  const std::optional<std::size_t> single = materials.single_law();
  if (!single) return f.template operator()<AnyNormalLaw>();
  with_normal_law(*single, std::forward<F>(f));
}

// Σ l·f of sphere i's intact bonds with the sign of a contact's rc Fn (> 0 compressive): the
// bond force acts at the bond centre, which divides the centre distance d = x_second - x_first
// as ri : rj, so both ends give share × (d · F), F the force on `second` (a broken bond's is 0).
// The bond loop leaves d · F in the bond's result.
double bond_arm_force(const BondSet& bonds, std::int64_t i) {
  double sum = 0.0;
  for (std::int32_t e = bonds.gather_offset[i]; e < bonds.gather_offset[i + 1]; ++e) {
    const std::int32_t entry = bonds.gather[e];
    const std::size_t b = static_cast<std::size_t>(entry >> 1);
    sum += bonds.constants.arm[static_cast<std::size_t>(entry & 1)][b] *
           bonds.result.separation_force[b];
  }
  return sum;
}

}  // namespace

void Engine::pair_forces() {
  with_scene_law(materials_, [&]<class Law>() {
    if (particle_stress_on_)
      pair_forces_with<true, Law>();
    else
      pair_forces_with<false, Law>();
  });
}

void Engine::gather_forces(double kick, bool with_bonds) {
  // Local damping is a template argument: a test per sphere made the undamped gather 7 % longer
  // (callgrind, bench scene).
  const bool damped = settings_.local_damping > 0.0;
  with_scene_law(materials_, [&]<class Law>() {
    if (particle_stress_on_)
      damped ? gather_forces_with<true, true, Law>(kick, with_bonds)
             : gather_forces_with<true, false, Law>(kick, with_bonds);
    else
      damped ? gather_forces_with<false, true, Law>(kick, with_bonds)
             : gather_forces_with<false, false, Law>(kick, with_bonds);
  });
}

template <bool stress_on, class Law>
void Engine::pair_forces_with() {
  const SphereState& s = state_;
  const std::int64_t count = static_cast<std::int64_t>(pairs_.size());
  const double dt = settings_.time_step;
  const double* __restrict geometry = geometry_.data();
  const double* __restrict motion = motion_.data();
  touching_index_.resize(static_cast<std::size_t>(count));
  std::int32_t* __restrict selected = touching_index_.data();
  std::int32_t* __restrict slot = pair_slot_.data();
  std::uint8_t* __restrict was_touching = pair_touching_.data();
  const std::int32_t* __restrict first = pairs_.first.data();
  const std::int32_t* __restrict second = pairs_.second.data();
  const std::uint8_t* __restrict image = pairs_.image.data();
  const double* __restrict image_shift = pairs_.image_shift.data();
  // Love–Weber: p of the last gather in; Fn and δ/2 of each touching pair out.
  const double* __restrict pressure = stress_on ? pressure_.data() : nullptr;
  double* __restrict virial = stress_on ? pair_virial_.data() : nullptr;
  std::int64_t touching = 0;
  // Bonded sub-spheres skip the contact law while their bond holds when the bond model says so
  // (BondSet::contact_when_bonded); pair_bond_ is empty otherwise.
  const std::int32_t* bond_of_pair = pair_bond_.empty() ? nullptr : pair_bond_.data();
  const std::uint8_t* bond_intact = bonds_.intact.data();
  const std::int32_t* __restrict first_offset = pairs_.first_offset.data();
  const std::int64_t spheres = static_cast<std::int64_t>(s.size());
  sphere_sums_.resize(static_cast<std::size_t>(spheres));
  SphereSums* __restrict sums = sphere_sums_.data();
  PairResult* __restrict results = pair_results_.data();
  // Spheres of one material have one pair constant: the Hertz law then runs over blocks of
  // contacts, vectorized (contact_block.hpp).
  [[maybe_unused]] const PairConstants* block_pair =
      sphere_material_ >= 0 ? &materials_.pair(sphere_material_, sphere_material_) : nullptr;
  [[maybe_unused]] const bool body_radii = block_pair != nullptr && block_pair->body_contact_radius;
  const std::int32_t* __restrict body = s.body.data();
  const double* __restrict body_radius = s.body_radius.data();
  const double* __restrict radius = s.radius.data();
  const int threads = count >= parallel_min_pairs ? omp_get_max_threads() : 1;
#pragma omp parallel num_threads(threads) reduction(+ : touching)
  {
    [[maybe_unused]] ContactBlock block;
    // Each thread takes whole chunks of spheres (force_chunks_, fixed by the sphere count):
    // the order of every sum is then the same for any number of threads.
    const std::int64_t team = omp_get_num_threads(), rank = omp_get_thread_num();
    for (std::int64_t chunk = thread_chunk_start(rank, team);
         chunk < thread_chunk_start(rank + 1, team); ++chunk) {
      const std::int64_t sphere_begin = chunk_start(chunk), sphere_end = chunk_start(chunk + 1);
      // Two passes over the chunk's pairs. The first selects the touching pairs without a
      // branch on the outcome (about half the list pairs touch in a dense bed, so a branch
      // there mispredicts all the time) and releases the contacts that just opened; the second
      // computes the law for the selected pairs only.
      const std::int64_t begin = first_offset[sphere_begin];
      std::int64_t k = begin;
      for (std::int64_t p = begin; p < first_offset[sphere_end]; ++p) {
        const double* gi = geometry + 4 * first[p];
        const double* gj = geometry + 4 * second[p];
        const double* shift = image_shift + 2 * image[p];
        const double dx = gj[0] - gi[0] + shift[0];
        const double dy = gj[1] - gi[1] + shift[1];
        const double dz = gj[2] - gi[2];
        const double reach = gi[3] + gj[3];
        const std::uint8_t held =
            bond_of_pair != nullptr && bond_of_pair[p] >= 0 && bond_intact[bond_of_pair[p]];
        const std::uint8_t now = (dx * dx + dy * dy + dz * dz < reach * reach) & (held ^ 1);
        if (was_touching[p] & (now ^ 1)) {  // the contact just opened: its spring is released
          history_[p] = ContactHistory{};
          if constexpr (stress_on) virial[2 * p] = virial[2 * p + 1] = 0.0;
        }
        was_touching[p] = now;
        // A touching pair's result slot is 1 + its rank among the touching pairs; the others
        // point at slot 0, which holds zeros.
        slot[p] = static_cast<std::int32_t>(now) * static_cast<std::int32_t>(k + 1);
        selected[k] = static_cast<std::int32_t>(p);
        k += now;
      }
      touching += k - begin;
      for (std::int64_t i = sphere_begin; i < sphere_end; ++i)
        sums[i] = SphereSums{};
      // Touching pair q's force on second and torques to their spheres, added to both ends here
      // in list order: a sphere of the chunk receives its partners below it (i second) in
      // increasing order, then those above (i first). A partner in a later chunk belongs to
      // another thread: it reads the result in the gather instead. With Love–Weber each end also
      // sums its rc Fn (`arm_first`, `arm_second`), and every touching pair keeps its result for
      // the stress tensor on demand (diagnostics.cpp).
      const auto deliver = [&](std::int64_t q, int i, int j, const double force[3],
                               const double torque_first[3], const double torque_second[3],
                               double arm_first, double arm_second) __attribute__((always_inline)) {
        SphereSums& a = sums[i];
        a.force[0] -= force[0], a.force[1] -= force[1], a.force[2] -= force[2];
        a.torque[0] += torque_first[0], a.torque[1] += torque_first[1];
        a.torque[2] += torque_first[2];
        if constexpr (stress_on) a.arm_force += arm_first;
        const bool same_chunk = j < sphere_end;
        if (same_chunk) {
          SphereSums& b = sums[j];
          b.force[0] += force[0], b.force[1] += force[1], b.force[2] += force[2];
          b.torque[0] += torque_second[0], b.torque[1] += torque_second[1];
          b.torque[2] += torque_second[2];
          if constexpr (stress_on) b.arm_force += arm_second;
        }
        if (!stress_on && same_chunk) return;
        PairResult& out = results[q + 1];
        for (int axis = 0; axis < 3; ++axis) {
          out.force[axis] = force[axis];
          out.torque_first[axis] = torque_first[axis];
          out.torque_second[axis] = torque_second[axis];
        }
      };
      // The multi-contact law reads P_ij and keeps Love–Weber's Fn and δ/2 (stress_on); Hertz's
      // block runs without them, as the scalar loop would.
      constexpr bool block_law =
          (!stress_on && std::is_same_v<Law, HertzLaw>) || std::is_same_v<Law, MulticontactLaw>;
      if constexpr (block_law) {
        if (block_pair != nullptr) {
          // The law vectorized over blocks of touching pairs (contact_block.hpp): copied in,
          // computed, then delivered in list order; the same bits as the loop below.
          for (std::int64_t q0 = begin; q0 < k; q0 += ContactBlock::capacity) {
            const int lanes =
                static_cast<int>(std::min<std::int64_t>(ContactBlock::capacity, k - q0));
            for (int l = 0; l < lanes; ++l) {
              const std::int64_t p = selected[q0 + l];
              const double* gi = geometry + 4 * first[p];
              const double* gj = geometry + 4 * second[p];
              const double* shift = image_shift + 2 * image[p];
              block.separation[0][l] = gj[0] - gi[0] + shift[0];
              block.separation[1][l] = gj[1] - gi[1] + shift[1];
              block.separation[2][l] = gj[2] - gi[2];
              block.radius_first[l] = gi[3];
              block.radius_second[l] = gj[3];
              block.body_radius[l] =
                  body_contact_radius(body_radii, body, body_radius, radius, first[p], second[p]);
              const double* mi = motion + 8 * first[p];
              const double* mj = motion + 8 * second[p];
              for (int axis = 0; axis < 3; ++axis) {
                block.velocity_first[axis][l] = mi[axis];
                block.spin_first[axis][l] = mi[3 + axis];
                block.velocity_second[axis][l] = mj[axis];
                block.spin_second[axis][l] = mj[3 + axis];
                block.spring[axis][l] = history_[p].tangential[axis];
              }
              block.mass_first[l] = mi[6];
              block.mass_second[l] = mj[6];
              block.inverse_inertia_first[l] = mi[7];
              block.inverse_inertia_second[l] = mj[7];
              if constexpr (std::is_same_v<Law, MulticontactLaw>) {
                block.pair_pressure[l] =
                    stress_on ? 0.5 * (pressure[first[p]] + pressure[second[p]]) : 0.0;
                block.plastic_force[l] = plastic_force(history_[p]);
              }
            }
            if constexpr (std::is_same_v<Law, MulticontactLaw>)
              multicontact_contact_block(block, lanes, *block_pair, dt);
            else
              hertz_contact_block(block, lanes, *block_pair, dt);
            for (int l = 0; l < lanes; ++l) {
              const std::int64_t p = selected[q0 + l];
              const double force[3] = {block.force[0][l], block.force[1][l], block.force[2][l]};
              const double torque_first[3] = {block.torque_first[0][l], block.torque_first[1][l],
                                              block.torque_first[2][l]};
              const double torque_second[3] = {block.torque_second[0][l], block.torque_second[1][l],
                                               block.torque_second[2][l]};
              for (int axis = 0; axis < 3; ++axis)
                history_[p].tangential[axis] = block.spring[axis][l];
              if constexpr (std::is_same_v<Law, MulticontactLaw>)
                plastic_force(history_[p]) = block.plastic_force[l];
              double arm_first = 0.0, arm_second = 0.0;
              if constexpr (stress_on) {
                const double fn = block.normal_force[l], half_overlap = 0.5 * block.overlap[l];
                virial[2 * p] = fn;
                virial[2 * p + 1] = half_overlap;
                arm_first = (block.radius_first[l] - half_overlap) * fn;
                arm_second = (block.radius_second[l] - half_overlap) * fn;
              }
              deliver(q0 + l, first[p], second[p], force, torque_first, torque_second, arm_first,
                      arm_second);
            }
          }
          continue;
        }
      }
      for (std::int64_t q = begin; q < k; ++q) {
        const std::int64_t p = selected[q];
        const int i = first[p], j = second[p];
        const double* gi = geometry + 4 * i;
        const double* gj = geometry + 4 * j;
        const double* shift = image_shift + 2 * image[p];
        const double d[3] = {gj[0] - gi[0] + shift[0], gj[1] - gi[1] + shift[1], gj[2] - gi[2]};
        const double* mi = motion + 8 * i;
        const double* mj = motion + 8 * j;
        PairKinematics kinematics = pair_kinematics(
            d, gi[3], gj[3], {{mi[0], mi[1], mi[2]}, {mi[3], mi[4], mi[5]}, mi[6], mi[7]},
            {{mj[0], mj[1], mj[2]}, {mj[3], mj[4], mj[5]}, mj[6], mj[7]});
        ContactKinematics& c = kinematics.contact;
        if constexpr (stress_on) c.pair_pressure = 0.5 * (pressure[i] + pressure[j]);
        const PairConstants& pc = materials_.pair(s.material[i], s.material[j]);
        const double bodies_radius =
            body_contact_radius(pc.body_contact_radius, body, body_radius, radius, i, j);
        if (bodies_radius > 0.0) c.effective_radius = bodies_radius;
        const ContactForce f = contact_force<Law>(c, pc, history_[p], dt);
        double arm_first = 0.0, arm_second = 0.0;
        if constexpr (stress_on) {  // for this step's gather of p = Σ rc Fn / (3V)
          const double half_overlap = 0.5 * c.overlap;
          virial[2 * p] = f.normal_force;
          virial[2 * p + 1] = half_overlap;
          arm_first = (gi[3] - half_overlap) * f.normal_force;
          arm_second = (gj[3] - half_overlap) * f.normal_force;
        }
        double torque_first[3], torque_second[3];
        contact_torques(c.normal, f, kinematics.arm_first, kinematics.arm_second, torque_first,
                        torque_second);
        deliver(q, i, j, f.force, torque_first, torque_second, arm_first, arm_second);
      }
    }
  }
  sphere_contacts_ = touching;
}

template <bool stress_on, bool damped, class Law>
void Engine::gather_forces_with(double kick, bool with_bonds) {
  SphereState& s = state_;
  const std::int64_t n = static_cast<std::int64_t>(s.size());
  const std::size_t wall_count = walls_.size();
  wall_force_per_sphere_.resize(wall_count);
  wall_touching_.resize(wall_count);
  for (std::size_t k = 0; k < wall_count; ++k) {  // zero while a sphere does not touch wall k
    wall_force_per_sphere_[k].resize(static_cast<std::size_t>(n), 0.0);
    wall_touching_[k].resize(static_cast<std::size_t>(n), 0);
  }
  const double dt = settings_.time_step;
  const double alpha = settings_.local_damping;
  const auto& g = settings_.gravity;
  const std::int32_t* __restrict second_offset = pairs_.second_offset.data();
  const std::int32_t* __restrict second_pairs = pairs_.second_pairs.data();
  const PairResult* __restrict results = pair_results_.data();
  const std::int32_t* __restrict slot = pair_slot_.data();
  const std::int32_t* __restrict cross_second_end = cross_second_end_.data();
  const SphereSums* __restrict sums = sphere_sums_.data();
  // Raw pointers hoisted out of the loop: through the containers the compiler reloads every
  // array's address after each store.
  const double* __restrict geometry = geometry_.data();
  const double* __restrict motion = motion_.data();
  const std::int32_t* __restrict material = s.material.data();
  const double* __restrict inverse_mass = s.inverse_mass.data();
  double* __restrict fx = s.force.x.data();
  double* __restrict fy = s.force.y.data();
  double* __restrict fz = s.force.z.data();
  double* __restrict tx = s.torque.x.data();
  double* __restrict ty = s.torque.y.data();
  double* __restrict tz = s.torque.z.data();
  double* __restrict vx = s.velocity.x.data();
  double* __restrict vy = s.velocity.y.data();
  double* __restrict vz = s.velocity.z.data();
  double* __restrict wx = s.angular_velocity.x.data();
  double* __restrict wy = s.angular_velocity.y.data();
  double* __restrict wz = s.angular_velocity.z.data();
  // Love–Weber pressure p = -tr σ / 3 = Σ rc Fn / (3V): l · f = -rc Fn at either end of a
  // contact (rc the centre-to-contact distance, Fn > 0 repulsive), V the sphere's volume. The
  // tensor itself is summed on demand (Engine::particle_stress, diagnostics.cpp): the law needs
  // only the trace, and the trace needs two numbers per contact instead of five. Non-touching
  // pairs hold Fn = 0.
  const double* __restrict virial = stress_on ? pair_virial_.data() : nullptr;
  double* __restrict pressure = stress_on ? pressure_.data() : nullptr;
  if constexpr (stress_on)
    for (std::size_t k = 0; k < wall_count; ++k)
      wall_tangential_[k].resize(2 * static_cast<std::size_t>(n));
  std::vector<double*> wall_force_per_sphere(wall_count);
  std::vector<std::uint8_t*> wall_touching(wall_count);
  for (std::size_t k = 0; k < wall_count; ++k) {
    wall_force_per_sphere[k] = wall_force_per_sphere_[k].data();
    wall_touching[k] = wall_touching_[k].data();
  }
  // Wall constants copied out of walls_: the byte stores to the touching flags below may alias
  // anything, and the loop would reload each wall's fields after every one.
  struct WallView {
    double position, facing, velocity;
    int material;
  };
  std::vector<WallView> wall_views(wall_count);
  for (std::size_t k = 0; k < wall_count; ++k)
    wall_views[k] = {walls_[k].position, static_cast<double>(walls_[k].facing), walls_[k].velocity,
                     walls_[k].material};
  const WallView* walls = wall_views.data();
  // Wall totals per chunk, then over the chunks in order: the same bits for any thread count.
  const std::int64_t chunks = force_chunks_;
  wall_chunk_force_.assign(static_cast<std::size_t>(chunks) * wall_count, 0.0);
  wall_chunk_contacts_.assign(static_cast<std::size_t>(chunks), 0);
  double* __restrict chunk_force = wall_chunk_force_.data();
  std::int64_t* __restrict chunk_contacts = wall_chunk_contacts_.data();
  const bool has_bonds = !bonds_.empty();
  const BondGather bond_gather(bonds_);
  const int threads = n >= parallel_min_spheres ? omp_get_max_threads() : 1;
#pragma omp parallel num_threads(threads)
  {
    // The pair loop's chunks, on the same threads: each thread gathers the sums it wrote.
    const std::int64_t team = omp_get_num_threads(), rank = omp_get_thread_num();
    constexpr std::int64_t no_sphere = std::numeric_limits<std::int64_t>::max();
    std::vector<const std::int32_t*> cursor(wall_count), stop(wall_count);
    for (std::int64_t chunk = thread_chunk_start(rank, team);
         chunk < thread_chunk_start(rank + 1, team); ++chunk) {
      double* __restrict wall_sum = chunk_force + chunk * static_cast<std::int64_t>(wall_count);
      std::int64_t wall_contact_count = 0;
      const std::int64_t chunk_begin = chunk_start(chunk), chunk_end = chunk_start(chunk + 1);
      std::int64_t next_near = no_sphere;
      for (std::size_t k = 0; k < wall_count; ++k) {
        const std::vector<std::int32_t>& near = wall_candidates_[k];
        cursor[k] = std::lower_bound(near.data(), near.data() + near.size(), chunk_begin);
        stop[k] = near.data() + near.size();
        if (cursor[k] != stop[k]) next_near = std::min<std::int64_t>(next_near, *cursor[k]);
      }
      for (std::int64_t i = chunk_begin; i < chunk_end; ++i) {
        double f[3] = {0.0, 0.0, 0.0}, t[3] = {0.0, 0.0, 0.0};
        double arm_force = 0.0;  // Σ rc Fn
        const double zi = geometry[4 * i + 2], ri = geometry[4 * i + 3];
        // The pair loop's sums over the contacts within i's chunk, then the partners in earlier
        // chunks (a prefix of i's "second" pairs, in increasing partner order).
        const SphereSums& own = sums[i];
        f[0] = own.force[0], f[1] = own.force[1], f[2] = own.force[2];
        t[0] = own.torque[0], t[1] = own.torque[1], t[2] = own.torque[2];
        if constexpr (stress_on) arm_force = own.arm_force;
        for (std::int32_t e = second_offset[i]; e < cross_second_end[i]; ++e) {
          const PairResult& r = results[slot[second_pairs[e]]];
          f[0] += r.force[0], f[1] += r.force[1], f[2] += r.force[2];
          t[0] += r.torque_second[0], t[1] += r.torque_second[1], t[2] += r.torque_second[2];
          if constexpr (stress_on) {
            const double* v = virial + 2 * second_pairs[e];
            arm_force += (ri - v[1]) * v[0];
          }
        }
        if (has_bonds) {
          // A bonded sub-sphere's stress includes its bonds (models.md, "Stress of a bonded
          // sub-sphere"): summed over a body's sub-spheres the bond terms leave the body's stress
          // from its external contacts.
          if (with_bonds)
            gather_bond_forces<stress_on>(bond_gather, i, f, t, &arm_force);
          else if constexpr (stress_on)
            arm_force += bond_arm_force(bonds_, i);
        }
        // Walls: the same law with the wall as partner j (infinite radius and mass, no rotation).
        // Only the spheres near a wall at the last list build can touch it (build_list), and
        // next_near is the lowest of them still ahead.
        if (i == next_near) {
          next_near = no_sphere;
          for (std::size_t k = 0; k < wall_count; ++k) {
            if (cursor[k] == stop[k] || *cursor[k] != i) {
              if (cursor[k] != stop[k]) next_near = std::min<std::int64_t>(next_near, *cursor[k]);
              continue;
            }
            if (++cursor[k] != stop[k]) next_near = std::min<std::int64_t>(next_near, *cursor[k]);
            const WallView& w = walls[k];
            const double gap = w.facing * (zi - w.position);
            if (gap >= ri) {  // most spheres, most steps: nothing to write
              if (wall_touching[k][i]) release_wall_contact(k, static_cast<std::size_t>(i));
              continue;
            }
            ContactKinematics c;
            c.normal[0] = c.normal[1] = 0.0;
            c.normal[2] = -w.facing;
            c.overlap = ri - gap;
            const double rc = gap;  // the contact point lies on the plane
            const double* nn = c.normal;
            // Predicted end-of-step velocities, as for sphere pairs (pack_spheres()).
            const double* mi = motion + 8 * i;
            const double vx = mi[0], vy = mi[1], vz = mi[2], wx = mi[3], wy = mi[4], wz = mi[5];
            c.relative_velocity[0] = -(vx + rc * (wy * nn[2] - wz * nn[1]));
            c.relative_velocity[1] = -(vy + rc * (wz * nn[0] - wx * nn[2]));
            c.relative_velocity[2] = w.velocity - (vz + rc * (wx * nn[1] - wy * nn[0]));
            c.relative_rotation[0] = wx;
            c.relative_rotation[1] = wy;
            c.relative_rotation[2] = wz;
            c.effective_radius = ri;
            c.radius_first = ri;
            c.radius_second = 0.0;  // a wall
            c.effective_mass = mi[6];
            c.inverse_inertia_sum = mi[7];
            // Against a wall the pair's pressure is the sphere's own p_i of the last step
            // (overwritten below): a sphere on a plate is the mirror half of two equal spheres
            // pressed together, whose P_ij is p (models.md, "Which reading of Eq. 6").
            c.pair_pressure = 0.0;
            if constexpr (stress_on) c.pair_pressure = pressure[i];
            const PairConstants& pc = materials_.pair(material[i], w.material);
            const ContactForce cf = contact_force<Law>(c, pc, wall_history_[k][i], dt);
            const double cx = nn[1] * cf.force[2] - nn[2] * cf.force[1];
            const double cy = nn[2] * cf.force[0] - nn[0] * cf.force[2];
            const double cz = nn[0] * cf.force[1] - nn[1] * cf.force[0];
            f[0] -= cf.force[0], f[1] -= cf.force[1], f[2] -= cf.force[2];
            t[0] += -rc * cx + cf.rolling_torque[0];
            t[1] += -rc * cy + cf.rolling_torque[1];
            t[2] += -rc * cz + cf.rolling_torque[2];
            wall_force_per_sphere[k][i] = cf.force[2];
            wall_touching[k][i] = 1;
            wall_sum[k] += cf.force[2];
            ++wall_contact_count;
            if constexpr (stress_on) {
              arm_force += rc * cf.normal_force;
              wall_tangential_[k][2 * i] = cf.force[0];  // for the tensor on demand
              wall_tangential_[k][2 * i + 1] = cf.force[1];
            }
          }
        }
        if constexpr (stress_on) pressure[i] = arm_force / (4.0 * std::numbers::pi * ri * ri * ri);
        const double m = motion[8 * i + 6];
        f[0] += m * g[0], f[1] += m * g[1], f[2] += m * g[2];
        fx[i] = f[0], fy[i] = f[1], fz[i] = f[2];
        tx[i] = t[0], ty[i] = t[1], tz[i] = t[2];
        if (kick > 0.0) {
          const double im = kick * inverse_mass[i], ii = kick * motion[8 * i + 7];
          if constexpr (damped) {  // local damping by the half-step velocity
            f[0] = locally_damped(f[0], vx[i], alpha), f[1] = locally_damped(f[1], vy[i], alpha);
            f[2] = locally_damped(f[2], vz[i], alpha), t[0] = locally_damped(t[0], wx[i], alpha);
            t[1] = locally_damped(t[1], wy[i], alpha), t[2] = locally_damped(t[2], wz[i], alpha);
          }
          vx[i] += f[0] * im, vy[i] += f[1] * im, vz[i] += f[2] * im;
          wx[i] += t[0] * ii, wy[i] += t[1] * ii, wz[i] += t[2] * ii;
        }
      }
      chunk_contacts[chunk] = wall_contact_count;
    }
  }
  wall_force_.assign(wall_count, 0.0);
  wall_contacts_ = 0;
  for (std::int64_t chunk = 0; chunk < chunks; ++chunk) {
    for (std::size_t k = 0; k < wall_count; ++k)
      wall_force_[k] += wall_chunk_force_[static_cast<std::size_t>(chunk) * wall_count + k];
    wall_contacts_ += wall_chunk_contacts_[static_cast<std::size_t>(chunk)];
  }
}

}  // namespace shapepress::simulate
