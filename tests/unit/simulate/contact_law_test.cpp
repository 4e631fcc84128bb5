// The contact sub-models on hand-made contacts: Hertz force, damping factor, the tangential
// spring's rotation and Coulomb truncation, and CDT rolling with its chatter guard.
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.hpp"
#include "simulate/contact_law.hpp"

namespace shapepress::simulate {
namespace {

PairConstants pair(double mu_s = 0.5, double mu_r = 0.0, double e = 0.5) {
  Material m{"m", 1e8, 0.3, 1541.0};
  Interaction in{"m", "m", e, mu_s, mu_r, HertzLaw{}};
  MaterialTable table({m}, {in});
  return table.pair(0, 0);
}

ContactKinematics resting_contact(double overlap) {
  ContactKinematics c{};
  c.normal[2] = 1.0;
  c.overlap = overlap;
  c.effective_radius = 2.5e-4;
  c.effective_mass = 4e-7;
  c.inverse_inertia_sum = 1e14;
  return c;
}

TEST(ContactLaw, EffectiveModuliFollowTheStandardForm) {
  const PairConstants p = pair();
  // 1/E* = 2 (1 - ν²)/E; 1/G* = 2 (2 - ν)/G with G = E / 2.6 (models.md, Eq. 2 corrected).
  EXPECT_NEAR(p.effective_modulus, 1e8 / (2.0 * 0.91), 1e-6);
  EXPECT_NEAR(p.effective_shear_modulus, 1e8 / 2.6 / (2.0 * 1.7), 1e-6);
}

TEST(ContactLaw, AnInteractionsEffectiveModulusReplacesTheMaterialsOne) {
  // A sub-sphere (E = 200 MPa, ν = 0.46) against a plate (1 GPa, 0.3): the materials give
  // E* = 1/((1 − 0.46²)/2e8 + (1 − 0.3²)/1e9) ≈ 0.21 GPa; effective_modulus = 1 GPa states it,
  // and G* keeps the materials' ratio G*/E*.
  const Material sub{"sub", 2e8, 0.46, 2000.0}, plate{"plate", 1e9, 0.3, 7800.0};
  const Interaction from_materials{"sub", "plate", 0.7, 0.5};
  Interaction stated = from_materials;
  stated.effective_modulus = 1e9;
  const MaterialTable a({sub, plate}, {{"sub", "sub", 0.7, 0.5}, from_materials});
  const MaterialTable b({sub, plate}, {{"sub", "sub", 0.7, 0.5}, stated});
  const PairConstants& p = a.pair(0, 1);
  const PairConstants& q = b.pair(0, 1);
  EXPECT_NEAR(p.effective_modulus, 1.0 / ((1 - 0.46 * 0.46) / 2e8 + 0.91 / 1e9), 1e-3);
  EXPECT_DOUBLE_EQ(q.effective_modulus, 1e9);
  EXPECT_NEAR(q.effective_shear_modulus / q.effective_modulus,
              p.effective_shear_modulus / p.effective_modulus, 1e-12);
  // The damping follows the stated stiffness: γn ∝ √(2 E*).
  EXPECT_NEAR(q.normal_damping_scale / p.normal_damping_scale,
              std::sqrt(q.effective_modulus / p.effective_modulus), 1e-12);
  EXPECT_DOUBLE_EQ(b.pair(0, 0).effective_modulus, a.pair(0, 0).effective_modulus);
  stated.effective_modulus = -1.0;
  EXPECT_THROW(MaterialTable({sub, plate}, {{"sub", "sub", 0.7, 0.5}, stated}), InputError);
}

TEST(ContactLaw, StaticHertzForce) {
  const PairConstants p = pair();
  ContactHistory h;
  const double overlap = 1e-6;
  const ContactForce f = contact_force(resting_contact(overlap), p, h, 1e-7);
  const double expected =
      4.0 / 3.0 * p.effective_modulus * std::sqrt(2.5e-4) * std::pow(overlap, 1.5);
  EXPECT_NEAR(f.force[2], expected, 1e-12 * expected);  // same formula, round-off only
  EXPECT_DOUBLE_EQ(f.normal_force, f.force[2]);
}

TEST(ContactLaw, DampingFactorVanishesForElasticContacts) {
  EXPECT_EQ(restitution_damping_factor(1.0), 0.0);
  // β(0.35) = ln 0.35 / √(ln² 0.35 + π²) = -0.316941 (by hand); factor = -2√(5/6) β.
  EXPECT_NEAR(restitution_damping_factor(0.35), 2.0 * std::sqrt(5.0 / 6.0) * 0.316941, 1e-5);
}

TEST(ContactLaw, TangentialSpringIsRotatedIntoTheTangentPlaneKeepingItsLength) {
  const PairConstants p = pair(10.0);  // friction high enough not to truncate
  ContactHistory h;
  h.tangential[0] = 3e-9;
  h.tangential[2] = 4e-9;  // partly along the normal (0, 0, 1)
  double force[3];
  const double n[3] = {0, 0, 1}, vt[3] = {0, 0, 0};
  mindlin_tangential(p, n, vt, 1000.0, 0.0, 1.0, 1e-7, h, force);
  EXPECT_NEAR(h.tangential[0], 5e-9, 1e-22);
  EXPECT_EQ(h.tangential[2], 0.0);
  EXPECT_NEAR(force[0], -1000.0 * 5e-9, 1e-18);
}

TEST(ContactLaw, CoulombLimitTruncatesForceAndSpring) {
  const PairConstants p = pair(0.5);
  ContactHistory h;
  double force[3];
  const double n[3] = {0, 0, 1}, vt[3] = {1.0, 0, 0};
  const double kt = 1000.0, fn = 2.0;
  mindlin_tangential(p, n, vt, kt, 5.0, fn, 1e-2, h, force);  // spring 10 N > μ Fn = 1 N
  EXPECT_NEAR(std::hypot(force[0], force[1], force[2]), 0.5 * fn, 1e-12);
  EXPECT_NEAR(h.tangential[0], 0.5 * fn / kt, 1e-15);
  EXPECT_LT(force[0], 0.0);  // opposes the sliding of j relative to i
}

TEST(ContactLaw, RollingTorqueIsConstantAndGuardedNearRest) {
  const PairConstants p = pair(0.5, 0.1);
  ContactKinematics c = resting_contact(1e-6);
  const double fn = 2.0, dt = 1e-6;
  double torque[3];
  c.relative_rotation[0] = 1e5;  // fast (guard at 5000 rad/s): full torque
  cdt_rolling(p, c, fn, dt, torque);
  EXPECT_NEAR(torque[0], -0.1 * 2.5e-4 * fn, 1e-15);
  // Slow: the torque only removes the relative rotation, it does not reverse it.
  const double guard = 0.1 * 2.5e-4 * fn * dt * c.inverse_inertia_sum;
  c.relative_rotation[0] = 0.25 * guard;
  cdt_rolling(p, c, fn, dt, torque);
  const double change = torque[0] * dt * c.inverse_inertia_sum;
  EXPECT_NEAR(change, -0.25 * guard, 1e-12 * guard);
  // Spin about the normal is not rolling.
  c.relative_rotation[0] = 0.0;
  c.relative_rotation[2] = 100.0;
  cdt_rolling(p, c, fn, dt, torque);
  EXPECT_EQ(torque[2], 0.0);
}

}  // namespace
}  // namespace shapepress::simulate
