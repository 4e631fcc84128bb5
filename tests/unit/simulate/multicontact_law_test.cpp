// The multi-contact elastic–plastic law (paper Eq. 6) on hand-made contacts: its reduction to
// Hertz–Mindlin, each branch and the plastic history over a load–unload–reload–pull-off cycle,
// the multi-contact term β ν A_ij P_ij, and the friction limit measured from the adhesive floor.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/config.hpp"
#include "common/error.hpp"
#include "simulate/contact_law.hpp"
#include "simulate/contact_law_config.hpp"

namespace shapepress::simulate {
namespace {

constexpr double young = 1e8, poisson = 0.3;

PairConstants pair(NormalLawChoice law, double e = 0.5, double mu_s = 0.5, double mu_r = 0.1) {
  Material mat{"m", young, poisson, 1541.0};
  Interaction in{"m", "m", e, mu_s, mu_r, law};
  return MaterialTable({mat}, {in}).pair(0, 0);
}

ContactKinematics moving_contact(double overlap, double vn, double vt, double spin) {
  ContactKinematics c{};
  c.normal[2] = 1.0;
  c.overlap = overlap;
  c.relative_velocity[0] = vt;
  c.relative_velocity[2] = vn;
  c.relative_rotation[1] = spin;
  c.effective_radius = 2.5e-4;
  c.effective_mass = 4e-7;
  c.inverse_inertia_sum = 1e14;
  return c;
}

// Relative difference in units of the larger magnitude (round-off: a few 1e-16).
double relative(double a, double b) {
  const double scale = std::max(std::fabs(a), std::fabs(b));
  return scale > 0.0 ? std::fabs(a - b) / scale : 0.0;
}

TEST(MulticontactLaw, ReducesToHertzMindlinToRoundOff) {
  // λp = 1, kc = 0, F0 = 0, β = 0 (the defaults), with damping, friction, rolling, a slide past
  // the Coulomb limit and a confining pressure that β = 0 must ignore.
  const PairConstants hertz = pair(HertzLaw{});
  const PairConstants mc = pair(MulticontactLaw{});
  ContactHistory h_hertz, h_mc;
  const double dt = 1e-7;
  for (int k = 0; k < 400; ++k) {
    const double phase = k / 400.0 * std::numbers::pi;
    const double overlap = 2e-6 * std::sin(phase) + 1e-9;
    ContactKinematics c = moving_contact(overlap, -0.05 * std::cos(phase), 0.02 * (k % 7 - 3),
                                         300.0 * std::cos(3 * phase));
    c.pair_pressure = 5e6;
    const ContactForce a = contact_force(c, hertz, h_hertz, dt);
    const ContactForce b = contact_force(c, mc, h_mc, dt);
    for (int i = 0; i < 3; ++i) {
      ASSERT_LE(relative(a.force[i], b.force[i]), 4e-16) << "step " << k << " component " << i;
      ASSERT_LE(relative(a.rolling_torque[i], b.rolling_torque[i]), 4e-16);
      ASSERT_LE(relative(h_hertz.tangential[i], h_mc.tangential[i]), 4e-16);
    }
  }
  EXPECT_EQ(plastic_force(h_mc), 0.0);  // λp = 1 leaves no plastic overlap
  EXPECT_NEAR(multicontact_elastic_energy(mc, 2.5e-4, 1e-6, 0.0) /
                  hertz_elastic_energy(hertz, 2.5e-4, 1e-6),
              1.0, 1e-14);
}

// The analytic branches of Eq. 6 with x = δ^{3/2}, xp = (1 - λp) xmax^{3/2}, k2 = k1/λp.
struct Branches {
  double k1, lambda, kc, f0;
  double k2() const { return k1 / lambda; }
  double loading(double d) const { return f0 + k1 * std::pow(d, 1.5); }
  double plastic(double d_max) const { return (1.0 - lambda) * std::pow(d_max, 1.5); }
  double unloading(double d, double d_max) const {
    return f0 + k2() * (std::pow(d, 1.5) - plastic(d_max));
  }
  double adhesive(double d) const { return f0 - kc * std::pow(d, 1.5); }
};

TEST(MulticontactLaw, LoadUnloadReloadPullOffCycleFollowsEachBranch) {
  const Branches b{2.0e7, 0.35, 6.0e6, -1e-4};
  MulticontactParameters m;
  m.loading_stiffness = b.k1;
  m.plasticity_ratio = b.lambda;
  m.adhesion_stiffness = b.kc;
  m.pull_off_force = b.f0;
  const PairConstants p = pair(MulticontactLaw{m}, 1.0);  // e = 1: no damping
  const double radius = 2.5e-4, mass = 4e-7;
  ContactHistory h;
  const auto force = [&](double d) {
    const double root = std::sqrt(std::sqrt(radius * d) * mass);
    return multicontact_normal(p, d, radius, mass, std::sqrt(radius * d), root, 0.0, 0.0,
                               plastic_force(h))
        .force;
  };
  const double d1 = 4e-6, d2 = 6e-6;
  // Virgin loading to δ1.
  for (int k = 1; k <= 40; ++k) {
    const double d = d1 * k / 40;
    ASSERT_LE(relative(force(d), b.loading(d)), 1e-10) << "loading at " << d;
  }
  EXPECT_LE(relative(plastic_force(h), b.k1 * b.plastic(d1)), 1e-10);  // δp from δmax
  // Unloading from δ1 follows k2 down to where it meets the adhesive branch; reloading follows
  // it back up to δ1 (no new plastic overlap).
  const double x_meet = b.k2() * b.plastic(d1) / (b.k2() + b.kc);  // k2 (x - xp) = -kc x
  const double d_meet = std::pow(x_meet, 2.0 / 3.0);
  for (int k = 39; k >= 1; --k) {
    const double d = d1 * k / 40;
    const double expected = d > d_meet ? b.unloading(d, d1) : b.adhesive(d);
    ASSERT_LE(relative(force(d), expected), 1e-10) << "unloading at " << d;
  }
  for (int k = 1; k <= 40; ++k) {
    const double d = d1 * k / 40;
    const double expected = d > d_meet ? b.unloading(d, d1) : b.adhesive(d);
    ASSERT_LE(relative(force(d), expected), 1e-10) << "reloading at " << d;
  }
  EXPECT_LE(relative(plastic_force(h), b.k1 * b.plastic(d1)), 1e-10);
  // The branches meet at δmax: unloading and loading give the same force there.
  EXPECT_LE(relative(b.unloading(d1, d1), b.loading(d1)), 1e-12);
  // Beyond δ1 the contact is back on virgin loading, and δp grows with the new δmax.
  for (int k = 1; k <= 20; ++k) {
    const double d = d1 + (d2 - d1) * k / 20;
    ASSERT_LE(relative(force(d), b.loading(d)), 1e-10) << "loading again at " << d;
  }
  EXPECT_LE(relative(plastic_force(h), b.k1 * b.plastic(d2)), 1e-10);
  // Pull-off: unloading from δ2 into the adhesive branch; the most attractive force is where
  // the branches meet, F0 - kc k2 xp / (k2 + kc).
  const double x2 = b.k2() * b.plastic(d2) / (b.k2() + b.kc);
  const double d2_meet = std::pow(x2, 2.0 / 3.0);
  double most_attractive = 0.0;
  for (int k = 399; k >= 1; --k) {
    const double d = d2 * k / 400;
    const double f = force(d);
    const double expected = d > d2_meet ? b.unloading(d, d2) : b.adhesive(d);
    ASSERT_LE(relative(f, expected), 1e-10) << "pull-off at " << d;
    most_attractive = std::min(most_attractive, f);
  }
  const double pull_off = b.f0 - b.kc * b.k2() * b.plastic(d2) / (b.k2() + b.kc);
  EXPECT_LE(relative(force(d2_meet), pull_off), 1e-10);
  // No sampled force is more attractive than the pull-off force, and one comes within 1 %.
  EXPECT_GE(most_attractive, pull_off * (1.0 + 1e-12));
  EXPECT_LE(most_attractive, pull_off * (1.0 - 1e-2));
}

TEST(MulticontactLaw, MultiContactTermAddsBetaNuAreaPressure) {
  MulticontactParameters m;
  m.prefactor = 1.71;
  const PairConstants with = pair(MulticontactLaw{m}, 1.0);
  const PairConstants without = pair(MulticontactLaw{}, 1.0);
  const double r = 2.5e-4, d = 3e-6, pressure = 4e6;
  double xp = 0.0, xq = 0.0;
  const double f1 =
      multicontact_normal(with, d, r, 1e-6, std::sqrt(r * d), 0.0, 0.0, pressure, xp).force;
  const double f0 =
      multicontact_normal(without, d, r, 1e-6, std::sqrt(r * d), 0.0, 0.0, pressure, xq).force;
  // β ν A_ij P_ij with A_ij = π a², a² = R* δ, and P_ij the mean trace 3p̄ of the pair's mean
  // pressure p̄ (models.md, "Which reading of Eq. 6").
  const double expected = 1.71 * poisson * std::numbers::pi * r * d * 3.0 * pressure;
  EXPECT_LE(relative(f1 - f0, expected), 1e-12);
  // Tension does not pull: P < 0 adds nothing.
  const double f_tension =
      multicontact_normal(with, d, r, 1e-6, std::sqrt(r * d), 0.0, 0.0, -pressure, xp).force;
  EXPECT_EQ(f_tension, f0);
}

TEST(MulticontactLaw, FrictionLimitIsMeasuredFromTheAdhesiveFloor) {
  MulticontactParameters m;
  m.plasticity_ratio = 0.5;
  m.adhesion_stiffness = 1e7;
  m.pull_off_force = -2e-3;
  const PairConstants p = pair(MulticontactLaw{m}, 1.0, 0.4, 0.0);
  ContactHistory h;
  // Load to 4 µm, then back to 1 µm where the unloading force is attractive, and slide fast.
  contact_force(moving_contact(4e-6, 0.0, 0.0, 0.0), p, h, 1e-7);
  const double d = 1e-6;
  const ContactForce f = contact_force(moving_contact(d, 0.0, 10.0, 0.0), p, h, 1e-7);
  const double floor = -2e-3 - 1e7 * d * std::sqrt(d);
  EXPECT_LT(f.normal_force, 0.0);  // attractive, yet it holds friction
  const double tangential = std::hypot(f.force[0], f.force[1]);
  EXPECT_GT(f.normal_force - floor, 0.0);
  EXPECT_LE(relative(tangential, 0.4 * (f.normal_force - floor)), 1e-12);
}

// A loading modulus E_L gives every contact k1 = 4/3 E*_L √R* (docs/models.md, "One material"):
// the loading force scales as √R* like Hertz's, so a contact 2.5 times smaller is not stiffer per
// unit of its size, and E*_L comes from the two materials' loading moduli as E* from their Young's
// moduli (a wall without one keeps its E). The damping keeps the input restitution.
TEST(MulticontactLaw, LoadingModulusGivesEachContactItsOwnKOne) {
  const double loading = 7.0 * young;
  Material particle{"p", young, poisson, 1541.0}, tool{"t", 200.0 * young, 0.31, 7800.0};
  particle.loading_modulus = loading;
  const std::vector<Material> materials = {particle, tool};
  const MaterialTable table(materials, {{"p", "p", 1.0, 0.5, 0.1, MulticontactLaw{}},
                                        {"p", "t", 1.0, 0.5, 0.1, MulticontactLaw{}}});
  const auto force = [](const PairConstants& p, double r, double d) {
    double plastic = 0.0;
    const double root = std::sqrt(std::sqrt(r * d) * 1e-7);
    return multicontact_normal(p, d, r, 1e-7, std::sqrt(r * d), root, 0.0, 0.0, plastic).force;
  };
  const double star_pp = loading / (2.0 * (1.0 - poisson * poisson));
  const double star_pt =
      1.0 / ((1.0 - poisson * poisson) / loading + (1.0 - 0.31 * 0.31) / (200.0 * young));
  for (const double r : {2.5e-4, 1e-4}) {
    const double d = 1e-3 * r;
    EXPECT_LE(relative(force(table.pair(0, 0), r, d),
                       4.0 / 3.0 * star_pp * std::sqrt(r) * d * std::sqrt(d)),
              1e-12)
        << r;
    EXPECT_LE(relative(force(table.pair(0, 1), r, d),
                       4.0 / 3.0 * star_pt * std::sqrt(r) * d * std::sqrt(d)),
              1e-12)
        << r;
  }
  // The time step's bound follows the loading branch: E*_L/E* times Hertz's.
  const MaterialTable elastic({{"p", young, poisson, 1541.0}},
                              {{"p", "p", 1.0, 0.5, 0.1, MulticontactLaw{}}});
  EXPECT_NEAR(normal_stiffness_ratio(table.pair(0, 0), 2.5e-4) /
                  normal_stiffness_ratio(elastic.pair(0, 0), 2.5e-4),
              7.0, 1e-12);
}

TEST(MulticontactLaw, ALoadingModulusIsReadOnceAndOnlyByTheLaw) {
  Material particle{"p", young, poisson, 1541.0};
  particle.loading_modulus = 5.0 * young;
  MulticontactParameters k1;
  k1.loading_stiffness = 1e7;
  // k1 stated and a loading modulus: two statements of one stiffness.
  EXPECT_THROW(MaterialTable({particle}, {{"p", "p", 0.5, 0.5, 0.1, MulticontactLaw{k1}}}),
               InputError);
  // A loading modulus that no multi-contact interaction reads would be ignored.
  EXPECT_THROW(MaterialTable({particle}, {{"p", "p", 0.5, 0.5}}), InputError);
  particle.loading_modulus = -1.0;
  EXPECT_THROW(MaterialTable({particle}, {{"p", "p", 0.5, 0.5, 0.1, MulticontactLaw{}}}),
               InputError);
}

TEST(MulticontactLaw, ParametersAreCheckedAndNeedTheLaw) {
  MulticontactParameters bad;
  bad.plasticity_ratio = 0.0;
  EXPECT_THROW(pair(MulticontactLaw{bad}), InputError);
  bad = {};
  bad.pull_off_force = 1e-3;  // repulsive F0 is not a pull-off force
  EXPECT_THROW(pair(MulticontactLaw{bad}), InputError);
  // Multi-contact parameters under a Hertz pair: refused where they are read.
  const ConfigTable hertz_with_keys =
      ConfigTable::parse("normal_law = \"hertz\"\nplasticity_ratio = 0.5\n", "interaction");
  EXPECT_THROW(read_normal_law(hertz_with_keys, "interaction m–m"), InputError);
}

}  // namespace
}  // namespace shapepress::simulate
