// Bond breakage (models.md "Bonded multi-sphere", breakage): a bond breaks for good at its
// tensile or its shear strength, an unbreakable one never does, a bonded pair pressed together
// never breaks (the strengths are tensile and shear), and a partly broken set goes through a
// snapshot and restarts bit-identically, its broken bonds visible in the XDMF sidecar.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "simulate/bonds.hpp"
#include "simulate/engine.hpp"
#include "simulate/snapshot.hpp"
#include "tests/support/files.hpp"

namespace shapepress::simulate {
namespace {

using ::testing::HasSubstr;

constexpr double r = 1e-3;
constexpr double rho = 2000.0;
constexpr double kn_bar = 1e10;  // N/m^3
constexpr double ks_bar = 0.5e10;
const double area = std::numbers::pi * r * r;

BondParameters with_strengths(double tensile, double shear) {
  BondParameters p;
  p.normal_stiffness = kn_bar;
  p.shear_stiffness = ks_bar;
  p.tensile_strength = tensile;
  p.shear_strength = shear;
  return p;
}

// `count` touching sub-spheres of one particle along x.
SphereState chain(int count) {
  SphereState s;
  for (int k = 0; k < count; ++k)
    s.add_sphere(2 * r * k, 0.0, 0.0, r, rho, 0);
  s.body.assign(static_cast<std::size_t>(count), 0);
  return s;
}

const MaterialTable& table() {
  static const MaterialTable t({{"m", 1e7, 0.3, rho}}, {{"m", "m", 0.7, 0.5}});
  return t;
}

TEST(BondBreakage, AShearedBondBreaksAtItsShearStrength) {
  // One step of dt at a sliding velocity v adds |Fs| = k̄s A v dt: τ = |Fs|/A = k̄s v dt.
  SphereState s = chain(2);
  const double tau_c = 1e5, dt = 1e-6;
  BondSet bonds = create_bonds(s, 1.15, with_strengths(1e30, tau_c));
  const std::vector<double> motion(16, 0.0);
  s.velocity.y[1] = 0.9 * tau_c / (ks_bar * dt);
  compute_bond_forces(bonds, s, motion.data(), Box{}, dt, false);
  EXPECT_EQ(bonds.intact_count(), 1);
  EXPECT_NEAR(std::fabs(bonds.history.at(0).shear_force[1]) / area, 0.9 * tau_c, 1e-9 * tau_c);
  s.velocity.y[1] = 0.2 * tau_c / (ks_bar * dt);
  compute_bond_forces(bonds, s, motion.data(), Box{}, dt, false);
  EXPECT_EQ(bonds.intact_count(), 0);
  EXPECT_EQ(bonds.history.at(0).shear_force[1], 0.0);
  EXPECT_EQ(bonds.result.at(0).force[1], 0.0);  // a broken bond pulls no more
}

TEST(BondBreakage, AnUnbreakableBondNeverBreaks) {
  // The default strengths are infinite: stretched by half a radius and sheared as far, the bond
  // holds (σ = k̄n r/2 = 5 MPa here) and keeps pulling.
  SphereState s = chain(2);
  BondSet bonds = create_bonds(
      s, 1.15, with_strengths(BondParameters{}.tensile_strength, BondParameters{}.shear_strength));
  EXPECT_FALSE(bonds.breakable);
  const std::vector<double> motion(16, 0.0);
  const double dt = 1e-6;
  s.position.x[1] += 0.5 * r;
  s.velocity.y[1] = 0.5 * r / dt;
  compute_bond_forces(bonds, s, motion.data(), Box{}, dt, false);
  EXPECT_EQ(bonds.intact_count(), 1);
  EXPECT_NEAR(bonds.result.at(0).force[0], -kn_bar * area * 0.5 * r, 1e-9 * kn_bar * area * r);
}

// A bonded pair pressed to 0.8 of its radii sum (what a tablet's density does to some pairs of
// a BMS bed), from touching: the bond carries k̄n A (ri + rj - d) as a linear spring; with
// contact_when_bonded the contact law acts beside it at that overlap, without it the bond alone.
// A compressed bond does not break (σ = -Fn/A < 0, no shear).
Engine pressed_pair(double centre_distance, bool bonded, bool contact_when_bonded) {
  SphereState s = chain(2);
  BondParameters p = with_strengths(1e5, 1e5);
  p.contact_when_bonded = contact_when_bonded;
  BondSet bonds = bonded ? create_bonds(s, 1.15, p) : BondSet{};
  if (!bonded) s.body = {0, 1};
  s.position.x[1] = centre_distance;
  return Engine(std::move(s), Box{}, table(), {}, EngineSettings{1e-8, {0, 0, 0}, 0.1 * r},
                std::move(bonds));
}

TEST(BondBreakage, APairPressedToFourFifthsOfItsRadiiSumIsBondPlusContactOrBondAlone) {
  const double d = 0.8 * 2 * r;
  const double bond_force = kn_bar * area * (2 * r - d);  // on sphere 1, along +x
  const Engine alone = pressed_pair(d, true, false);
  const Engine both = pressed_pair(d, true, true);
  const Engine contact = pressed_pair(d, false, true);  // two particles: the contact law alone
  EXPECT_EQ(alone.bonds().intact_count(), 1);
  EXPECT_EQ(both.bonds().intact_count(), 1);
  EXPECT_NEAR(alone.state().force.x[1], bond_force, 1e-12 * bond_force);
  const double contact_force = contact.state().force.x[1];
  EXPECT_GT(contact_force, 0.0);
  EXPECT_NEAR(both.state().force.x[1], bond_force + contact_force,
              1e-12 * (bond_force + contact_force));
  // Equal spheres at 0.8 of the radii sum overlap by 0.4 r: within the contact check's 0.5 r and
  // the bond-only limit, so neither run stops.
  EXPECT_NO_THROW(alone.check_divergence());
  EXPECT_NO_THROW(both.check_divergence());
}

TEST(BondBreakage, APairPressedPastItsLimitStopsNamingThePairAndItsOverlap) {
  // Bond alone: past bond_only_overlap_limit of the radii sum (centres within 0.2 of it).
  const double radii_sum = 2 * r;
  try {
    pressed_pair((1 - bond_only_overlap_limit - 0.05) * radii_sum, true, false).check_divergence();
    FAIL() << "a bond-only pair past the limit is not caught";
  } catch (const ComputationError& error) {
    EXPECT_THAT(error.what(), HasSubstr("bonded spheres 0 and 1"));
    EXPECT_THAT(error.what(), HasSubstr("0.850 of their radii sum"));
    EXPECT_THAT(error.what(), HasSubstr("contact_when_bonded = false"));
  }
  // Just inside the limit the bond alone still holds.
  EXPECT_NO_THROW(pressed_pair((1 - bond_only_overlap_limit + 0.05) * radii_sum, true, false)
                      .check_divergence());
  // With the contact law the pair is a contact: past max_overlap_fraction of the smaller radius.
  try {
    pressed_pair(1.4 * r, true, true).check_divergence();
    FAIL() << "a bonded contact past max_overlap_fraction is not caught";
  } catch (const ComputationError& error) {
    EXPECT_THAT(error.what(), HasSubstr("spheres 0 and 1 overlap"));
  }
}

TEST(BondBreakage, APartlyBrokenBodyRestartsBitIdenticallyAndShowsItsBrokenBonds) {
  // A chain of six sub-spheres whose ends are flung apart: the end bonds break, the inner ones
  // hold, and the snapshot taken then carries which is which.
  const auto start = [] {
    SphereState s = chain(6);
    BondSet bonds = create_bonds(s, 1.15, with_strengths(4e4, 1e30));
    s.velocity.x[0] = -0.5, s.velocity.x[5] = 0.5;
    return Engine(std::move(s), Box{}, table(), {}, EngineSettings{2e-7, {0, 0, 0}, 0.1 * r},
                  std::move(bonds));
  };
  omp_set_num_threads(1);
  Engine continuous = start(), first = start();
  for (int k = 0; k < 300; ++k)
    first.step();
  const std::int64_t intact = first.bonds().intact_count();
  ASSERT_GT(intact, 0);
  ASSERT_LT(intact, 5);
  const std::filesystem::path file =
      shapepress::testing::fresh_directory("bond_breakage") / "restart.h5";
  write_snapshot(file, first, ScenarioState{}, Provenance{"test", "", std::nullopt});
  LoadedSnapshot loaded = read_snapshot(file);
  std::filesystem::remove(file);
  EXPECT_EQ(loaded.checkpoint.bonds.intact, first.bonds().intact);
  Engine resumed(std::move(loaded.state), loaded.box, table(), first.settings(),
                 std::move(loaded.checkpoint));
  EXPECT_EQ(resumed.bonds().intact_count(), intact);
  for (int k = 0; k < 600; ++k)
    continuous.step();
  for (int k = 0; k < 300; ++k)
    resumed.step();
  omp_set_num_threads(2);
  EXPECT_EQ(continuous.bonds().intact, resumed.bonds().intact);
  EXPECT_EQ(continuous.bonds().history, resumed.bonds().history);
  EXPECT_EQ(continuous.state().position, resumed.state().position);
  EXPECT_EQ(continuous.state().velocity, resumed.state().velocity);

  // ParaView: the bonds are line cells with a per-cell "intact" flag to threshold on.
  const std::filesystem::path xdmf =
      shapepress::testing::fresh_directory("bond_breakage") / "bonds.xdmf";
  write_xdmf(xdmf, {SnapshotIndexEntry{"s.h5", 0.0, 6, 0, false, 5, 0}});
  std::stringstream text;
  text << std::ifstream(xdmf).rdbuf();
  std::filesystem::remove(xdmf);
  EXPECT_THAT(text.str(), HasSubstr("Attribute Name=\"intact\""));
  EXPECT_THAT(text.str(), HasSubstr("s.h5:/bonds/intact"));
}

}  // namespace
}  // namespace shapepress::simulate
