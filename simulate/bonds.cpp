#include "simulate/bonds.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <variant>

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
  std::visit([](const auto& m) { m.check(); }, model);
}

void BondSet::History::resize(std::size_t n) {
  for (auto* array : {&length, &normal_force, &twist_moment})
    array->resize(n, 0.0);
  shear_force.x.resize(n, 0.0), shear_force.y.resize(n, 0.0), shear_force.z.resize(n, 0.0);
  bend_moment.x.resize(n, 0.0), bend_moment.y.resize(n, 0.0), bend_moment.z.resize(n, 0.0);
  for (SphereArray<double>& field : model_fields)
    field.resize(n, 0.0);
}

void BondSet::Results::resize(std::size_t n) {
  for (Vec3Array* v : {&force, &torque[0], &torque[1]})
    v->resize(n);
  separation_force.assign(n, 0.0);
}

std::int64_t BondSet::intact_count() const {
  std::int64_t n = 0;
  for (std::uint8_t b : intact)
    n += b;
  return n;
}

std::array<double, 4> bond_damper_coefficients(const BondSet& bonds, std::size_t b,
                                               const SphereState& state) {
  const double zeta = bonds.damping_ratio[b];
  if (zeta <= 0.0) return {0.0, 0.0, 0.0, 0.0};
  const auto i = static_cast<std::size_t>(bonds.first[b]);
  const auto j = static_cast<std::size_t>(bonds.second[b]);
  const double m_eff = 1.0 / (state.inverse_mass[i] + state.inverse_mass[j]);
  const double i_eff = 1.0 / (state.inverse_inertia[i] + state.inverse_inertia[j]);
  const double spring[4] = {bonds.normal_spring[b], bonds.shear_spring[b], bonds.twist_spring[b],
                            bonds.bend_spring[b]};
  const double inertia[4] = {m_eff, m_eff, i_eff, i_eff};
  std::array<double, 4> damper;
  for (std::size_t mode = 0; mode < 4; ++mode)
    damper[mode] = 2.0 * zeta * std::sqrt(spring[mode] * inertia[mode]);
  return damper;
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
  result.resize(size());
  for (auto* array : {&constants.arm[0], &constants.arm[1]})
    array->assign(size(), 0.0);
  for (std::size_t mode = 0; mode < 4; ++mode) {
    constants.spring[mode].assign(size(), 0.0);
    constants.damping[mode].assign(size(), 0.0);
  }
  breakable = false;
  yields = bond_model_yields(model);
  hardening_ratio = 0.0;
  for (std::size_t mode = 0; mode < 4; ++mode)
    constants.yield_limit[mode].assign(yields ? size() : 0, 0.0);
  if (const auto* plastic = std::get_if<ElasticPlasticBond>(&model)) {
    hardening_ratio = plastic->hardening_ratio;
    for (std::size_t b = 0; b < size(); ++b) {
      const std::array<double, 4> limit = plastic->yield_limits(radius[b]);
      for (std::size_t mode = 0; mode < 4; ++mode)
        constants.yield_limit[mode][b] = limit[mode];
    }
  }
  std::size_t with_dampers = 0;
  for (std::size_t b = 0; b < size(); ++b) {
    breakable = breakable || std::isfinite(tensile_strength[b]) || std::isfinite(shear_strength[b]);
    with_dampers += damping_ratio[b] > 0.0;
    const auto i = static_cast<std::size_t>(first[b]), j = static_cast<std::size_t>(second[b]);
    const double ri = state.radius[i], rj = state.radius[j];
    constants.arm[0][b] = ri / (ri + rj), constants.arm[1][b] = rj / (ri + rj);
    const double spring[4] = {normal_spring[b], shear_spring[b], twist_spring[b], bend_spring[b]};
    const std::array<double, 4> damper = bond_damper_coefficients(*this, b, state);
    for (std::size_t mode = 0; mode < 4; ++mode) {
      constants.spring[mode][b] = spring[mode];
      constants.damping[mode][b] = damper[mode];
    }
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
  const std::size_t b = bonds.history.size();
  bonds.history.resize(b + 1);
  bonds.history.length[b] =
      centre_distance(s, static_cast<std::size_t>(i), static_cast<std::size_t>(j));
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
  bonds.model = parameters.model;
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

// The arrays of a BondSet that the bond loop reads and writes, from one bond on: the history,
// the constants and the results (bonds.hpp). Each is distinct (a vector of its own), which
// restrict tells the compiler: passed by value, the blocks load and store them as vectors
// without checks for overlap. (GCC takes restrict from named members, not from arrays of them.)
struct BondArrays {
  double* __restrict length;
  double* __restrict normal_force;
  double* __restrict shear_x;
  double* __restrict shear_y;
  double* __restrict shear_z;
  double* __restrict twist_moment;
  double* __restrict bend_x;
  double* __restrict bend_y;
  double* __restrict bend_z;
  const double* __restrict arm_first;
  const double* __restrict arm_second;
  const double* __restrict normal_spring;
  const double* __restrict shear_spring;
  const double* __restrict twist_spring;
  const double* __restrict bend_spring;
  const double* __restrict normal_damping;
  const double* __restrict shear_damping;
  const double* __restrict twist_damping;
  const double* __restrict bend_damping;
  double* __restrict force_x;
  double* __restrict force_y;
  double* __restrict force_z;
  double* __restrict torque_first_x;
  double* __restrict torque_first_y;
  double* __restrict torque_first_z;
  double* __restrict torque_second_x;
  double* __restrict torque_second_y;
  double* __restrict torque_second_z;
  double* __restrict separation_force;

  explicit BondArrays(BondSet& bonds)
      : length(bonds.history.length.data()),
        normal_force(bonds.history.normal_force.data()),
        shear_x(bonds.history.shear_force.x.data()),
        shear_y(bonds.history.shear_force.y.data()),
        shear_z(bonds.history.shear_force.z.data()),
        twist_moment(bonds.history.twist_moment.data()),
        bend_x(bonds.history.bend_moment.x.data()),
        bend_y(bonds.history.bend_moment.y.data()),
        bend_z(bonds.history.bend_moment.z.data()),
        arm_first(bonds.constants.arm[0].data()),
        arm_second(bonds.constants.arm[1].data()),
        normal_spring(bonds.constants.spring[0].data()),
        shear_spring(bonds.constants.spring[1].data()),
        twist_spring(bonds.constants.spring[2].data()),
        bend_spring(bonds.constants.spring[3].data()),
        normal_damping(bonds.constants.damping[0].data()),
        shear_damping(bonds.constants.damping[1].data()),
        twist_damping(bonds.constants.damping[2].data()),
        bend_damping(bonds.constants.damping[3].data()),
        force_x(bonds.result.force.x.data()),
        force_y(bonds.result.force.y.data()),
        force_z(bonds.result.force.z.data()),
        torque_first_x(bonds.result.torque[0].x.data()),
        torque_first_y(bonds.result.torque[0].y.data()),
        torque_first_z(bonds.result.torque[0].z.data()),
        torque_second_x(bonds.result.torque[1].x.data()),
        torque_second_y(bonds.result.torque[1].y.data()),
        torque_second_z(bonds.result.torque[1].z.data()),
        separation_force(bonds.result.separation_force.data()) {}

  // The same arrays from bond b on.
  BondArrays from(std::int64_t b) const {
    BondArrays a = *this;
    for (double* __restrict* p :
         {&a.length, &a.normal_force, &a.shear_x, &a.shear_y, &a.shear_z, &a.twist_moment,
          &a.bend_x, &a.bend_y, &a.bend_z, &a.force_x, &a.force_y, &a.force_z, &a.torque_first_x,
          &a.torque_first_y, &a.torque_first_z, &a.torque_second_x, &a.torque_second_y,
          &a.torque_second_z, &a.separation_force})
      *p += b;
    for (const double* __restrict* p :
         {&a.arm_first, &a.arm_second, &a.normal_spring, &a.shear_spring, &a.twist_spring,
          &a.bend_spring, &a.normal_damping, &a.shear_damping, &a.twist_damping, &a.bend_damping})
      *p += b;
    return a;
  }
  BondSprings springs(std::int64_t b) const {
    return {length[b],
            normal_force[b],
            {shear_x[b], shear_y[b], shear_z[b]},
            twist_moment[b],
            {bend_x[b], bend_y[b], bend_z[b]}};
  }
  void store(std::int64_t b, const BondSprings& h) const {
    length[b] = h.length, normal_force[b] = h.fn, twist_moment[b] = h.mt;
    shear_x[b] = h.fs[0], shear_y[b] = h.fs[1], shear_z[b] = h.fs[2];
    bend_x[b] = h.mb[0], bend_y[b] = h.mb[1], bend_z[b] = h.mb[2];
  }
};

// The bond's force on `second` and the torques on its ends from its springs, with the dampers
// `damping` (normal, shear, twist, bending) on the predicted end-of-step motion `predicted`, as
// the contact law's (forces.cpp). `separation`: x_second - x_first.
struct BondResult {
  double force[3], torque_first[3], torque_second[3], separation_force;
};
template <bool damped>
[[gnu::always_inline]] inline void bond_result(BondResult& out, const BondSprings& h,
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

inline void store_result(const BondArrays& a, std::int64_t b, const BondResult& out) {
  a.force_x[b] = out.force[0], a.force_y[b] = out.force[1], a.force_z[b] = out.force[2];
  a.torque_first_x[b] = out.torque_first[0], a.torque_first_y[b] = out.torque_first[1];
  a.torque_first_z[b] = out.torque_first[2];
  a.torque_second_x[b] = out.torque_second[0], a.torque_second_y[b] = out.torque_second[1];
  a.torque_second_z[b] = out.torque_second[2];
  a.separation_force[b] = out.separation_force;
}

// A yielding model's arrays for the blocks: per mode its accumulated plastic displacement κ
// (history, read and written) and its limit at κ = 0, and H; as BondArrays, from bond b on.
struct YieldArrays {
  double* __restrict path_normal = nullptr;
  double* __restrict path_shear = nullptr;
  double* __restrict path_twist = nullptr;
  double* __restrict path_bend = nullptr;
  const double* __restrict limit_normal = nullptr;
  const double* __restrict limit_shear = nullptr;
  const double* __restrict limit_twist = nullptr;
  const double* __restrict limit_bend = nullptr;
  double hardening = 0.0;

  YieldArrays() = default;
  explicit YieldArrays(BondSet& bonds)
      : path_normal(bonds.history.model_fields[0].data()),
        path_shear(bonds.history.model_fields[1].data()),
        path_twist(bonds.history.model_fields[2].data()),
        path_bend(bonds.history.model_fields[3].data()),
        limit_normal(bonds.constants.yield_limit[0].data()),
        limit_shear(bonds.constants.yield_limit[1].data()),
        limit_twist(bonds.constants.yield_limit[2].data()),
        limit_bend(bonds.constants.yield_limit[3].data()),
        hardening(bonds.hardening_ratio) {}
  YieldArrays from(std::int64_t b) const {
    YieldArrays y = *this;
    for (double* __restrict* p : {&y.path_normal, &y.path_shear, &y.path_twist, &y.path_bend})
      *p += b;
    for (const double* __restrict* p :
         {&y.limit_normal, &y.limit_shear, &y.limit_twist, &y.limit_bend})
      *p += b;
    return y;
  }
};

// Bonds [begin, end) of compute_bond_forces, one thread's share, one bond at a time: the loop for
// breakable bonds and mixed dampers (the others go through bond_blocks_range).
// An AVX2 clone is picked at load time where the CPU has it: the same scalar IEEE operations (no
// FMA), but three-operand instructions, which spare the register copies of a loop this long.
__attribute__((target_clones("avx2", "default"))) void bond_forces_range(
    BondSet& bonds, const SphereState& s, const double* __restrict motion, const Box& box,
    double increment_dt, std::int64_t begin, std::int64_t end) {
  const BondArrays a(bonds);
  const std::int32_t* __restrict first = bonds.first.data();
  const std::int32_t* __restrict second = bonds.second.data();
  std::uint8_t* __restrict intact = bonds.intact.data();
  const bool periodic_x = box.periodic_x(), periodic_y = box.periodic_y();
  for (std::int64_t b = begin; b < end; ++b) {
    if (!intact[b]) continue;
    const std::size_t i = static_cast<std::size_t>(first[b]);
    const std::size_t j = static_cast<std::size_t>(second[b]);
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
    const double rci = d * a.arm_first[b], rcj = d * a.arm_second[b];
    const BondEnds ends{
        {s.velocity.x[i], s.velocity.y[i], s.velocity.z[i]},
        {s.angular_velocity.x[i], s.angular_velocity.y[i], s.angular_velocity.z[i]},
        {s.velocity.x[j], s.velocity.y[j], s.velocity.z[j]},
        {s.angular_velocity.x[j], s.angular_velocity.y[j], s.angular_velocity.z[j]}};
    BondSprings h = a.springs(b);
    advance_springs(h, d, n, rci, rcj, ends, a.normal_spring[b], a.shear_spring[b],
                    a.twist_spring[b], a.bend_spring[b], increment_dt);
    if (bonds.yields) {
      // Each mode's elastic trial back to its yield limit, which grows with the mode's
      // accumulated plastic displacement (bond_models.hpp, ElasticPlasticBond):
      //   |Fn| ≤ σy A + H kn κn,  |Fs| ≤ τy A + H ks κs,  |Mt| ≤ τy J/R̄ + H kt κt,
      //   |Mb| ≤ σy I/R̄ + H kb κb,
      // the vector modes radially. Before the strength test: a bond breaks on the forces it
      // can carry.
      const auto& limit = bonds.constants.yield_limit;
      const double H = bonds.hardening_ratio;
      auto& kappa = bonds.history.model_fields;
      return_to_yield(h.fn, kappa[0][b], a.normal_spring[b], limit[0][b], H * a.normal_spring[b]);
      return_to_yield(h.fs, kappa[1][b], a.shear_spring[b], limit[1][b], H * a.shear_spring[b]);
      return_to_yield(h.mt, kappa[2][b], a.twist_spring[b], limit[2][b], H * a.twist_spring[b]);
      return_to_yield(h.mb, kappa[3][b], a.bend_spring[b], limit[3][b], H * a.bend_spring[b]);
    }
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
    a.store(b, h);
    BondResult out{};
    if (!intact[b]) {
      store_result(a, b, out);
      continue;
    }
    const double damping[4] = {a.normal_damping[b], a.shear_damping[b], a.twist_damping[b],
                               a.bend_damping[b]};
    if (damping[0] > 0.0) {
      const double* mi = motion + 8 * i;
      const double* mj = motion + 8 * j;
      const BondEnds predicted{{mi[0], mi[1], mi[2]},
                               {mi[3], mi[4], mi[5]},
                               {mj[0], mj[1], mj[2]},
                               {mj[3], mj[4], mj[5]}};
      bond_result<true>(out, h, x, n, rci, rcj, predicted, damping);
    } else {
      bond_result<false>(out, h, x, n, rci, rcj, ends, damping);
    }
    store_result(a, b, out);
  }
}

// Unbreakable bonds over blocks of `bond_block_capacity`, so that the compiler vectorizes
// bond_forces_range's arithmetic across bonds: the ends' positions and motion gathered into a
// block laid out as arrays, then computed lane by lane with the scalar loop's IEEE operations in
// its order (no FMA, no reassociation: the same bits as bond_forces_range,
// tests/unit/simulate/bonds_test.cpp), reading and writing the history, constants and results
// in place. `damped`: every bond has dampers (BondSet::Constants::damping[0] > 0), or none has.
constexpr int bond_block_capacity = 32;

struct alignas(64) BondEndsBlock {
  static constexpr int capacity = bond_block_capacity;
  double dx[capacity], dy[capacity], dz[capacity];
  double vi[3][capacity], vj[3][capacity], wi[3][capacity], wj[3][capacity];
  double mvi[3][capacity], mvj[3][capacity], mwi[3][capacity], mwj[3][capacity];
};

// `a` points at the block's first bond. Its arrays are read and written here in place, not
// through BondArrays' helpers: a member call takes the struct's address, and GCC then no longer
// trusts its restrict and leaves the loop scalar.
template <bool damped, bool yielding>
[[gnu::always_inline]] inline void bond_block_lanes(BondEndsBlock& k, BondArrays a, YieldArrays y,
                                                    int lanes, double increment_dt) {
  for (int l = 0; l < lanes; ++l) {
    const double x[3] = {k.dx[l], k.dy[l], k.dz[l]};
    const double d = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const double inverse_d = 1.0 / d;
    const double n[3] = {x[0] * inverse_d, x[1] * inverse_d, x[2] * inverse_d};
    const double rci = d * a.arm_first[l], rcj = d * a.arm_second[l];
    const BondEnds ends{{k.vi[0][l], k.vi[1][l], k.vi[2][l]},
                        {k.wi[0][l], k.wi[1][l], k.wi[2][l]},
                        {k.vj[0][l], k.vj[1][l], k.vj[2][l]},
                        {k.wj[0][l], k.wj[1][l], k.wj[2][l]}};
    BondSprings h{a.length[l],
                  a.normal_force[l],
                  {a.shear_x[l], a.shear_y[l], a.shear_z[l]},
                  a.twist_moment[l],
                  {a.bend_x[l], a.bend_y[l], a.bend_z[l]}};
    advance_springs(h, d, n, rci, rcj, ends, a.normal_spring[l], a.shear_spring[l],
                    a.twist_spring[l], a.bend_spring[l], increment_dt);
    if constexpr (yielding) {
      const double H = y.hardening;
      return_to_yield(h.fn, y.path_normal[l], a.normal_spring[l], y.limit_normal[l],
                      H * a.normal_spring[l]);
      return_to_yield(h.fs, y.path_shear[l], a.shear_spring[l], y.limit_shear[l],
                      H * a.shear_spring[l]);
      return_to_yield(h.mt, y.path_twist[l], a.twist_spring[l], y.limit_twist[l],
                      H * a.twist_spring[l]);
      return_to_yield(h.mb, y.path_bend[l], a.bend_spring[l], y.limit_bend[l],
                      H * a.bend_spring[l]);
    }
    a.length[l] = h.length, a.normal_force[l] = h.fn, a.twist_moment[l] = h.mt;
    a.shear_x[l] = h.fs[0], a.shear_y[l] = h.fs[1], a.shear_z[l] = h.fs[2];
    a.bend_x[l] = h.mb[0], a.bend_y[l] = h.mb[1], a.bend_z[l] = h.mb[2];
    BondResult out;
    if constexpr (damped) {
      const double damping[4] = {a.normal_damping[l], a.shear_damping[l], a.twist_damping[l],
                                 a.bend_damping[l]};
      const BondEnds predicted{{k.mvi[0][l], k.mvi[1][l], k.mvi[2][l]},
                               {k.mwi[0][l], k.mwi[1][l], k.mwi[2][l]},
                               {k.mvj[0][l], k.mvj[1][l], k.mvj[2][l]},
                               {k.mwj[0][l], k.mwj[1][l], k.mwj[2][l]}};
      bond_result<true>(out, h, x, n, rci, rcj, predicted, damping);
    } else {
      const double none[4] = {0.0, 0.0, 0.0, 0.0};
      bond_result<false>(out, h, x, n, rci, rcj, ends, none);
    }
    a.force_x[l] = out.force[0], a.force_y[l] = out.force[1], a.force_z[l] = out.force[2];
    a.torque_first_x[l] = out.torque_first[0], a.torque_first_y[l] = out.torque_first[1];
    a.torque_first_z[l] = out.torque_first[2];
    a.torque_second_x[l] = out.torque_second[0], a.torque_second_y[l] = out.torque_second[1];
    a.torque_second_z[l] = out.torque_second[2];
    a.separation_force[l] = out.separation_force;
  }
}

// The clones are plain functions: GCC does not vectorize a function template's clones.
__attribute__((target_clones("avx2", "default"))) void bond_block_forces_damped(
    BondEndsBlock& k, BondArrays a, int lanes, double increment_dt) {
  bond_block_lanes<true, false>(k, a, YieldArrays{}, lanes, increment_dt);
}
__attribute__((target_clones("avx2", "default"))) void bond_block_forces_undamped(
    BondEndsBlock& k, BondArrays a, int lanes, double increment_dt) {
  bond_block_lanes<false, false>(k, a, YieldArrays{}, lanes, increment_dt);
}
__attribute__((target_clones("avx2", "default"))) void bond_block_forces_damped_yielding(
    BondEndsBlock& k, BondArrays a, YieldArrays y, int lanes, double increment_dt) {
  bond_block_lanes<true, true>(k, a, y, lanes, increment_dt);
}
__attribute__((target_clones("avx2", "default"))) void bond_block_forces_undamped_yielding(
    BondEndsBlock& k, BondArrays a, YieldArrays y, int lanes, double increment_dt) {
  bond_block_lanes<false, true>(k, a, y, lanes, increment_dt);
}

// d -= L nearbyint(d / L), the scalar loop's nearest image, calling nearbyint only for the few
// bonds across the boundary: for |d| <= L/2 the quotient rounds to a zero of d's sign, and
// subtracting L times it is d + 0 (which turns -0 into +0 as the subtraction does).
inline void wrap_to_nearest_image(double* d, int lanes, double length) {
  const double half = 0.5 * length;
  for (int l = 0; l < lanes; ++l)
    d[l] = std::fabs(d[l]) > half ? d[l] - length * std::nearbyint(d[l] / length) : d[l] + 0.0;
}

// Bonds [begin, end) as bond_forces_range computes them, for unbreakable bonds all damped or all
// undamped: the ends gathered into a block, then bond_block_forces.
template <bool damped, bool yielding>
void bond_blocks_range(BondSet& bonds, const SphereState& s, const double* __restrict motion,
                       const Box& box, double increment_dt, std::int64_t begin, std::int64_t end) {
  const BondArrays arrays(bonds);
  const YieldArrays yields(bonds);
  const std::int32_t* __restrict first = bonds.first.data();
  const std::int32_t* __restrict second = bonds.second.data();
  const bool periodic_x = box.periodic_x(), periodic_y = box.periodic_y();
  // One pass per quantity: with every sphere array at once the copy ran out of registers and
  // reloaded their addresses for each bond.
  const double *__restrict x = s.position.x.data(), *__restrict y = s.position.y.data(),
                           *__restrict z = s.position.z.data();
  const double *__restrict vx = s.velocity.x.data(), *__restrict vy = s.velocity.y.data(),
                           *__restrict vz = s.velocity.z.data();
  const double *__restrict wx = s.angular_velocity.x.data(),
                           *__restrict wy = s.angular_velocity.y.data(),
                           *__restrict wz = s.angular_velocity.z.data();
  BondEndsBlock k;
  for (std::int64_t b0 = begin; b0 < end; b0 += BondEndsBlock::capacity) {
    const int lanes = static_cast<int>(std::min<std::int64_t>(BondEndsBlock::capacity, end - b0));
    const std::int32_t* __restrict is = first + b0;
    const std::int32_t* __restrict js = second + b0;
    for (int l = 0; l < lanes; ++l) {
      const std::int32_t i = is[l], j = js[l];
      k.dx[l] = x[j] - x[i], k.dy[l] = y[j] - y[i], k.dz[l] = z[j] - z[i];
    }
    if (periodic_x) wrap_to_nearest_image(k.dx, lanes, box.length_x);
    if (periodic_y) wrap_to_nearest_image(k.dy, lanes, box.length_y);
    for (int l = 0; l < lanes; ++l) {
      const std::int32_t i = is[l], j = js[l];
      k.vi[0][l] = vx[i], k.vi[1][l] = vy[i], k.vi[2][l] = vz[i];
      k.vj[0][l] = vx[j], k.vj[1][l] = vy[j], k.vj[2][l] = vz[j];
    }
    for (int l = 0; l < lanes; ++l) {
      const std::int32_t i = is[l], j = js[l];
      k.wi[0][l] = wx[i], k.wi[1][l] = wy[i], k.wi[2][l] = wz[i];
      k.wj[0][l] = wx[j], k.wj[1][l] = wy[j], k.wj[2][l] = wz[j];
    }
    if constexpr (damped)
      for (int l = 0; l < lanes; ++l) {
        const double* __restrict mi = motion + 8 * is[l];
        const double* __restrict mj = motion + 8 * js[l];
        for (int c = 0; c < 3; ++c) {
          k.mvi[c][l] = mi[c], k.mwi[c][l] = mi[3 + c];
          k.mvj[c][l] = mj[c], k.mwj[c][l] = mj[3 + c];
        }
      }
    const BondArrays a = arrays.from(b0);
    if constexpr (yielding) {
      const YieldArrays y = yields.from(b0);
      if constexpr (damped)
        bond_block_forces_damped_yielding(k, a, y, lanes, increment_dt);
      else
        bond_block_forces_undamped_yielding(k, a, y, lanes, increment_dt);
    } else if constexpr (damped) {
      bond_block_forces_damped(k, a, lanes, increment_dt);
    } else {
      bond_block_forces_undamped(k, a, lanes, increment_dt);
    }
  }
}

// Bonds [begin, end) by blocks where every bond is intact and unbreakable and the dampers are
// uniform (elastic or yielding); else the scalar loop.
void bond_forces_of(BondSet& bonds, const SphereState& s, const double* motion, const Box& box,
                    double increment_dt, std::int64_t begin, std::int64_t end) {
  if (bonds.breakable || bonds.damping_mix)
    bond_forces_range(bonds, s, motion, box, increment_dt, begin, end);
  else if (bonds.yields && bonds.damped)
    bond_blocks_range<true, true>(bonds, s, motion, box, increment_dt, begin, end);
  else if (bonds.yields)
    bond_blocks_range<false, true>(bonds, s, motion, box, increment_dt, begin, end);
  else if (bonds.damped)
    bond_blocks_range<true, false>(bonds, s, motion, box, increment_dt, begin, end);
  else
    bond_blocks_range<false, false>(bonds, s, motion, box, increment_dt, begin, end);
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
  const BondSet::History& h = bonds.history;
  const auto square = [](const Vec3Array& v, std::size_t b) {
    return v.x[b] * v.x[b] + v.y[b] * v.y[b] + v.z[b] * v.z[b];
  };
  double e = 0.0;
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    if (!bonds.intact[b]) continue;
    e += 0.5 * h.normal_force[b] * h.normal_force[b] / bonds.normal_spring[b] +
         0.5 * square(h.shear_force, b) / bonds.shear_spring[b] +
         0.5 * h.twist_moment[b] * h.twist_moment[b] / bonds.twist_spring[b] +
         0.5 * square(h.bend_moment, b) / bonds.bend_spring[b];
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
    const double ri = state.radius[i], rj = state.radius[j], d = bonds.history.length[b];
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
  bonds.model = parameters.model;
  for (std::size_t b = 0; b < pairs.size(); ++b) {
    const auto [i, j] = pairs[b];
    if (i < 0 || j <= i || j >= n || (b > 0 && !(pairs[b - 1] < pairs[b])))
      throw InputError(fmt::format(
          "bond {} joins spheres {} and {}: pairs must be i < j < {} and sorted", b, i, j, n));
    if (!(rest_length[b] > 0.0 && std::isfinite(rest_length[b])))
      throw InputError(fmt::format("bond {}: rest length {} must be > 0", b, rest_length[b]));
    add_bond(bonds, state, i, j, parameters);
    bonds.history.normal_force[b] =
        bonds.normal_spring.back() * (rest_length[b] - bonds.history.length[b]);
  }
  bonds.index(state);
  return bonds;
}

}  // namespace shapepress::simulate
