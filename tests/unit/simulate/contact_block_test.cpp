// The vectorized contact block against the scalar law, bit for bit: the pair loop takes one or
// the other by the bed's materials, and a run must not depend on which (contact_block.hpp).
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <memory>
#include <random>

#include "simulate/contact_block.hpp"

namespace shapepress::simulate {
namespace {

PairConstants pair(double mu_s, double mu_r) {
  Material m{"m", 1e8, 0.3, 1541.0};
  MaterialTable table({m}, {Interaction{"m", "m", 0.35, mu_s, mu_r, HertzLaw{}}});
  return table.pair(0, 0);
}

// Contacts of 1 mm spheres overlapping by up to 1 %, moving at up to 1 m/s and spinning at up to
// 2000 rad/s, with springs from none (a new contact) to far past the Coulomb limit (sliding).
void fill(ContactBlock& b, int lanes, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), radius(0.4e-3, 0.6e-3);
  for (int l = 0; l < lanes; ++l) {
    b.radius_first[l] = radius(random);
    b.radius_second[l] = radius(random);
    double d[3] = {unit(random), unit(random), unit(random)};
    const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double distance =
        (b.radius_first[l] + b.radius_second[l]) * (1.0 - 0.01 * (0.5 + 0.5 * unit(random)));
    const double spring = l % 4 == 0 ? 0.0 : (l % 4 == 1 ? 1e-9 : 1e-5) * unit(random);
    for (int axis = 0; axis < 3; ++axis) {
      b.separation[axis][l] = d[axis] / length * distance;
      b.velocity_first[axis][l] = unit(random);
      b.velocity_second[axis][l] = unit(random);
      b.spin_first[axis][l] = 2000.0 * unit(random);
      b.spin_second[axis][l] = 2000.0 * unit(random);
      b.spring[axis][l] = spring * unit(random);
    }
    b.mass_first[l] = 1541.0 * 4.0 / 3.0 * 3.14159 * std::pow(b.radius_first[l], 3);
    b.mass_second[l] = 1541.0 * 4.0 / 3.0 * 3.14159 * std::pow(b.radius_second[l], 3);
    b.inverse_inertia_first[l] = 2.5 / (b.mass_first[l] * b.radius_first[l] * b.radius_first[l]);
    b.inverse_inertia_second[l] =
        2.5 / (b.mass_second[l] * b.radius_second[l] * b.radius_second[l]);
  }
}

// Lane l's kinematics as the scalar pair loop computes them.
PairKinematics lane_kinematics(const ContactBlock& in, int l) {
  const double d[3] = {in.separation[0][l], in.separation[1][l], in.separation[2][l]};
  const PairEnd first{{in.velocity_first[0][l], in.velocity_first[1][l], in.velocity_first[2][l]},
                      {in.spin_first[0][l], in.spin_first[1][l], in.spin_first[2][l]},
                      in.mass_first[l],
                      in.inverse_inertia_first[l]};
  const PairEnd second{
      {in.velocity_second[0][l], in.velocity_second[1][l], in.velocity_second[2][l]},
      {in.spin_second[0][l], in.spin_second[1][l], in.spin_second[2][l]},
      in.mass_second[l],
      in.inverse_inertia_second[l]};
  return pair_kinematics(d, in.radius_first[l], in.radius_second[l], first, second);
}

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

void expect_scalar_bits(double mu_s, double mu_r, int lanes) {
  const PairConstants p = pair(mu_s, mu_r);
  const double dt = 1e-6;
  auto block = std::make_unique<ContactBlock>();
  fill(*block, lanes, 20261202 + lanes);
  const ContactBlock in = *block;
  hertz_contact_block(*block, lanes, p, dt);
  int sliding = 0;
  for (int l = 0; l < lanes; ++l) {
    const PairKinematics k = lane_kinematics(in, l);
    ContactHistory history;
    for (int axis = 0; axis < 3; ++axis)
      history.tangential[axis] = in.spring[axis][l];
    const ContactForce f = contact_force<HertzLaw>(k.contact, p, history, dt);
    double torque_first[3], torque_second[3];
    contact_torques(k.contact.normal, f, k.arm_first, k.arm_second, torque_first, torque_second);
    const double limit = mu_s * std::fabs(f.normal_force);
    const double xi2 = history.tangential[0] * history.tangential[0] +
                       history.tangential[1] * history.tangential[1] +
                       history.tangential[2] * history.tangential[2];
    sliding += 8.0 * p.effective_shear_modulus *
                   std::sqrt(k.contact.effective_radius * k.contact.overlap) * std::sqrt(xi2) >=
               limit * (1.0 - 1e-12);
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_TRUE(same_bits(block->force[axis][l], f.force[axis])) << "lane " << l;
      EXPECT_TRUE(same_bits(block->torque_first[axis][l], torque_first[axis])) << "lane " << l;
      EXPECT_TRUE(same_bits(block->torque_second[axis][l], torque_second[axis])) << "lane " << l;
      EXPECT_TRUE(same_bits(block->spring[axis][l], history.tangential[axis])) << "lane " << l;
    }
  }
  // Both branches of the tangential law were taken.
  EXPECT_GT(sliding, 0);
  EXPECT_LT(sliding, lanes);
}

TEST(ContactBlock, SameBitsAsTheScalarLaw) {
  expect_scalar_bits(0.5, 0.0, ContactBlock::capacity);
}

TEST(ContactBlock, SameBitsWithRollingFrictionAndAPartialBlock) {
  expect_scalar_bits(0.3, 0.1, ContactBlock::capacity - 3);
}

// The multi-contact law's block: P_ij from tension to confinement, and plastic forces from none
// (virgin loading raises it) to past the loading force (the unloading and adhesive branches).
// `law` states k1 or leaves it to the loading modulus, with or without adhesion.
void expect_multicontact_scalar_bits(const MulticontactParameters& law, int lanes) {
  Material m{"m", 1e8, 0.3, 1541.0};
  if (!law.loading_stiffness) m.loading_modulus = 5.4e8;  // one source of k1
  const PairConstants p =
      MaterialTable({m}, {Interaction{"m", "m", 0.35, 0.5, 0.1, MulticontactLaw{law}}}).pair(0, 0);
  const double dt = 1e-6;
  auto block = std::make_unique<ContactBlock>();
  fill(*block, lanes, 20261207 + lanes);
  std::mt19937_64 random(7 + lanes);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int l = 0; l < lanes; ++l) {
    block->pair_pressure[l] = 1e6 * (unit(random) - 0.2);
    block->plastic_force[l] = l % 3 == 0 ? 0.0 : 0.5 * unit(random) * (l % 3);  // N
  }
  const ContactBlock in = *block;
  multicontact_contact_block(*block, lanes, p, dt);
  int raised = 0;
  for (int l = 0; l < lanes; ++l) {
    PairKinematics k = lane_kinematics(in, l);
    k.contact.pair_pressure = in.pair_pressure[l];
    ContactHistory history;
    for (int axis = 0; axis < 3; ++axis)
      history.tangential[axis] = in.spring[axis][l];
    plastic_force(history) = in.plastic_force[l];
    const ContactForce f = contact_force<MulticontactLaw>(k.contact, p, history, dt);
    double torque_first[3], torque_second[3];
    contact_torques(k.contact.normal, f, k.arm_first, k.arm_second, torque_first, torque_second);
    raised += plastic_force(history) > in.plastic_force[l];
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_TRUE(same_bits(block->force[axis][l], f.force[axis])) << "lane " << l;
      EXPECT_TRUE(same_bits(block->torque_first[axis][l], torque_first[axis])) << "lane " << l;
      EXPECT_TRUE(same_bits(block->torque_second[axis][l], torque_second[axis])) << "lane " << l;
      EXPECT_TRUE(same_bits(block->spring[axis][l], history.tangential[axis])) << "lane " << l;
    }
    EXPECT_TRUE(same_bits(block->plastic_force[l], plastic_force(history))) << "lane " << l;
    EXPECT_TRUE(same_bits(block->normal_force[l], f.normal_force)) << "lane " << l;
    EXPECT_TRUE(same_bits(block->overlap[l], k.contact.overlap)) << "lane " << l;
  }
  // Both the virgin loading and the branches below it were taken.
  EXPECT_GT(raised, 0);
  EXPECT_LT(raised, lanes);
}

TEST(ContactBlock, MulticontactSameBitsAsTheScalarLaw) {
  // The study's law: k1 from the loading modulus, λp = 0.3, β = 1.3.
  expect_multicontact_scalar_bits({std::nullopt, 0.3, 0.0, 0.0, 1.3}, ContactBlock::capacity);
}

TEST(ContactBlock, MulticontactSameBitsWithAStatedK1AdhesionAndAPartialBlock) {
  expect_multicontact_scalar_bits({1.0e7, 0.5, 2.0e6, -1e-4, 1.0}, ContactBlock::capacity - 5);
}

}  // namespace
}  // namespace shapepress::simulate
