// The parallel bond on two sub-spheres, against its formulas (models.md "Bonded multi-sphere"):
// each mode's spring, rotation with the bond, breakage, energy, and Eq. 10 creation with its
// refusals.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "common/error.hpp"
#include "simulate/bonds.hpp"
#include "simulate/engine.hpp"
#include "simulate/timestep.hpp"
#include "tests/unit/simulate/random_motion.hpp"

namespace shapepress::simulate {
namespace {

using ::testing::HasSubstr;

constexpr double r = 1e-3;  // sub-sphere radius
constexpr double rho = 2000.0;
constexpr double kn_bar = 1e10;  // N/m^3
constexpr double ks_bar = 0.5e10;

BondParameters stiff() {
  BondParameters p;
  p.normal_stiffness = kn_bar;
  p.shear_stiffness = ks_bar;
  return p;
}

// Two sub-spheres of one particle along x, touching by default; 2.01 r apart they are bonded
// by Eq. 10 without touching: a free oscillator of the bond alone.
SphereState pair_state(double centre_distance = 2 * r) {
  SphereState s;
  s.add_sphere(0.0, 0.0, 0.0, r, rho, 0);
  s.add_sphere(centre_distance, 0.0, 0.0, r, rho, 0);
  s.body = {0, 0};
  return s;
}

std::vector<double> still_motion(const SphereState& s) {
  std::vector<double> motion(8 * s.size(), 0.0);
  for (std::size_t i = 0; i < s.size(); ++i)
    motion[8 * i + 6] = s.mass[i], motion[8 * i + 7] = s.inverse_inertia[i];
  return motion;
}

const double area = std::numbers::pi * r * r;
const double polar = 0.5 * std::numbers::pi * r * r * r * r;

TEST(Bonds, NormalSpringIsKnTimesAreaOnTheChangeOfLength) {
  SphereState s = pair_state();
  BondSet bonds = create_bonds(s, 1.15, stiff());
  ASSERT_EQ(bonds.size(), 1u);
  const std::vector<double> motion = still_motion(s);
  const double stretch = 1e-6;
  s.position.x[1] += stretch;  // pulled apart: tension pulls sphere 1 back (-x)
  compute_bond_forces(bonds, s, motion.data(), Box{}, 1e-6, false);
  EXPECT_NEAR(bonds.result.at(0).force[0], -kn_bar * area * stretch,
              1e-9 * kn_bar * area * stretch);
  EXPECT_DOUBLE_EQ(bonds.result.at(0).force[1], 0.0);
  // Incremental: a second step with the same length adds nothing.
  compute_bond_forces(bonds, s, motion.data(), Box{}, 1e-6, false);
  EXPECT_NEAR(bonds.result.at(0).force[0], -kn_bar * area * stretch,
              1e-9 * kn_bar * area * stretch);
}

TEST(Bonds, ShearTwistAndBendingSpringsAct) {
  SphereState s = pair_state();
  BondSet bonds = create_bonds(s, 1.15, stiff());
  const std::vector<double> motion = still_motion(s);
  const double dt = 1e-6, v = 0.01, w = 2.0;
  s.velocity.y[1] = v;          // shear along y
  s.angular_velocity.x[1] = w;  // twist about the bond axis
  s.angular_velocity.z[1] = w;  // bending about z
  compute_bond_forces(bonds, s, motion.data(), Box{}, dt, false);
  const BondSet::Results::Record out = bonds.result.at(0);
  // The bond centre of sphere 1 moves at v_y + (ω × (-r n))_y = v + r ω_z... the shear
  // displacement of the bond centre: (v - r ωz·(+1)) since ω × (-r x̂) = -r (ω_z ŷ - ω_y ẑ).
  const double shear_velocity = v - r * w;
  EXPECT_NEAR(bonds.history.at(0).shear_force[1], -ks_bar * area * shear_velocity * dt, 1e-15);
  EXPECT_NEAR(bonds.history.at(0).twist_moment, -ks_bar * polar * w * dt, 1e-20);
  EXPECT_NEAR(bonds.history.at(0).bend_moment[2], -kn_bar * 0.5 * polar * w * dt, 1e-20);
  // Equal and opposite forces; the torques balance the couple of the shear force about the
  // centres: τ1 + τ2 + (x2 - x1) × F2 = 0.
  const double couple_z = 2 * r * out.force[1];
  EXPECT_NEAR(out.torque_first[2] + out.torque_second[2] + couple_z, 0.0, 1e-18);
  EXPECT_NEAR(out.torque_first[0] + out.torque_second[0], 0.0, 1e-20);
}

TEST(Bonds, ShearForceTurnsWithTheBond) {
  SphereState s = pair_state();
  BondSet bonds = create_bonds(s, 1.15, stiff());
  const std::vector<double> motion = still_motion(s);
  bonds.history.shear_force.y[0] = 3.0;
  // The pair turned by 2° about z: the shear force keeps its length and lies in the new plane
  // normal to the bond.
  const double angle = 2.0 * std::numbers::pi / 180.0;
  s.position.x[1] = 2 * r * std::cos(angle);
  s.position.y[1] = 2 * r * std::sin(angle);
  compute_bond_forces(bonds, s, motion.data(), Box{}, 1e-6, false);
  const double fx = bonds.history.at(0).shear_force[0], fy = bonds.history.at(0).shear_force[1],
               fz = bonds.history.at(0).shear_force[2];
  EXPECT_NEAR(std::sqrt(fx * fx + fy * fy + fz * fz), 3.0, 1e-12);
  EXPECT_NEAR(fx * std::cos(angle) + fy * std::sin(angle), 0.0, 1e-12);
  EXPECT_NEAR(fx, -3.0 * std::sin(angle), 1e-12);
}

TEST(Bonds, BreakForGoodAtTheTensileStrength) {
  SphereState s = pair_state();
  BondParameters p = stiff();
  p.tensile_strength = 1e5;  // Pa
  BondSet bonds = create_bonds(s, 1.15, p);
  const std::vector<double> motion = still_motion(s);
  const double breaking_stretch = p.tensile_strength / kn_bar;  // σ = k̄n Δ
  s.position.x[1] += 0.9 * breaking_stretch;
  compute_bond_forces(bonds, s, motion.data(), Box{}, 1e-6, false);
  EXPECT_EQ(bonds.intact_count(), 1);
  s.position.x[1] += 0.2 * breaking_stretch;
  compute_bond_forces(bonds, s, motion.data(), Box{}, 1e-6, false);
  EXPECT_EQ(bonds.intact_count(), 0);
  s.position.x[1] -= 1.1 * breaking_stretch;  // back to the start: stays broken
  compute_bond_forces(bonds, s, motion.data(), Box{}, 1e-6, false);
  EXPECT_EQ(bonds.intact_count(), 0);
  EXPECT_EQ(bonds.history.at(0).normal_force, 0.0);
}

TEST(Bonds, FreeOscillationKeepsEnergyAndHasTheSpringPeriod) {
  // Two sub-spheres stretched and let go, no contact (slightly apart), no damping: the normal
  // mode's period is 2π √(m*/kn) and the energy stays put.
  SphereState s = pair_state(2.01 * r);
  BondSet bonds = create_bonds(s, 1.15, stiff());
  const double kn = kn_bar * area, m_eff = 0.5 * s.mass[0];
  const double period = 2 * std::numbers::pi * std::sqrt(m_eff / kn);
  const double dt = period / 200;
  s.position.x[1] += 1e-6;
  MaterialTable table({{"m", 1e7, 0.3, rho}}, {{"m", "m", 0.7, 0.5}});
  Engine engine(std::move(s), Box{}, table, {}, EngineSettings{dt, {0, 0, 0}, 0.2 * r}, bonds);
  const double e0 = engine.energy().elastic + engine.energy().kinetic;
  EXPECT_NEAR(e0, 0.5 * kn * 1e-12, 1e-6 * 0.5 * kn * 1e-12);
  // Count zero crossings of the stretch over 10 periods.
  int crossings = 0;
  double last = 1.0;
  for (int k = 0; k < 2000; ++k) {
    engine.step();
    const double stretch = engine.state().position.x[1] - engine.state().position.x[0] - 2.01 * r;
    if (stretch * last < 0.0) ++crossings;
    last = stretch;
    const EnergySummary e = engine.energy();
    ASSERT_NEAR(e.elastic + e.kinetic, e0, 1e-3 * e0) << "step " << k;
  }
  EXPECT_EQ(crossings, 20);  // two per period
}

TEST(Bonds, OscillationPeriodBoundIsBelowThePairsPeriod) {
  SphereState s = pair_state();
  const BondSet bonds = create_bonds(s, 1.15, stiff());
  const double kn = kn_bar * area, m_eff = 0.5 * s.mass[0];
  const double bound = bond_oscillation_period(bonds, s);
  EXPECT_LE(bound, 2 * std::numbers::pi * std::sqrt(m_eff / kn));
  EXPECT_GT(bound, 0.0);
  MaterialTable table({{"m", 1e7, 0.3, rho}}, {{"m", "m", 0.7, 0.5}});
  const TimeStepChoice dt = select_time_step(s, table, {}, std::nullopt, 0.2, 0.1, bonds);
  EXPECT_LE(dt.time_step, 0.2 * bound * (1 + 1e-12));
  // A fixed step beyond Verlet's stability limit is refused.
  EXPECT_THROW(select_time_step(s, table, {}, bound, 0.2, 0.1, bonds), InputError);
}

TEST(Bonds, ABondedPairWithoutTheContactLawMayOverlapDeepButNotPassThrough) {
  // contact_when_bonded = false: a bonded pair is one elastic body, so an overlap of 0.9 r (its
  // bond pressed to 0.55 of its touching length) is a strain, not a divergence; the contact
  // check's 0.5 r holds for pairs that touch through the contact law. Centres within a fifth of
  // the radii sum are.
  const MaterialTable table({{"m", 1e7, 0.3, rho}}, {{"m", "m", 0.7, 0.5}});
  const auto engine = [&](double distance, bool contact_when_bonded) {
    SphereState s = pair_state(distance);
    BondParameters p = stiff();
    p.contact_when_bonded = contact_when_bonded;
    BondSet bonds = create_bonds(s, 1.15, p);
    return Engine(std::move(s), Box{}, table, {}, EngineSettings{1e-9, {0, 0, 0}, 0.1 * r},
                  std::move(bonds));
  };
  EXPECT_NO_THROW(engine(1.1 * r, false).check_divergence());
  EXPECT_THROW(engine(1.1 * r, true).check_divergence(), ComputationError);
  try {
    engine(0.35 * r, false).check_divergence();
    FAIL() << "a bonded pair 0.35 r apart is not caught";
  } catch (const ComputationError& error) {
    EXPECT_THAT(error.what(), HasSubstr("bonded spheres 0 and 1"));
  }
}

TEST(Bonds, CreatedOnlyWithinOneParticleByEq10) {
  SphereState s;
  s.add_sphere(0.0, 0.0, 0.0, r, rho, 0);
  s.add_sphere(2 * r, 0.0, 0.0, r, rho, 0);
  s.add_sphere(4.2 * r, 0.0, 0.0, r, rho, 0);  // 2.2 r from sphere 1: within m_b = 1.15
  s.add_sphere(6.2 * r, 0.0, 0.0, r, rho, 0);  // touching sphere 2 but another particle
  s.add_sphere(6.2 * r, 2 * r, 0.0, r, rho, 0);
  s.body = {0, 0, 0, 1, 1};
  const BondSet bonds = create_bonds(s, 1.15, stiff());
  ASSERT_EQ(bonds.size(), 3u);
  EXPECT_EQ(bonds.first, (std::vector<std::int32_t>{0, 1, 3}));
  EXPECT_EQ(bonds.second, (std::vector<std::int32_t>{1, 2, 4}));
  // m_b = 1.05 leaves sphere 2 of particle 0 without a bond: refused, naming the particle.
  try {
    create_bonds(s, 1.05, stiff(), {"grain-a", "grain-b"});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("particle 'grain-a'"));
    EXPECT_THAT(e.what(), HasSubstr("sub-sphere 2"));
  }
}

TEST(Bonds, BadParametersAreInputErrors) {
  const SphereState s = pair_state();
  EXPECT_THROW(create_bonds(s, 1.0, stiff()), InputError);  // m_b <= 1
  EXPECT_THROW(create_bonds(s, 0.9, stiff()), InputError);
  BondParameters p = stiff();
  p.normal_stiffness = -1e6;
  try {
    create_bonds(s, 1.15, p);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("normal stiffness"));
  }
  p = stiff();
  p.shear_stiffness = 0.0;
  EXPECT_THROW(create_bonds(s, 1.15, p), InputError);
  p = stiff();
  p.radius_multiplier = 0.0;
  EXPECT_THROW(create_bonds(s, 1.15, p), InputError);
}

TEST(Bonds, ModulusFormKeepsTheBondModulusForAnySubSphereSize) {
  // k̄n = Ē/(ri + rj): the axial stiffness per length, kn·L/A, equals Ē for any radius.
  for (double radius : {0.5e-3, 2e-3}) {
    SphereState s;
    s.add_sphere(0.0, 0.0, 0.0, radius, rho, 0);
    s.add_sphere(2 * radius, 0.0, 0.0, radius, rho, 0);
    s.body = {0, 0};
    BondParameters p;
    p.modulus = 5e6;
    p.shear_ratio = 0.4;
    const BondSet bonds = create_bonds(s, 1.15, p);
    const double a = std::numbers::pi * radius * radius;
    EXPECT_NEAR(bonds.normal_spring[0] * 2 * radius / a, 5e6, 1e-6);
    EXPECT_NEAR(bonds.shear_spring[0] / bonds.normal_spring[0], 0.4, 1e-12);
  }
}

}  // namespace
}  // namespace shapepress::simulate

namespace shapepress::simulate {
namespace {

TEST(Bonds, EveryModeKeepsEnergyWithoutDamping) {
  // Shear, twist and bending excited together on a free pair: a sign slip in any mode's spring or
  // torque shows up as energy growing without bound.
  SphereState s = pair_state(2.01 * r);
  BondSet bonds = create_bonds(s, 1.15, stiff());
  s.velocity.y[1] = 1e-3;
  s.velocity.z[0] = -0.5e-3;
  s.angular_velocity.x[1] = 0.7;
  s.angular_velocity.y[0] = -0.4;
  s.angular_velocity.z[1] = 0.9;
  MaterialTable table({{"m", 1e7, 0.3, rho}}, {{"m", "m", 0.7, 0.5}});
  const double dt = 0.1 * bond_oscillation_period(bonds, s);
  Engine engine(std::move(s), Box{}, table, {}, EngineSettings{dt, {0, 0, 0}, 0.2 * r}, bonds);
  const double e0 = engine.energy().elastic + engine.energy().kinetic;
  for (int k = 0; k < 5000; ++k) {
    engine.step();
    const EnergySummary e = engine.energy();
    ASSERT_NEAR(e.elastic + e.kinetic, e0, 0.02 * e0) << "step " << k;
  }
}

TEST(LocalDamping, EachSwingKeepsOneMinusAlphaOverOnePlusAlphaOfTheEnergy) {
  // Cundall's local damping (engine.hpp, P&C 2004 §2.1.4) on the free stretched pair: a sphere
  // moving towards balance gains (1 − α) of the work, moving away pays (1 + α), so each swing's
  // peak elastic energy is (1 − α)/(1 + α) of the last, whatever the potential. Undamped (α = 0)
  // the peaks stay put (FreeOscillationKeepsEnergyAndHasTheSpringPeriod).
  constexpr double alpha = 0.3;
  SphereState s = pair_state(2.01 * r);
  BondSet bonds = create_bonds(s, 1.15, stiff());
  const double kn = kn_bar * area, m_eff = 0.5 * s.mass[0];
  const double period = 2 * std::numbers::pi * std::sqrt(m_eff / kn);
  s.position.x[1] += 1e-6;
  MaterialTable table({{"m", 1e7, 0.3, rho}}, {{"m", "m", 0.7, 0.5}});
  EngineSettings settings{period / 400, {0, 0, 0}, 0.2 * r};
  settings.local_damping = alpha;
  Engine engine(std::move(s), Box{}, table, {}, settings, bonds);
  // Peak elastic energy of each half period (one swing from a turning point to the next).
  std::vector<double> peaks = {engine.energy().elastic};
  double peak = 0.0, last = 1.0;
  for (int k = 0; k < 400 * 3; ++k) {
    engine.step();
    const double stretch = engine.state().position.x[1] - engine.state().position.x[0] - 2.01 * r;
    if (stretch * last < 0.0) peaks.push_back(peak), peak = 0.0;  // a new swing begins
    peak = std::max(peak, engine.energy().elastic);
    if (stretch != 0.0) last = stretch;
  }
  ASSERT_GE(peaks.size(), 5u);
  // Crossings split the swings at the balance point: each recorded peak after the first is the
  // turning point that ends the swing before it.
  for (std::size_t k = 2; k < peaks.size(); ++k)
    EXPECT_NEAR(peaks[k] / peaks[k - 1], (1 - alpha) / (1 + alpha), 0.02) << "swing " << k;
  // A damping of 1 or more would cancel or reverse the restoring force: refused.
  settings.local_damping = 1.0;
  SphereState t = pair_state();
  EXPECT_THROW(Engine(t, Box{}, table, {}, settings, create_bonds(t, 1.15, stiff())), InputError);
}

}  // namespace
}  // namespace shapepress::simulate

namespace shapepress::simulate {
namespace {

using Vec = std::array<double, 3>;

Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec& a, const Vec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
double norm(const Vec& a) {
  return std::sqrt(dot(a, a));
}
Vec unit(const Vec& a) {
  return {a[0] / norm(a), a[1] / norm(a), a[2] / norm(a)};
}
// Rodrigues: v turned by `angle` about the unit `axis`.
Vec turned(const Vec& v, const Vec& axis, double angle) {
  const Vec k = cross(axis, v);
  const double c = std::cos(angle), s = std::sin(angle), along = dot(axis, v) * (1 - c);
  return {v[0] * c + k[0] * s + axis[0] * along, v[1] * c + k[1] * s + axis[1] * along,
          v[2] * c + k[2] * s + axis[2] * along};
}
Vec position(const SphereState& s, std::size_t i) {
  return {s.position.x[i], s.position.y[i], s.position.z[i]};
}

// Loads every bond of `bonds` with a normal force, a twist moment, and a shear force and a
// bending moment normal to it (in different directions, different per bond), as a bed leaves
// them; then evaluates once without increments so `result` holds the loaded bond's forces.
void load_bonds(BondSet& bonds, const SphereState& s, const std::vector<double>& motion) {
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    const Vec n = unit({s.position.x[bonds.second[b]] - s.position.x[bonds.first[b]],
                        s.position.y[bonds.second[b]] - s.position.y[bonds.first[b]],
                        s.position.z[bonds.second[b]] - s.position.z[bonds.first[b]]});
    const Vec e1 = unit(cross(n, {0.3, -0.5, 0.8}));
    const Vec e2 = cross(n, e1);
    const double k = static_cast<double>(b) + 1.0;
    BondSet::History& h = bonds.history;
    h.normal_force[b] = 5.0 * k;
    h.twist_moment[b] = 2e-3 * k;
    const Vec shear = {3.0 * k * (0.6 * e1[0] + 0.8 * e2[0]), 3.0 * k * (0.6 * e1[1] + 0.8 * e2[1]),
                       3.0 * k * (0.6 * e1[2] + 0.8 * e2[2])};
    const Vec bend = {1e-3 * k * (0.8 * e1[0] - 0.6 * e2[0]),
                      1e-3 * k * (0.8 * e1[1] - 0.6 * e2[1]),
                      1e-3 * k * (0.8 * e1[2] - 0.6 * e2[2])};
    h.shear_force.x[b] = shear[0], h.shear_force.y[b] = shear[1], h.shear_force.z[b] = shear[2];
    h.bend_moment.x[b] = bend[0], h.bend_moment.y[b] = bend[1], h.bend_moment.z[b] = bend[2];
  }
  compute_bond_forces(bonds, s, motion.data(), Box{}, 0.0, true);
}

// The spheres of `s` turned rigidly by `angle` about `axis` through `centre` in `steps` steps at
// a steady spin ω: each step the positions on the exact turn, v = ω × (x - c) and the spin ω for
// every sphere (what a rigid body's integrator leaves), the bond forces evaluated, their dampers
// fed the same motion.
void turn_rigidly(BondSet& bonds, SphereState& s, const Vec& axis, const Vec& centre, double angle,
                  int steps) {
  const double dt = 1e-6, rate = angle / (steps * dt);
  const Vec spin = {rate * axis[0], rate * axis[1], rate * axis[2]};
  std::vector<Vec> start(s.size());
  for (std::size_t i = 0; i < s.size(); ++i)
    start[i] = {position(s, i)[0] - centre[0], position(s, i)[1] - centre[1],
                position(s, i)[2] - centre[2]};
  std::vector<double> motion(8 * s.size(), 0.0);
  for (int k = 1; k <= steps; ++k) {
    for (std::size_t i = 0; i < s.size(); ++i) {
      const Vec arm = turned(start[i], axis, angle * k / steps);
      const Vec v = cross(spin, arm);
      s.position.x[i] = centre[0] + arm[0], s.position.y[i] = centre[1] + arm[1];
      s.position.z[i] = centre[2] + arm[2];
      s.velocity.x[i] = v[0], s.velocity.y[i] = v[1], s.velocity.z[i] = v[2];
      s.angular_velocity.x[i] = spin[0], s.angular_velocity.y[i] = spin[1];
      s.angular_velocity.z[i] = spin[2];
      for (int c = 0; c < 3; ++c)
        motion[8 * i + c] = v[c], motion[8 * i + 3 + c] = spin[c];
      motion[8 * i + 6] = s.mass[i], motion[8 * i + 7] = s.inverse_inertia[i];
    }
    compute_bond_forces(bonds, s, motion.data(), Box{}, dt, false);
  }
}

// After a rigid turn R, each bond's normal force and twist moment are unchanged, its shear force
// and bending moment are R of what they were, and so are the forces and torques it applies.
// `tolerance` is relative to each vector's length.
void expect_turned_with_the_bodies(const BondSet& before, const BondSet& after, const Vec& axis,
                                   double angle, double tolerance) {
  const auto vec = [](const double v[3]) { return Vec{v[0], v[1], v[2]}; };
  // Fs and Mb each keep their length to rounding whatever the turn; a sum of them (a torque)
  // keeps it to the tolerance, which bounds the drift between their directions.
  const auto expect_near = [&](const Vec& got, const Vec& was, const char* what, std::size_t b,
                               bool history = false) {
    const Vec want = turned(was, axis, angle);
    EXPECT_NEAR(norm(got), norm(was), (history ? 1e-12 : tolerance) * norm(was))
        << what << " of bond " << b;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(got[c], want[c], tolerance * norm(was)) << what << "[" << c << "] of bond " << b;
  };
  for (std::size_t b = 0; b < before.size(); ++b) {
    const BondSet::History::Record h0 = before.history.at(b), h = after.history.at(b);
    EXPECT_NEAR(h.normal_force, h0.normal_force, 1e-9 * std::fabs(h0.normal_force));
    EXPECT_DOUBLE_EQ(h.twist_moment, h0.twist_moment);
    expect_near(vec(h.shear_force), vec(h0.shear_force), "shear force", b, true);
    expect_near(vec(h.bend_moment), vec(h0.bend_moment), "bending moment", b, true);
    const BondSet::Results::Record r0 = before.result.at(b), r = after.result.at(b);
    expect_near(vec(r.force), vec(r0.force), "force", b);
    expect_near(vec(r.torque_first), vec(r0.torque_first), "torque on first", b);
    expect_near(vec(r.torque_second), vec(r0.torque_second), "torque on second", b);
  }
}

BondParameters damped() {
  BondParameters p = stiff();
  p.damping_ratio = 0.2;  // a damper must not see a rigid turn either
  return p;
}

TEST(BondRotation, APairSpinningAboutItsBondKeepsItsForcesInTheBodies) {
  // The turn about the bond's own axis: n stays put, so only the spin term turns the history.
  // Without it the shear force would stay fixed in space and, seen from the bodies, turn by -φ:
  // a spurious shear of 2 |Fs| sin(φ/2). The turn's angle error, 2θ⁵/15 per step, is far below
  // the tolerance.
  SphereState s = pair_state();
  BondSet bonds = create_bonds(s, 1.15, damped());
  load_bonds(bonds, s, still_motion(s));
  const BondSet before = bonds;
  const double angle = 0.5 * std::numbers::pi;
  turn_rigidly(bonds, s, {1, 0, 0}, {r, 0, 0}, angle, 500);
  expect_turned_with_the_bodies(before, bonds, {1, 0, 0}, angle, 1e-9);
}

TEST(BondRotation, APairTurningAboutANormalAxisKeepsItsForcesInTheBodies) {
  // The bond's axis turns: the history is carried into the new plane each step. That first-order
  // carry keeps lengths exactly but drifts a vector's direction by at most α²/2 per step of
  // angle α (towards the turn's axis), at most φ α/2 over the turn: the tolerance is 2 φ α.
  SphereState s = pair_state();
  BondSet bonds = create_bonds(s, 1.15, damped());
  load_bonds(bonds, s, still_motion(s));
  const BondSet before = bonds;
  const double angle = 1.0;
  const int steps = 2000;
  turn_rigidly(bonds, s, {0, 0, 1}, {r, 0, 0}, angle, steps);
  expect_turned_with_the_bodies(before, bonds, {0, 0, 1}, angle, 2 * angle * angle / steps);
}

TEST(BondRotation, ASmallBondedBodyTurningAboutAnyAxisKeepsItsBondForces) {
  // A tetrahedron of four touching sub-spheres, six loaded bonds at different angles to the
  // turn's axis: each sees a tilt of its axis and a spin about it at once.
  SphereState s;
  const double h = 2 * r * std::sqrt(2.0 / 3.0);
  s.add_sphere(0.0, 0.0, 0.0, r, rho, 0);
  s.add_sphere(2 * r, 0.0, 0.0, r, rho, 0);
  s.add_sphere(r, std::sqrt(3.0) * r, 0.0, r, rho, 0);
  s.add_sphere(r, r / std::sqrt(3.0), h, r, rho, 0);
  s.body = {0, 0, 0, 0};
  BondSet bonds = create_bonds(s, 1.15, damped());
  ASSERT_EQ(bonds.size(), 6u);
  load_bonds(bonds, s, still_motion(s));
  const BondSet before = bonds;
  const Vec axis = unit({1, 2, 3});
  const double angle = 1.0;
  const int steps = 2000;
  turn_rigidly(bonds, s, axis, {r, r / std::sqrt(3.0), h / 4}, angle, steps);
  expect_turned_with_the_bodies(before, bonds, axis, angle, 2 * angle * angle / steps);
}

}  // namespace
}  // namespace shapepress::simulate

namespace shapepress::simulate {
namespace {

TEST(BondSubsteps, WithoutSlowForcesTheyAreTheBondsOwnVerletOnTheSubstep) {
  // A free pair with every bond mode excited and no contact, wall or gravity: n sub-steps of a
  // step Δ are the single-rate run on Δ/n, to rounding.
  const auto excited = [] {
    SphereState s = pair_state(2.01 * r);
    s.velocity.y[1] = 1e-3;
    s.velocity.z[0] = -0.5e-3;
    s.angular_velocity.x[1] = 0.7;
    s.angular_velocity.z[1] = 0.9;
    return s;
  };
  const BondSet bonds = create_bonds(excited(), 1.15, stiff());
  MaterialTable table({{"m", 1e7, 0.3, rho}}, {{"m", "m", 0.7, 0.5}});
  const double h = 0.1 * bond_oscillation_period(bonds, excited());
  const int n = 5;
  EngineSettings single{h, {0, 0, 0}, 0.2 * r};
  EngineSettings substepped{n * h, {0, 0, 0}, 0.2 * r};
  substepped.bond_substeps = n;
  Engine a(excited(), Box{}, table, {}, single, bonds);
  Engine b(excited(), Box{}, table, {}, substepped, bonds);
  for (int k = 0; k < 200; ++k) {
    for (int j = 0; j < n; ++j)
      a.step();
    b.step();
  }
  const SphereState &sa = a.state(), &sb = b.state();
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(sb.position.x[i], sa.position.x[i], 1e-12 * r);
    EXPECT_NEAR(sb.position.y[i], sa.position.y[i], 1e-12 * r);
    EXPECT_NEAR(sb.angular_velocity.x[i], sa.angular_velocity.x[i], 1e-9);
    EXPECT_NEAR(sb.angular_velocity.z[i], sa.angular_velocity.z[i], 1e-9);
    EXPECT_NEAR(sb.force.y[i], sa.force.y[i], 1e-9 * std::fabs(sa.force.y[i]) + 1e-15);
  }
  EXPECT_NEAR(b.time(), a.time(), 1e-12 * a.time());
}

TEST(BondSubsteps, ASubstepAboveTheBondsStabilityLimitIsRefused) {
  SphereState s = pair_state();
  const BondSet bonds = create_bonds(s, 1.15, stiff());
  MaterialTable table({{"m", 1e7, 0.3, rho}}, {{"m", "m", 0.7, 0.5}});
  const double bound = bond_oscillation_period(bonds, s);
  const double limit = bond_stability_step(bonds, s, Box{});
  // A fixed step of 1.8 × the limit takes 2 sub-steps; of 2.2 ×, 2 put each above it.
  EXPECT_NO_THROW(select_time_step(s, table, {}, 1.8 * limit, 0.2, 0.1, bonds, ClumpSet{}, 2));
  try {
    select_time_step(s, table, {}, 2.2 * limit, 0.2, 0.1, bonds, ClumpSet{}, 2);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("raise bond_substeps"));
  }
  // 0: as many as the bonds need under the contacts' step.
  const TimeStepChoice automatic =
      select_time_step(s, table, {}, std::nullopt, 0.2, 0.1, bonds, ClumpSet{}, 0);
  EXPECT_GE(automatic.bond_substeps, 1);
  EXPECT_LE(automatic.time_step / automatic.bond_substeps, 0.2 * bound * (1 + 1e-12));
}

}  // namespace
}  // namespace shapepress::simulate

namespace shapepress::simulate {
namespace {

// Bonds that cannot break go through the vectorized blocks (bonds.cpp); bonds that can, through
// the scalar loop. With strengths no force reaches the two must give the same bits, elastic or
// yielding (`model`: with yield stresses the random steps exceed in part of the bonds' modes).
void expect_blocks_match_the_scalar_loop(double damping_ratio,
                                         BondModelChoice model = ElasticBond{}) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  SphereState s;
  for (int i = 0; i < 70; ++i)  // a crooked chain with side bonds: 92 bonds, 3 blocks
    s.add_sphere(1.6 * r * i + 0.2 * r * unit(random), 0.4 * r * unit(random),
                 0.4 * r * unit(random), r * (1.0 + 0.1 * unit(random)), rho, 0);
  s.body.assign(s.size(), 0);
  BondParameters unbreakable = stiff();
  unbreakable.damping_ratio = damping_ratio;
  unbreakable.model = model;
  BondParameters breakable = unbreakable;
  breakable.tensile_strength = breakable.shear_strength = 1e300;
  BondSet blocks = create_bonds(s, 1.6, unbreakable);
  BondSet scalar = create_bonds(s, 1.6, breakable);
  ASSERT_FALSE(blocks.breakable);
  ASSERT_TRUE(scalar.breakable);
  ASSERT_GT(blocks.size(), 64u);
  std::vector<double> motion = still_motion(s);
  for (int step = 0; step < 5; ++step) {
    testing::move_at_random(s, motion, r, random);
    compute_bond_forces(blocks, s, motion.data(), Box{}, 1e-7, step == 0);
    compute_bond_forces(scalar, s, motion.data(), Box{}, 1e-7, step == 0);
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      const BondSet::History::Record hb = blocks.history.at(b), hs = scalar.history.at(b);
      ASSERT_EQ(std::memcmp(&hb, &hs, sizeof hb), 0) << "bond " << b << " step " << step;
      const BondSet::Results::Record rb = blocks.result.at(b), rs = scalar.result.at(b);
      ASSERT_EQ(std::memcmp(&rb, &rs, sizeof rb), 0) << "bond " << b << " step " << step;
    }
    ASSERT_EQ(blocks.history.model_fields, scalar.history.model_fields) << "step " << step;
  }
  if (blocks.yields) {
    // Both outcomes of the return were taken: some modes yielded, some did not.
    std::size_t yielded = 0, modes = 0;
    for (const auto& path : blocks.history.model_fields)
      for (double kappa : path)
        yielded += kappa > 0.0, ++modes;
    EXPECT_GT(yielded, modes / 10) << yielded << " of " << modes;
    EXPECT_LT(yielded, modes - modes / 10) << yielded << " of " << modes;
  }
}

TEST(BondBlocks, UndampedGiveTheScalarLoopsBits) {
  expect_blocks_match_the_scalar_loop(0.0);
}
TEST(BondBlocks, DampedGiveTheScalarLoopsBits) {
  expect_blocks_match_the_scalar_loop(0.315);
}
TEST(BondBlocks, YieldingGiveTheScalarLoopsBits) {
  expect_blocks_match_the_scalar_loop(0.0, ElasticPlasticBond{1.5e4, 1e4, 0.25});
  expect_blocks_match_the_scalar_loop(0.315, ElasticPlasticBond{1.5e4, 1e4, 0.0});
}

}  // namespace
}  // namespace shapepress::simulate

namespace shapepress::simulate {
namespace {

// The bonded network's top frequency by Lanczos (bond_spectrum.cpp) against a pair's modes in
// closed form, and against velocity Verlet itself on a small body: stable just below 2/ω_max,
// unstable just above.
// Two equal spheres (mass m, inertia I) bonded along x with arms a to the bond's centre: the
// stretch has ω² = 2kn/m, the twist 2kt/I, the bend 2kb/I, and the shear with the spins a
// rank-one block of energy ½ ks (Δy − a(θi + θj))² over the masses m/2 and I/2 of Δy and θi + θj,
// ω² = ks (2/m + 2a²/I).
double pair_top_frequency2(const BondSet& bonds, const SphereState& s) {
  const double m = s.mass[0], inertia = 1.0 / s.inverse_inertia[0];
  const double a = 0.5 * bonds.history.length[0];
  return std::max({2.0 * bonds.normal_spring[0] / m, 2.0 * bonds.twist_spring[0] / inertia,
                   2.0 * bonds.bend_spring[0] / inertia,
                   bonds.shear_spring[0] * (2.0 / m + 2.0 * a * a / inertia)});
}

TEST(BondSpectrum, APairsTopFrequencyIsItsStiffestModeInClosedForm) {
  BondParameters shear_tops = stiff(), stretch_tops = stiff();
  stretch_tops.shear_stiffness = 0.1 * kn_bar;
  for (const BondParameters& p : {shear_tops, stretch_tops}) {
    const SphereState s = pair_state();
    const BondSet bonds = create_bonds(s, 1.15, p);
    const double want = std::sqrt(pair_top_frequency2(bonds, s));
    EXPECT_NEAR(bond_top_frequency(bonds, s, Box{}), want, 1e-6 * want);
    // Gershgorin bounds the same number from above.
    EXPECT_LE(want, 2 * std::numbers::pi / bond_oscillation_period(bonds, s) * (1 + 1e-12));
  }
  // The stretch leads in the second set and the shear in the first: both branches are checked.
  const SphereState s = pair_state();
  const BondSet bonds = create_bonds(s, 1.15, stretch_tops);
  EXPECT_DOUBLE_EQ(pair_top_frequency2(bonds, s), 2.0 * bonds.normal_spring[0] / s.mass[0]);
}

TEST(BondSpectrum, APairAcrossThePeriodicBoundaryHasTheSameFrequency) {
  const SphereState inside = pair_state();
  SphereState across = pair_state();
  const Box box{10 * r, 10 * r};
  across.position.x[0] = 10 * r - 0.5 * r;  // the pair straddles x = 0 as its nearest image
  across.position.x[1] = 1.5 * r;
  const BondSet bonds = create_bonds(inside, 1.15, stiff());
  EXPECT_NEAR(bond_top_frequency(bonds, across, box), bond_top_frequency(bonds, inside, Box{}),
              1e-9 * bond_top_frequency(bonds, inside, Box{}));
}

// A body of 27 sub-spheres on a jittered cubic lattice, 2.05 r apart (bonded by Eq. 10 without
// touching, so the bonds alone act), every sphere moving at random, run at a multiple of the
// bonds' stability limit without its margin: below it the energy stays bounded, above it the top
// mode takes it without bound.
struct BodyRun {
  double energy_growth = 0.0;  // largest energy over the first
};

BodyRun run_body(double step_over_limit, double damping_ratio = 0.0) {
  SphereState s = testing::moving_cube_body(r, rho);
  BondParameters p = stiff();
  p.contact_when_bonded = false;
  p.damping_ratio = damping_ratio;
  BondSet bonds = create_bonds(s, 1.15, p);
  // The limit without its margin: 2/ω_max undamped.
  const double dt = step_over_limit * bond_stability_step(bonds, s, Box{}) / bond_stability_margin;
  MaterialTable table({{"m", 1e3, 0.3, rho}}, {{"m", "m", 0.7, 0.5}});
  EngineSettings settings{dt, {0, 0, 0}, 0.2 * r};
  settings.check_every = 1 << 30;  // the run is judged by its energy, not stopped
  Engine engine(std::move(s), Box{}, table, {}, settings, bonds);
  const double e0 = engine.energy().elastic + engine.energy().kinetic;
  BodyRun out;
  for (int k = 0; k < 3000; ++k) {
    engine.step();
    const EnergySummary e = engine.energy();
    const double growth = (e.elastic + e.kinetic) / e0;
    if (!std::isfinite(growth) || growth > 1e6) return {1e6};
    out.energy_growth = std::max(out.energy_growth, growth);
  }
  return out;
}

TEST(BondSpectrum, VerletIsStableJustBelowTheEstimatedLimitAndNotJustAbove) {
  // Undamped the limit is 2/ω_max; with the dampers the bound (ω dt)² + 4 γ dt ≤ 4 on the largest
  // ω and γ is as tight on this body (stable to 1.0 of it, unstable from 1.05 at every ζ tried).
  for (double zeta : {0.0, 0.1, 0.315, 1.0}) {
    EXPECT_LT(run_body(0.97, zeta).energy_growth, 3.0) << "zeta " << zeta;
    EXPECT_GT(run_body(1.05, zeta).energy_growth, 1e3) << "zeta " << zeta;
  }
}

TEST(BondSpectrum, TheStableStepHoldsTheMarginAndTheDampersTerms) {
  const SphereState s = pair_state();
  const BondSet plain = create_bonds(s, 1.15, stiff());
  const double omega = bond_top_frequency(plain, s, Box{});
  EXPECT_NEAR(bond_stability_step(plain, s, Box{}), bond_stability_margin * 2.0 / omega,
              1e-12 / omega);
  // Dampers: (ω dt)² + 4 γ dt = 4 at the limit without its margin.
  const BondSet with_dampers = create_bonds(s, 1.15, damped());
  const double gamma = bond_top_damping_rate(with_dampers, s, Box{});
  EXPECT_GT(gamma, 0.0);
  const double dt = bond_stability_step(with_dampers, s, Box{}) / bond_stability_margin;
  EXPECT_NEAR(omega * omega * dt * dt + 4.0 * gamma * dt, 4.0, 1e-9);
  EXPECT_EQ(bond_top_damping_rate(plain, s, Box{}), 0.0);
  EXPECT_EQ(bond_stability_step(BondSet{}, s, Box{}), std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace shapepress::simulate
