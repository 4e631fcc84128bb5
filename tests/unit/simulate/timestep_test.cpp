// The time step's bounds from the contact laws and the bonds (timestep.hpp): a law stiffer than
// Hertz (the multi-contact unloading branch k2 = k1/λp, a stated k1) shortens the step, Hertz
// keeps it, and a fraction above the bonds' stability limit is refused by name.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "common/error.hpp"
#include "simulate/bonds.hpp"
#include "simulate/timestep.hpp"

namespace shapepress::simulate {
namespace {

using ::testing::HasSubstr;

constexpr double radius = 1e-4, density = 1500.0;
const Material material{"m", 1e8, 0.3, density};

SphereState bed() {
  SphereState s;
  for (int k = 0; k < 4; ++k)
    s.add_sphere(3.0 * radius * k, 0.0, 0.0, radius, density, 0);
  return s;
}

double step_with(const NormalLawChoice& law) {
  const MaterialTable table({material}, {{"m", "m", 0.5, 0.5, 0.0, law}});
  return select_time_step(bed(), table, {}, std::nullopt, 0.2, 0.01).time_step;
}

TEST(TimeStep, MulticontactUnloadingStiffnessShortensTheStep) {
  const double hertz = step_with(HertzLaw{});
  MulticontactParameters p;
  p.plasticity_ratio = 0.2;  // k2 = 5 k1 (Eq. 6, Giannis 2023)
  const double plastic = step_with(MulticontactLaw{p});
  EXPECT_LT(plastic, hertz);
  // The Rayleigh time goes as 1/√E: a 5 times stiffer contact, a √5 times shorter step.
  EXPECT_NEAR(plastic / hertz, 1.0 / std::sqrt(5.0), 1e-12);
  // The defaults are Hertz: the step does not change by a bit.
  EXPECT_EQ(step_with(MulticontactLaw{}), hertz);
}

TEST(TimeStep, StatedLoadingStiffnessAndPrefactorCount) {
  const double hertz = step_with(HertzLaw{});
  // k1 three times Hertz's 4/3 E* √R* at R* = r/2 (two equal spheres).
  const double e_star = materials_effective_modulus(material, material);
  MulticontactParameters p;
  p.loading_stiffness = 3.0 * 4.0 / 3.0 * e_star * std::sqrt(0.5 * radius);
  EXPECT_NEAR(step_with(MulticontactLaw{p}) / hertz, 1.0 / std::sqrt(3.0), 1e-12);
  // β ν adds 3 β ν s1 to the ratio (multicontact_law.hpp, P_ij the trace 3p): β = 2, ν = 0.3,
  // s1 = 1 → 2.8.
  MulticontactParameters q;
  q.prefactor = 2.0;
  EXPECT_NEAR(step_with(MulticontactLaw{q}) / hertz, 1.0 / std::sqrt(2.8), 1e-12);
}

// Two touching spheres of 1 mm, one body, and a stiff bond between them.
SphereState two_touching_spheres() {
  constexpr double r = 1e-3;
  SphereState s;
  s.add_sphere(0.0, 0.0, 0.0, r, 2000.0, 0);
  s.add_sphere(2 * r, 0.0, 0.0, r, 2000.0, 0);
  s.body = {0, 0};
  return s;
}

BondSet stiff_bond(const SphereState& s) {
  BondParameters stiff;
  stiff.normal_stiffness = 1e10;
  stiff.shear_stiffness = 0.5e10;
  return create_bonds(s, 1.15, stiff);
}

TEST(TimeStep, FractionAboveTheBondLimitIsRefusedByName) {
  const SphereState s = two_touching_spheres();
  const BondSet bonds = stiff_bond(s);
  const MaterialTable table({{"m", 1e7, 0.3, 2000.0}}, {{"m", "m", 0.7, 0.5}});
  const double period = bond_oscillation_period(bonds, s);
  // Below the bonds' stability limit: accepted, and the bonds set the step. The limit, 0.9 of
  // 2/ω_max, lies between Gershgorin's T_b/π and about twice it.
  const TimeStepChoice ok = select_time_step(s, table, {}, std::nullopt, 0.3, 0.1, bonds);
  EXPECT_NEAR(ok.time_step, 0.3 * period, 1e-15 * period);
  const double largest = ok.bond_stability_step / period;
  EXPECT_GT(largest, bond_stability_margin / std::numbers::pi);
  EXPECT_LT(largest, 2.0 / std::numbers::pi);
  EXPECT_NO_THROW(select_time_step(s, table, {}, std::nullopt, 0.99 * largest, 0.1, bonds));
  try {
    select_time_step(s, table, {}, std::nullopt, 1.01 * largest, 0.1, bonds);
    ADD_FAILURE() << "a fraction above the bonds' stability limit was accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("time_step_fraction"));
    EXPECT_THAT(e.what(), HasSubstr(fmt::format("above {:.3g}", largest)));
  }
}

// The bonds' own fraction: the step where the bonds bind follows it, the contacts keep theirs,
// and above the bonds' stability limit it is refused by its own name.
TEST(TimeStep, TheBondsTakeTheirOwnFractionOfTheirPeriodBound) {
  const SphereState s = two_touching_spheres();
  const BondSet bonds = stiff_bond(s);
  const MaterialTable table({{"m", 1e5, 0.3, 2000.0}}, {{"m", "m", 0.7, 0.5}});
  const double period = bond_oscillation_period(bonds, s);
  const TimeStepChoice shared =
      select_time_step(s, table, {}, std::nullopt, 0.1, 0.1, bonds, ClumpSet{}, 1, std::nullopt);
  EXPECT_NEAR(shared.time_step, 0.1 * period, 1e-15 * period);
  const TimeStepChoice own =
      select_time_step(s, table, {}, std::nullopt, 0.1, 0.1, bonds, ClumpSet{}, 1, 0.3);
  EXPECT_NEAR(own.time_step, 0.3 * period, 1e-15 * period);
  ASSERT_LT(0.3 * period, 0.1 * own.rayleigh_time);  // soft contacts: the bonds still bind
  // Stiff contacts bind first whatever the bonds' fraction.
  const MaterialTable stiff_contacts({{"m", 1e13, 0.3, 2000.0}}, {{"m", "m", 0.7, 0.5}});
  const TimeStepChoice contacts =
      select_time_step(s, stiff_contacts, {}, std::nullopt, 0.1, 0.1, bonds, ClumpSet{}, 1, 0.3);
  EXPECT_NEAR(contacts.time_step, 0.1 * contacts.rayleigh_time, 1e-15 * contacts.time_step);
  EXPECT_LT(contacts.time_step, 0.3 * period);
  try {
    select_time_step(s, table, {}, std::nullopt, 0.1, 0.1, bonds, ClumpSet{}, 1, 0.7);
    ADD_FAILURE() << "a bond fraction of 0.7 was accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("bond_time_step_fraction 0.7"));
    EXPECT_THAT(e.what(), HasSubstr(fmt::format("above {:.3g}", own.bond_stability_step / period)));
  }
}

}  // namespace
}  // namespace shapepress::simulate
