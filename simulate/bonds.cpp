#include "simulate/bonds.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include <fmt/format.h>

#include "common/error.hpp"

namespace shapepress::simulate {

void BondParameters::check() const {
  const auto positive = [](double v) { return v > 0.0 && std::isfinite(v); };
  if (modulus == 0.0) {
    if (!positive(normal_stiffness))
      throw InputError(
          fmt::format("bond normal stiffness k̄n = {} N/m^3 must be > 0", normal_stiffness));
    if (!positive(shear_stiffness))
      throw InputError(
          fmt::format("bond shear stiffness k̄s = {} N/m^3 must be > 0", shear_stiffness));
  } else {
    if (!positive(modulus))
      throw InputError(fmt::format("bond modulus Ē = {} Pa must be > 0", modulus));
    if (!positive(shear_ratio))
      throw InputError(fmt::format("bond shear ratio k̄s/k̄n = {} must be > 0", shear_ratio));
  }
  if (!(modulus_fraction >= 0.0 && std::isfinite(modulus_fraction)))
    throw InputError(fmt::format("bond modulus fraction = {} must be >= 0", modulus_fraction));
  if (!(radius_multiplier > 0.0 && radius_multiplier <= 2.0))
    throw InputError(
        fmt::format("bond radius multiplier λ̄ = {} must be in (0, 2]", radius_multiplier));
  if (!(tensile_strength > 0.0) || !(shear_strength > 0.0))
    throw InputError(fmt::format("bond strengths σc = {} Pa, τc = {} Pa must be > 0",
                                 tensile_strength, shear_strength));
  if (!(damping_ratio >= 0.0 && damping_ratio <= 1.0))
    throw InputError(fmt::format("bond damping ratio {} must be in [0, 1]", damping_ratio));
}

std::int64_t BondSet::intact_count() const {
  std::int64_t n = 0;
  for (std::uint8_t b : intact)
    n += b;
  return n;
}

void BondSet::index(const SphereState& state) {
  const std::size_t sphere_count = state.size();
  gather_offset.assign(sphere_count + 1, 0);
  for (std::size_t b = 0; b < size(); ++b) {
    ++gather_offset[static_cast<std::size_t>(first[b]) + 1];
    ++gather_offset[static_cast<std::size_t>(second[b]) + 1];
  }
  std::partial_sum(gather_offset.begin(), gather_offset.end(), gather_offset.begin());
  gather.assign(2 * size(), 0);
  std::vector<std::int32_t> fill(gather_offset.begin(), gather_offset.end() - 1);
  // Bonds in increasing index: each sphere's entries come out in increasing bond index.
  for (std::size_t b = 0; b < size(); ++b) {
    const auto entry = static_cast<std::int32_t>(2 * b);
    gather[static_cast<std::size_t>(fill[static_cast<std::size_t>(first[b])]++)] = entry;
    gather[static_cast<std::size_t>(fill[static_cast<std::size_t>(second[b])]++)] = entry + 1;
  }
  result.assign(size(), Result{});
  constants.assign(size(), Constants{});
  breakable = false;
  std::size_t with_dampers = 0;
  for (std::size_t b = 0; b < size(); ++b) {
    breakable = breakable || std::isfinite(tensile_strength[b]) || std::isfinite(shear_strength[b]);
    with_dampers += damping_ratio[b] > 0.0;
    const auto i = static_cast<std::size_t>(first[b]), j = static_cast<std::size_t>(second[b]);
    const double ri = state.radius[i], rj = state.radius[j];
    Constants& k = constants[b];
    k.first = first[b], k.second = second[b];
    k.arm_first = ri / (ri + rj), k.arm_second = rj / (ri + rj);
    k.normal_spring = normal_spring[b], k.shear_spring = shear_spring[b];
    k.twist_spring = twist_spring[b], k.bend_spring = bend_spring[b];
    const double zeta = damping_ratio[b];
    if (zeta <= 0.0) continue;
    const double m_eff = 1.0 / (state.inverse_mass[i] + state.inverse_mass[j]);
    const double i_eff = 1.0 / (state.inverse_inertia[i] + state.inverse_inertia[j]);
    k.damping[0] = 2.0 * zeta * std::sqrt(normal_spring[b] * m_eff);
    k.damping[1] = 2.0 * zeta * std::sqrt(shear_spring[b] * m_eff);
    k.damping[2] = 2.0 * zeta * std::sqrt(twist_spring[b] * i_eff);
    k.damping[3] = 2.0 * zeta * std::sqrt(bend_spring[b] * i_eff);
  }
  damped = with_dampers > 0 && with_dampers == size();
  damping_mix = with_dampers > 0 && with_dampers < size();
}

namespace {

double centre_distance(const SphereState& s, std::size_t i, std::size_t j) {
  const double dx = s.position.x[j] - s.position.x[i];
  const double dy = s.position.y[j] - s.position.y[i];
  const double dz = s.position.z[j] - s.position.z[i];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

void add_bond(BondSet& bonds, const SphereState& s, std::int32_t i, std::int32_t j,
              const BondParameters& p) {
  const double ri = s.radius[static_cast<std::size_t>(i)];
  const double rj = s.radius[static_cast<std::size_t>(j)];
  const double r = p.radius_multiplier * std::min(ri, rj);
  const double area = std::numbers::pi * r * r;
  const double polar = 0.5 * std::numbers::pi * r * r * r * r;  // J = π R̄⁴/2, I = J/2
  // P&C 2004 §2.2.2: with a bond modulus Ē, k̄n = Ē/(ri + rj) keeps the bond's axial stiffness
  // per unit area and length the same for every sub-sphere size.
  const double kn = p.modulus > 0.0 ? p.modulus / (ri + rj) : p.normal_stiffness;
  const double ks = p.modulus > 0.0 ? kn * p.shear_ratio : p.shear_stiffness;
  bonds.first.push_back(i);
  bonds.second.push_back(j);
  bonds.radius.push_back(r);
  bonds.normal_spring.push_back(kn * area);
  bonds.shear_spring.push_back(ks * area);
  bonds.twist_spring.push_back(ks * polar);
  bonds.bend_spring.push_back(kn * 0.5 * polar);
  bonds.tensile_strength.push_back(p.tensile_strength);
  bonds.shear_strength.push_back(p.shear_strength);
  bonds.damping_ratio.push_back(p.damping_ratio);
  BondSet::History h;
  h.length = centre_distance(s, static_cast<std::size_t>(i), static_cast<std::size_t>(j));
  bonds.history.push_back(h);
  bonds.intact.push_back(1);
}

}  // namespace

BondSet create_bonds(const SphereState& state, double bond_multiplier,
                     const BondParameters& parameters, const std::vector<std::string>& body_names) {
  if (!(bond_multiplier > 1.0 && std::isfinite(bond_multiplier)))
    throw InputError(fmt::format(
        "bond multiplier m_b = {} must be > 1: sub-spheres only touch, so with m_b <= 1 "
        "(Eq. 10, |xi - xj| < (ri + rj) m_b) they would not bond",
        bond_multiplier));
  parameters.check();
  const std::size_t n = state.size();
  // Sub-spheres grouped by body, in index order within each body.
  std::vector<std::int32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::int32_t a, std::int32_t b) { return state.body[a] < state.body[b]; });
  std::vector<std::array<std::int32_t, 2>> pairs;
  std::vector<std::int32_t> bonded(n, 0);
  for (std::size_t start = 0; start < n;) {
    std::size_t end = start;
    while (end < n && state.body[order[end]] == state.body[order[start]])
      ++end;
    for (std::size_t a = start; a < end; ++a)
      for (std::size_t b = a + 1; b < end; ++b) {
        const auto i = static_cast<std::size_t>(std::min(order[a], order[b]));
        const auto j = static_cast<std::size_t>(std::max(order[a], order[b]));
        const double reach = (state.radius[i] + state.radius[j]) * bond_multiplier;  // Eq. 10
        if (centre_distance(state, i, j) < reach) {
          pairs.push_back({static_cast<std::int32_t>(i), static_cast<std::int32_t>(j)});
          ++bonded[i], ++bonded[j];
        }
      }
    if (end - start > 1)
      for (std::size_t a = start; a < end; ++a)
        if (bonded[static_cast<std::size_t>(order[a])] == 0) {
          const std::int32_t body = state.body[order[a]];
          const std::string name = static_cast<std::size_t>(body) < body_names.size()
                                       ? "'" + body_names[static_cast<std::size_t>(body)] + "'"
                                       : fmt::format("{}", body);
          throw InputError(fmt::format(
              "particle {}: sub-sphere {} has no neighbour within (ri + rj) m_b = {} x the radii "
              "sum, so it would be left unbonded (raise m_b or refill the particle)",
              name, order[a], bond_multiplier));
        }
    start = end;
  }
  std::sort(pairs.begin(), pairs.end());
  BondSet bonds;
  bonds.contact_when_bonded = parameters.contact_when_bonded;
  for (const auto& p : pairs)
    add_bond(bonds, state, p[0], p[1], parameters);
  bonds.index(state);
  return bonds;
}

namespace {

// Turned with the pair over the step, keeping its length: into the plane normal to the current
// n (the tilt of the bond's axis, as LIGGGHTS turns its tangential history), and by the pair's
// mean spin θ = dt (ωi + ωj)·n / 2 about n (as Yade's ScGeom twists its shear force):
//   v ← |v| (v⊥ + τ n × v) / |v⊥ + τ n × v|,   v⊥ = v - (v·n) n,   τ = tan θ,
// a turn by θ within the plane whatever τ. n × v is normal to v⊥ and as long, so the norm is
// √(1 + τ²) |v⊥|: the one division and square root of the projection serve the turn too. No
// branch, so that the blocks vectorize: a zero v stays zero (its along, t2 and scale are zero).
inline void turn_with_pair(double v[3], const double n[3], double tan_spin,
                           double one_plus_tan_spin2) {
  const double length2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  const double along = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
  const double t2 = length2 - along * along;
  const double ratio = t2 > 0.0 ? length2 / (t2 * one_plus_tan_spin2) : 0.0;
  const double scale = std::sqrt(ratio);
  const double spun[3] = {n[1] * v[2] - n[2] * v[1], n[2] * v[0] - n[0] * v[2],
                          n[0] * v[1] - n[1] * v[0]};
  for (int k = 0; k < 3; ++k)
    v[k] = (v[k] - along * n[k] + tan_spin * spun[k]) * scale;
}

// Relative motion of the bond ends, j minus i: the velocity of the bond centre seen from each
// sphere, v + ω × arm with arms rci n from i and -rcj n from j, into v,
//   v = (vj - vi) - (rcj ωj + rci ωi) × n   (one cross product for both ends),
// and ωj - ωi into w.
inline void relative_motion(const double vi[3], const double wi[3], const double vj[3],
                            const double wj[3], const double n[3], double rci, double rcj,
                            double v[3], double w[3]) {
  const double a[3] = {rcj * wj[0] + rci * wi[0], rcj * wj[1] + rci * wi[1],
                       rcj * wj[2] + rci * wi[2]};
  v[0] = (vj[0] - vi[0]) - (a[1] * n[2] - a[2] * n[1]);
  v[1] = (vj[1] - vi[1]) - (a[2] * n[0] - a[0] * n[2]);
  v[2] = (vj[2] - vi[2]) - (a[0] * n[1] - a[1] * n[0]);
  for (int k = 0; k < 3; ++k)
    w[k] = wj[k] - wi[k];
}

// One bond's step, shared by the scalar loop and the vectorized blocks so that both give the
// same bits. `e`: the ends' half-step velocities and spins (those that moved the spheres) for
// the increments of shear, twist and bending; the normal force follows the exact change of
// length (so also at the first evaluation). The history turns with the pair, so a rigid turn
// leaves Fs and Mb fixed in the bodies.
struct BondEnds {
  double vi[3], wi[3], vj[3], wj[3];
};
struct BondSprings {
  double length, fn, fs[3], mt, mb[3];
};
[[gnu::always_inline]] inline void advance_springs(BondSprings& h, double d, const double n[3],
                                                   double rci, double rcj, const BondEnds& e,
                                                   double kn, double ks, double kt, double kb,
                                                   double increment_dt) {
  double v[3], w[3];
  relative_motion(e.vi, e.wi, e.vj, e.wj, n, rci, rcj, v, w);
  // θ, the pair's mean spin about the bond over the step (turn_with_pair).
  const double spin =
      0.5 * increment_dt *
      ((e.wi[0] + e.wj[0]) * n[0] + (e.wi[1] + e.wj[1]) * n[1] + (e.wi[2] + e.wj[2]) * n[2]);
  h.fn = h.fn - kn * (d - h.length);
  h.length = d;
  // tan θ ≈ θ (1 + θ²/3): the turn's angle is atan of it, θ - 2θ⁵/15, without a tangent here.
  const double tan_spin = spin * (1.0 + spin * spin * (1.0 / 3.0));
  const double one_plus_tan_spin2 = 1.0 + tan_spin * tan_spin;
  turn_with_pair(h.fs, n, tan_spin, one_plus_tan_spin2);
  turn_with_pair(h.mb, n, tan_spin, one_plus_tan_spin2);
  const double vn = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
  const double wt = w[0] * n[0] + w[1] * n[1] + w[2] * n[2];
  const double ks_dt = ks * increment_dt, kb_dt = kb * increment_dt;
  for (int c = 0; c < 3; ++c) {
    h.fs[c] -= ks_dt * (v[c] - vn * n[c]);
    h.mb[c] -= kb_dt * (w[c] - wt * n[c]);
  }
  h.mt = h.mt - kt * increment_dt * wt;
}

// The bond's force on `second` and the torques on its ends from its springs, with the dampers
// `damping` (normal, shear, twist, bending) on the predicted end-of-step motion `predicted`, as
// the contact law's (forces.cpp). `separation`: x_second - x_first.
template <bool damped>
[[gnu::always_inline]] inline void bond_result(BondSet::Result& out, const BondSprings& h,
                                               const double separation[3], const double n[3],
                                               double rci, double rcj, const BondEnds& predicted,
                                               const double damping[4]) {
  double force[3], moment[3];
  for (int c = 0; c < 3; ++c) {
    force[c] = h.fn * n[c] + h.fs[c];
    moment[c] = h.mt * n[c] + h.mb[c];
  }
  if constexpr (damped) {
    double dv[3], dw[3];
    relative_motion(predicted.vi, predicted.wi, predicted.vj, predicted.wj, n, rci, rcj, dv, dw);
    const double cn = damping[0], cs = damping[1], ct = damping[2], cb = damping[3];
    const double dvn = dv[0] * n[0] + dv[1] * n[1] + dv[2] * n[2];
    const double dwt = dw[0] * n[0] + dw[1] * n[1] + dw[2] * n[2];
    for (int c = 0; c < 3; ++c) {
      force[c] -= cn * dvn * n[c] + cs * (dv[c] - dvn * n[c]);
      moment[c] -= ct * dwt * n[c] + cb * (dw[c] - dwt * n[c]);
    }
  }
  const double cx = n[1] * force[2] - n[2] * force[1];
  const double cy = n[2] * force[0] - n[0] * force[2];
  const double cz = n[0] * force[1] - n[1] * force[0];
  for (int c = 0; c < 3; ++c)
    out.force[c] = force[c];
  out.separation_force =
      separation[0] * force[0] + separation[1] * force[1] + separation[2] * force[2];
  out.torque_first[0] = -rci * cx - moment[0];
  out.torque_first[1] = -rci * cy - moment[1];
  out.torque_first[2] = -rci * cz - moment[2];
  out.torque_second[0] = -rcj * cx + moment[0];
  out.torque_second[1] = -rcj * cy + moment[1];
  out.torque_second[2] = -rcj * cz + moment[2];
}

// Bonds [begin, end) of compute_bond_forces, one thread's share, one bond at a time: the loop for
// breakable bonds and for mixed dampers (the others go through bond_blocks_range).
// An AVX2 clone is picked at load time where the CPU has it: the same scalar IEEE operations (no
// FMA), but three-operand instructions, which spare the register copies of a loop this long.
__attribute__((target_clones("avx2", "default"))) void bond_forces_range(
    BondSet& bonds, const SphereState& s, const double* __restrict motion, const Box& box,
    double increment_dt, std::int64_t begin, std::int64_t end) {
  const BondSet::Constants* __restrict constants = bonds.constants.data();
  BondSet::History* __restrict history = bonds.history.data();
  std::uint8_t* __restrict intact = bonds.intact.data();
  BondSet::Result* __restrict result = bonds.result.data();
  const bool periodic_x = box.periodic_x(), periodic_y = box.periodic_y();
  for (std::int64_t b = begin; b < end; ++b) {
    if (!intact[b]) continue;
    const BondSet::Constants& k = constants[b];
    const std::size_t i = static_cast<std::size_t>(k.first);
    const std::size_t j = static_cast<std::size_t>(k.second);
    double separation[3] = {s.position.x[j] - s.position.x[i], s.position.y[j] - s.position.y[i],
                            s.position.z[j] - s.position.z[i]};
    // Bonds join sub-spheres of one particle, smaller than half the box: the nearest image.
    if (periodic_x) separation[0] -= box.length_x * std::nearbyint(separation[0] / box.length_x);
    if (periodic_y) separation[1] -= box.length_y * std::nearbyint(separation[1] / box.length_y);
    const double* x = separation;
    const double d = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const double inverse_d = 1.0 / d;
    const double n[3] = {x[0] * inverse_d, x[1] * inverse_d, x[2] * inverse_d};
    // The bond's centre divides the centre distance in the ratio of the radii (the contact point
    // of touching spheres).
    const double rci = d * k.arm_first, rcj = d * k.arm_second;
    const BondEnds ends{
        {s.velocity.x[i], s.velocity.y[i], s.velocity.z[i]},
        {s.angular_velocity.x[i], s.angular_velocity.y[i], s.angular_velocity.z[i]},
        {s.velocity.x[j], s.velocity.y[j], s.velocity.z[j]},
        {s.angular_velocity.x[j], s.angular_velocity.y[j], s.angular_velocity.z[j]}};
    BondSet::History& stored = history[b];
    BondSprings h{stored.length, stored.normal_force, {}, stored.twist_moment, {}};
    for (int c = 0; c < 3; ++c)
      h.fs[c] = stored.shear_force[c], h.mb[c] = stored.bend_moment[c];
    advance_springs(h, d, n, rci, rcj, ends, k.normal_spring, k.shear_spring, k.twist_spring,
                    k.bend_spring, increment_dt);
    if (bonds.breakable) {
      // Strength (P&C 2004 Eq. 11): the elastic forces only.
      const double r = bonds.radius[b];
      const double area = std::numbers::pi * r * r;
      const double bend_inertia = 0.25 * std::numbers::pi * r * r * r * r;
      const double fs_norm = std::sqrt(h.fs[0] * h.fs[0] + h.fs[1] * h.fs[1] + h.fs[2] * h.fs[2]);
      const double mb_norm = std::sqrt(h.mb[0] * h.mb[0] + h.mb[1] * h.mb[1] + h.mb[2] * h.mb[2]);
      const double sigma = -h.fn / area + mb_norm * r / bend_inertia;
      const double tau = fs_norm / area + std::fabs(h.mt) * r / (2.0 * bend_inertia);
      if (sigma >= bonds.tensile_strength[b] || tau >= bonds.shear_strength[b]) {
        // For good: the pair becomes a plain contact, and the zero result adds nothing to the
        // gather.
        intact[b] = 0;
        h.fn = h.mt = 0.0;
        for (int c = 0; c < 3; ++c)
          h.fs[c] = h.mb[c] = 0.0;
      }
    }
    stored.length = h.length, stored.normal_force = h.fn, stored.twist_moment = h.mt;
    for (int c = 0; c < 3; ++c)
      stored.shear_force[c] = h.fs[c], stored.bend_moment[c] = h.mb[c];
    if (!intact[b]) {
      result[b] = BondSet::Result{};
      continue;
    }
    if (k.damping[0] > 0.0) {
      const double* mi = motion + 8 * i;
      const double* mj = motion + 8 * j;
      const BondEnds predicted{{mi[0], mi[1], mi[2]},
                               {mi[3], mi[4], mi[5]},
                               {mj[0], mj[1], mj[2]},
                               {mj[3], mj[4], mj[5]}};
      bond_result<true>(result[b], h, x, n, rci, rcj, predicted, k.damping);
    } else {
      bond_result<false>(result[b], h, x, n, rci, rcj, ends, k.damping);
    }
  }
}

// Unbreakable bonds over blocks of `bond_block_capacity` laid out as arrays, so that the compiler
// vectorizes bond_forces_range's arithmetic across bonds: copied in, computed lane by lane with
// the scalar loop's IEEE operations in its order (no FMA, no reassociation: the same bits as
// bond_forces_range, tests/unit/simulate/bonds_test.cpp), then copied out. `damped`: every bond
// has dampers (BondSet::Constants::damping[0] > 0), or none has.
constexpr int bond_block_capacity = 32;

struct alignas(64) BondBlock {
  static constexpr int capacity = bond_block_capacity;
  double dx[capacity], dy[capacity], dz[capacity];
  double vi[3][capacity], vj[3][capacity], wi[3][capacity], wj[3][capacity];
  double mvi[3][capacity], mvj[3][capacity], mwi[3][capacity], mwj[3][capacity];
  double arm_first[capacity], arm_second[capacity];
  double kn[capacity], ks[capacity], kt[capacity], kb[capacity];
  double cn[capacity], cs[capacity], ct[capacity], cb[capacity];
  double length[capacity], fn[capacity], fs[3][capacity], mt[capacity], mb[3][capacity];
  double force[3][capacity], torque_first[3][capacity], torque_second[3][capacity];
  double separation_force[capacity];
};

template <bool damped>
[[gnu::always_inline]] inline void bond_block_lanes(BondBlock& k, int lanes, double increment_dt) {
  for (int l = 0; l < lanes; ++l) {
    const double x[3] = {k.dx[l], k.dy[l], k.dz[l]};
    const double d = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const double inverse_d = 1.0 / d;
    const double n[3] = {x[0] * inverse_d, x[1] * inverse_d, x[2] * inverse_d};
    const double rci = d * k.arm_first[l], rcj = d * k.arm_second[l];
    const BondEnds ends{{k.vi[0][l], k.vi[1][l], k.vi[2][l]},
                        {k.wi[0][l], k.wi[1][l], k.wi[2][l]},
                        {k.vj[0][l], k.vj[1][l], k.vj[2][l]},
                        {k.wj[0][l], k.wj[1][l], k.wj[2][l]}};
    BondSprings h{k.length[l],
                  k.fn[l],
                  {k.fs[0][l], k.fs[1][l], k.fs[2][l]},
                  k.mt[l],
                  {k.mb[0][l], k.mb[1][l], k.mb[2][l]}};
    advance_springs(h, d, n, rci, rcj, ends, k.kn[l], k.ks[l], k.kt[l], k.kb[l], increment_dt);
    k.length[l] = h.length, k.fn[l] = h.fn, k.mt[l] = h.mt;
    for (int c = 0; c < 3; ++c)
      k.fs[c][l] = h.fs[c], k.mb[c][l] = h.mb[c];
    BondSet::Result out;
    if constexpr (damped) {
      const double damping[4] = {k.cn[l], k.cs[l], k.ct[l], k.cb[l]};
      const BondEnds predicted{{k.mvi[0][l], k.mvi[1][l], k.mvi[2][l]},
                               {k.mwi[0][l], k.mwi[1][l], k.mwi[2][l]},
                               {k.mvj[0][l], k.mvj[1][l], k.mvj[2][l]},
                               {k.mwj[0][l], k.mwj[1][l], k.mwj[2][l]}};
      bond_result<true>(out, h, x, n, rci, rcj, predicted, damping);
    } else {
      const double none[4] = {0.0, 0.0, 0.0, 0.0};
      bond_result<false>(out, h, x, n, rci, rcj, ends, none);
    }
    for (int c = 0; c < 3; ++c) {
      k.force[c][l] = out.force[c];
      k.torque_first[c][l] = out.torque_first[c];
      k.torque_second[c][l] = out.torque_second[c];
    }
    k.separation_force[l] = out.separation_force;
  }
}

// The clones are plain functions: GCC does not vectorize a function template's clones.
__attribute__((target_clones("avx2", "default"))) void bond_block_forces_damped(
    BondBlock& k, int lanes, double increment_dt) {
  bond_block_lanes<true>(k, lanes, increment_dt);
}
__attribute__((target_clones("avx2", "default"))) void bond_block_forces_undamped(
    BondBlock& k, int lanes, double increment_dt) {
  bond_block_lanes<false>(k, lanes, increment_dt);
}

// Bonds [begin, end) as bond_forces_range computes them, for unbreakable bonds all damped or all
// undamped: blocks copied in, bond_block_forces, copied out.
template <bool damped>
void bond_blocks_range(BondSet& bonds, const SphereState& s, const double* __restrict motion,
                       const Box& box, double increment_dt, std::int64_t begin, std::int64_t end) {
  const BondSet::Constants* __restrict constants = bonds.constants.data();
  BondSet::History* __restrict history = bonds.history.data();
  BondSet::Result* __restrict result = bonds.result.data();
  const bool periodic_x = box.periodic_x(), periodic_y = box.periodic_y();
  BondBlock k;
  for (std::int64_t b0 = begin; b0 < end; b0 += BondBlock::capacity) {
    const int lanes = static_cast<int>(std::min<std::int64_t>(BondBlock::capacity, end - b0));
    for (int l = 0; l < lanes; ++l) {
      const BondSet::Constants& c = constants[b0 + l];
      const std::size_t i = static_cast<std::size_t>(c.first);
      const std::size_t j = static_cast<std::size_t>(c.second);
      double dx = s.position.x[j] - s.position.x[i], dy = s.position.y[j] - s.position.y[i];
      if (periodic_x) dx -= box.length_x * std::nearbyint(dx / box.length_x);
      if (periodic_y) dy -= box.length_y * std::nearbyint(dy / box.length_y);
      k.dx[l] = dx, k.dy[l] = dy, k.dz[l] = s.position.z[j] - s.position.z[i];
      k.vi[0][l] = s.velocity.x[i], k.vi[1][l] = s.velocity.y[i], k.vi[2][l] = s.velocity.z[i];
      k.vj[0][l] = s.velocity.x[j], k.vj[1][l] = s.velocity.y[j], k.vj[2][l] = s.velocity.z[j];
      k.wi[0][l] = s.angular_velocity.x[i], k.wi[1][l] = s.angular_velocity.y[i];
      k.wi[2][l] = s.angular_velocity.z[i];
      k.wj[0][l] = s.angular_velocity.x[j], k.wj[1][l] = s.angular_velocity.y[j];
      k.wj[2][l] = s.angular_velocity.z[j];
      if constexpr (damped) {
        const double* mi = motion + 8 * i;
        const double* mj = motion + 8 * j;
        for (int a = 0; a < 3; ++a) {
          k.mvi[a][l] = mi[a], k.mwi[a][l] = mi[3 + a];
          k.mvj[a][l] = mj[a], k.mwj[a][l] = mj[3 + a];
        }
        k.cn[l] = c.damping[0], k.cs[l] = c.damping[1];
        k.ct[l] = c.damping[2], k.cb[l] = c.damping[3];
      }
      k.arm_first[l] = c.arm_first, k.arm_second[l] = c.arm_second;
      k.kn[l] = c.normal_spring, k.ks[l] = c.shear_spring;
      k.kt[l] = c.twist_spring, k.kb[l] = c.bend_spring;
      const BondSet::History& h = history[b0 + l];
      k.length[l] = h.length, k.fn[l] = h.normal_force, k.mt[l] = h.twist_moment;
      for (int a = 0; a < 3; ++a)
        k.fs[a][l] = h.shear_force[a], k.mb[a][l] = h.bend_moment[a];
    }
    if constexpr (damped)
      bond_block_forces_damped(k, lanes, increment_dt);
    else
      bond_block_forces_undamped(k, lanes, increment_dt);
    for (int l = 0; l < lanes; ++l) {
      BondSet::History& h = history[b0 + l];
      h.length = k.length[l], h.normal_force = k.fn[l], h.twist_moment = k.mt[l];
      BondSet::Result& out = result[b0 + l];
      for (int a = 0; a < 3; ++a) {
        h.shear_force[a] = k.fs[a][l], h.bend_moment[a] = k.mb[a][l];
        out.force[a] = k.force[a][l];
        out.torque_first[a] = k.torque_first[a][l];
        out.torque_second[a] = k.torque_second[a][l];
      }
      out.separation_force = k.separation_force[l];
    }
  }
}

// Bonds [begin, end) by blocks where every bond is intact and unbreakable and the dampers are
// uniform; else the scalar loop.
void bond_forces_of(BondSet& bonds, const SphereState& s, const double* motion, const Box& box,
                    double increment_dt, std::int64_t begin, std::int64_t end) {
  if (bonds.breakable || bonds.damping_mix)
    bond_forces_range(bonds, s, motion, box, increment_dt, begin, end);
  else if (bonds.damped)
    bond_blocks_range<true>(bonds, s, motion, box, increment_dt, begin, end);
  else
    bond_blocks_range<false>(bonds, s, motion, box, increment_dt, begin, end);
}

}  // namespace

void compute_bond_forces(BondSet& bonds, const SphereState& s, const double* motion, const Box& box,
                         double dt, bool first_evaluation) {
  const auto count = static_cast<std::int64_t>(bonds.size());
  const double increment_dt = first_evaluation ? 0.0 : dt;
  if (count < parallel_min_bonds || omp_get_max_threads() == 1) {  // no region: not free either
    bond_forces_of(bonds, s, motion, box, increment_dt, 0, count);
    return;
  }
#pragma omp parallel
  {
    const std::int64_t team = omp_get_num_threads(), rank = omp_get_thread_num();
    bond_forces_of(bonds, s, motion, box, increment_dt, count * rank / team,
                   count * (rank + 1) / team);
  }
}

double bond_elastic_energy(const BondSet& bonds) {
  double e = 0.0;
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    if (!bonds.intact[b]) continue;
    const BondSet::History& h = bonds.history[b];
    const double fs2 = h.shear_force[0] * h.shear_force[0] + h.shear_force[1] * h.shear_force[1] +
                       h.shear_force[2] * h.shear_force[2];
    const double mb2 = h.bend_moment[0] * h.bend_moment[0] + h.bend_moment[1] * h.bend_moment[1] +
                       h.bend_moment[2] * h.bend_moment[2];
    e += 0.5 * h.normal_force * h.normal_force / bonds.normal_spring[b] +
         0.5 * fs2 / bonds.shear_spring[b] +
         0.5 * h.twist_moment * h.twist_moment / bonds.twist_spring[b] +
         0.5 * mb2 / bonds.bend_spring[b];
  }
  return e;
}

double bond_oscillation_period(const BondSet& bonds, const SphereState& state) {
  if (bonds.empty()) return std::numeric_limits<double>::infinity();
  // Gershgorin on the mass-normalised stiffness matrix M^-1/2 K M^-1/2: each row's diagonal
  // plus the magnitudes of its off-diagonals bounds ω². Per bond, translation rows carry
  // max(kn, ks) to both ends and ks·arm to both rotations; rotation rows carry ks·arm·arm' +
  // max(kt, kb) to both rotations and ks·arm to both translations.
  std::vector<double> translation(state.size(), 0.0), rotation(state.size(), 0.0);
  // Damping rates Σc/m and Σ(cs·arm² + c_turn)/I per sphere (its own and its partners' share,
  // hence the 2 below): an explicit step is stable for γ dt below about 1.
  std::vector<double> damping_t(state.size(), 0.0), damping_r(state.size(), 0.0);
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    const auto i = static_cast<std::size_t>(bonds.first[b]);
    const auto j = static_cast<std::size_t>(bonds.second[b]);
    const double k = std::max(bonds.normal_spring[b], bonds.shear_spring[b]);
    const double ks = bonds.shear_spring[b];
    const double turn = std::max(bonds.twist_spring[b], bonds.bend_spring[b]);
    const double ri = state.radius[i], rj = state.radius[j], d = bonds.history[b].length;
    const double ai = d * ri / (ri + rj), aj = d * rj / (ri + rj);
    const double mi = state.inverse_mass[i], mj = state.inverse_mass[j];  // inverses
    const double ii = state.inverse_inertia[i], ij = state.inverse_inertia[j];
    translation[i] +=
        k * (mi + std::sqrt(mi * mj)) + ks * (ai * std::sqrt(mi * ii) + aj * std::sqrt(mi * ij));
    translation[j] +=
        k * (mj + std::sqrt(mi * mj)) + ks * (ai * std::sqrt(mj * ii) + aj * std::sqrt(mj * ij));
    rotation[i] += (ks * ai * ai + turn) * ii + (ks * ai * aj + turn) * std::sqrt(ii * ij) +
                   ks * ai * (std::sqrt(ii * mi) + std::sqrt(ii * mj));
    rotation[j] += (ks * aj * aj + turn) * ij + (ks * ai * aj + turn) * std::sqrt(ii * ij) +
                   ks * aj * (std::sqrt(ij * mi) + std::sqrt(ij * mj));
    const double zeta = bonds.damping_ratio[b];
    if (zeta > 0.0) {
      const double m_eff = 1.0 / (mi + mj), i_eff = 1.0 / (ii + ij);
      const double c = 2.0 * zeta * std::sqrt(k * m_eff);
      const double cs = 2.0 * zeta * std::sqrt(ks * m_eff);
      const double c_turn = 2.0 * zeta * std::sqrt(turn * i_eff);
      damping_t[i] += c * mi, damping_t[j] += c * mj;
      damping_r[i] += (cs * ai * ai + c_turn) * ii, damping_r[j] += (cs * aj * aj + c_turn) * ij;
    }
  }
  double omega2 = 0.0;
  for (std::size_t i = 0; i < state.size(); ++i)
    omega2 = std::max({omega2, translation[i], rotation[i]});
  if (omega2 <= 0.0) return std::numeric_limits<double>::infinity();
  // Dampers shorten the stable step of an explicit scheme: for a damped oscillator the limit
  // 2/ω becomes (2/ω)(√(1+ζ²) − ζ); and the summed damping rate γ of a sphere's bonds (the shear
  // dampers act on its spin through the arm, I = 0.4 m r²) needs γ dt below about 1, so the
  // period bound is also held below π/γ (a step of 0.2 of it gives γ dt ≤ 0.63).
  const double zeta = *std::max_element(bonds.damping_ratio.begin(), bonds.damping_ratio.end());
  double period =
      2.0 * std::numbers::pi / std::sqrt(omega2) * (std::sqrt(1.0 + zeta * zeta) - zeta);
  double gamma = 0.0;
  for (std::size_t i = 0; i < state.size(); ++i)
    gamma = std::max({gamma, 2.0 * damping_t[i], 2.0 * damping_r[i]});
  if (gamma > 0.0) period = std::min(period, std::numbers::pi / gamma);
  return period;
}

}  // namespace shapepress::simulate

namespace shapepress::simulate {

BondSet bonds_from_pairs(const SphereState& state,
                         std::span<const std::array<std::int32_t, 2>> pairs,
                         std::span<const double> rest_length, const BondParameters& parameters) {
  parameters.check();
  if (rest_length.size() != pairs.size())
    throw InputError(
        fmt::format("bonds: {} pairs but {} rest lengths", pairs.size(), rest_length.size()));
  const auto n = static_cast<std::int32_t>(state.size());
  BondSet bonds;
  bonds.contact_when_bonded = parameters.contact_when_bonded;
  for (std::size_t b = 0; b < pairs.size(); ++b) {
    const auto [i, j] = pairs[b];
    if (i < 0 || j <= i || j >= n || (b > 0 && !(pairs[b - 1] < pairs[b])))
      throw InputError(fmt::format(
          "bond {} joins spheres {} and {}: pairs must be i < j < {} and sorted", b, i, j, n));
    if (!(rest_length[b] > 0.0 && std::isfinite(rest_length[b])))
      throw InputError(fmt::format("bond {}: rest length {} must be > 0", b, rest_length[b]));
    add_bond(bonds, state, i, j, parameters);
    BondSet::History& h = bonds.history.back();
    h.normal_force = bonds.normal_spring.back() * (rest_length[b] - h.length);
  }
  bonds.index(state);
  return bonds;
}

}  // namespace shapepress::simulate
