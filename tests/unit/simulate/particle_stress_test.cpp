// The Love–Weber particle stress the multi-contact law reads (paper Eq. 6's P_ij) and the
// multi-contact term it drives, on a hydrostatically loaded layer: 3 × 3 spheres in a periodic
// box, each pressed by its four lattice neighbours (±x, ±y) and by the two plates (±z), six
// contacts whose arm × force is the same on every axis, so σ = -p I with p analytic; and a
// bonded body, whose sub-spheres' stresses with their bonds sum to the body's.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "simulate/bonds.hpp"
#include "simulate/engine.hpp"

namespace shapepress::simulate {
namespace {

constexpr double radius = 0.5e-3, young = 1e8, poisson = 0.3;
constexpr double overlap = 4e-6;  // sphere–sphere

MaterialTable table(double beta) {
  MulticontactParameters m;
  m.prefactor = beta;
  return MaterialTable({{"m", young, poisson, 1541.0}},
                       {{"m", "m", 1.0, 0.5, 0.0, MulticontactLaw{m}}});
}

double hertz(double r_eff, double d) {
  const double e_star = young / (2.0 * (1.0 - poisson * poisson));
  return 4.0 / 3.0 * e_star * std::sqrt(r_eff) * d * std::sqrt(d);
}

// Wall overlap whose arm × force equals the lattice contacts' (r - δ/2) F(R/2, δ): bisection.
double wall_overlap() {
  const double target = (radius - 0.5 * overlap) * hertz(0.5 * radius, overlap);
  double lo = 0.0, hi = 4.0 * overlap;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    ((radius - mid) * hertz(radius, mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

struct Layer {
  Engine engine;
  double wall_overlap;
};

Layer layer(double beta) {
  const double spacing = 2.0 * radius - overlap, length = 3.0 * spacing;
  const double dw = wall_overlap(), z = radius;
  SphereState s;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      s.add_sphere((i + 0.5) * spacing, (j + 0.5) * spacing, z, radius, 1541.0, 0);
  std::vector<PlaneWall> walls = {PlaneWall{z - (radius - dw), 1, 0.0, 0},
                                  PlaneWall{z + (radius - dw), -1, 0.0, 0}};
  // Periodic length 3(2r - δ) < 3 cells of 2r + skin: the list's two-cell path is exercised.
  EngineSettings settings{1e-8, {0.0, 0.0, 0.0}, 0.05 * radius};
  return {Engine(std::move(s), Box{length, length}, table(beta), std::move(walls), settings), dw};
}

TEST(ParticleStress, HydrostaticLayerGivesTheAnalyticPressure) {
  Layer l = layer(0.0);
  ASSERT_TRUE(l.engine.computes_particle_stress());
  EXPECT_EQ(l.engine.sphere_contacts(), 18);  // 9 spheres × 4 lattice contacts / 2
  EXPECT_EQ(l.engine.wall_contacts(), 18);
  // σ = (1/V) Σ l ⊗ f: per axis two contacts of arm rc and force F, σ_aa = -2 rc F / V.
  const double volume = 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  const double arm_force = (radius - 0.5 * overlap) * hertz(0.5 * radius, overlap);
  const double p = 2.0 * arm_force / volume;
  const std::vector<double>& stress = l.engine.particle_stress();
  for (std::size_t i = 0; i < 9; ++i) {
    const double* s = &stress[stress_components * i];
    EXPECT_NEAR(l.engine.particle_pressure(i), p, 1e-12 * p) << "sphere " << i;
    EXPECT_NEAR(s[0], -p, 1e-12 * p);  // xx
    EXPECT_NEAR(s[3], -p, 1e-12 * p);  // yy
    EXPECT_NEAR(s[5], -p, 1e-9 * p);   // zz (wall overlap from a bisection)
    EXPECT_NEAR(s[1], 0.0, 1e-12 * p);
    EXPECT_NEAR(s[2], 0.0, 1e-12 * p);
    EXPECT_NEAR(s[4], 0.0, 1e-12 * p);
  }
}

TEST(ParticleStress, MultiContactTermChangesTheForceByBetaNuAreaPressure) {
  // The first force evaluation has no previous stress (p = 0); one step later each contact
  // carries β ν π R* δ P_ij, P_ij = 3p the mean trace, for two spheres and against a plate
  // alike (a plate takes the sphere's own p).
  const double beta = 1.3;
  Layer with = layer(beta), without = layer(0.0);
  EXPECT_EQ(with.engine.wall_load(0), without.engine.wall_load(0));
  const double p = with.engine.particle_pressure(0);
  with.engine.step();
  without.engine.step();
  const double extra = with.engine.wall_load(0) - without.engine.wall_load(0);
  const double expected =
      9.0 * beta * poisson * std::numbers::pi * radius * with.wall_overlap * 3.0 * p;
  EXPECT_NEAR(extra, expected, 1e-6 * expected);
  // The stress now includes the larger forces: the lattice contacts gained β ν π (R/2) δ 3p.
  const double gain = beta * poisson * std::numbers::pi * 0.5 * radius * overlap * 3.0 * p;
  const double volume = 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  const double xx_change = -2.0 * (radius - 0.5 * overlap) * gain / volume;
  const double xx_with = with.engine.particle_stress()[0];
  const double xx_without = without.engine.particle_stress()[0];
  EXPECT_NEAR(xx_with - xx_without, xx_change, 1e-6 * std::fabs(xx_change));
}

// A bonded body of three sub-spheres in a column (radii r, 1.2 r, r) between two plates, its
// two bonds compressed by the same length and the plates pressed in until each end sub-sphere is
// in equilibrium: the bonds carry the load through the middle sub-sphere, which touches nothing.
TEST(ParticleStress, BondedBodySumsToTheStressOfItsExternalContacts) {
  const double r[3] = {radius, 1.2 * radius, radius};
  const double gap_free = 0.1 * radius, gap_pressed = 0.05 * radius;  // between sub-sphere faces
  const auto column = [&](double gap) {
    SphereState s;
    double z = 0.0;
    for (int i = 0; i < 3; ++i) {
      if (i > 0) z += r[i - 1] + gap + r[i];
      s.add_sphere(0.0, 0.0, z, r[i], 1541.0, 0);
    }
    s.body = {0, 0, 0};
    return s;
  };
  BondParameters bond;
  bond.normal_stiffness = 5e9;  // N/m³: about 0.1 N, a plate overlap of 0.03 r
  bond.shear_stiffness = 5e9;
  bond.contact_when_bonded = false;
  BondSet bonds = create_bonds(column(gap_free), 1.15, bond);  // rest length at gap_free
  ASSERT_EQ(bonds.size(), 2u);
  SphereState s = column(gap_pressed);
  // Both bonds have R̄ = r (the smaller end): the same spring, the same compression.
  const double bond_force =
      bond.normal_stiffness * std::numbers::pi * radius * radius * (gap_free - gap_pressed);
  double lo = 0.0, hi = 0.1 * radius;  // plate overlap whose Hertz force is the bond force
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (hertz(radius, mid) < bond_force ? lo : hi) = mid;
  }
  const double dw = 0.5 * (lo + hi);
  const double bottom = s.position.z[0] - (radius - dw), top = s.position.z[2] + (radius - dw);
  std::vector<PlaneWall> walls = {PlaneWall{bottom, 1, 0.0, 0}, PlaneWall{top, -1, 0.0, 0}};
  EngineSettings settings{1e-9, {0.0, 0.0, 0.0}, 0.05 * radius};
  const Engine engine(std::move(s), Box{}, table(0.0), std::move(walls), settings,
                      std::move(bonds));
  ASSERT_TRUE(engine.computes_particle_stress());
  ASSERT_EQ(engine.sphere_contacts(), 0);
  const double load = engine.wall_load(0);
  ASSERT_NEAR(load, bond_force, 1e-9 * bond_force);
  // The body's stress from its external contacts: Σ (x_c - x_b) ⊗ f_c over the two plate
  // contacts, f = +load ẑ at z = bottom and -load ẑ at z = top: only zz = -load (top - bottom).
  const double body_zz = -load * (top - bottom);
  double summed[stress_components] = {}, summed_pressure = 0.0;
  const std::vector<double> stress = engine.particle_stress();
  for (std::size_t i = 0; i < 3; ++i) {
    const double volume = 4.0 / 3.0 * std::numbers::pi * r[i] * r[i] * r[i];
    for (int c = 0; c < stress_components; ++c)
      summed[c] += volume * stress[stress_components * i + c];
    summed_pressure += volume * engine.particle_pressure(i);
  }
  EXPECT_NEAR(summed[5], body_zz, 1e-9 * std::fabs(body_zz));
  for (int c = 0; c < 5; ++c)
    EXPECT_NEAR(summed[c], 0.0, 1e-12 * std::fabs(body_zz)) << "component " << c;
  EXPECT_NEAR(summed_pressure, -body_zz / 3.0, 1e-9 * std::fabs(body_zz));
  // The middle sub-sphere carries the load through its bonds alone: p = Σ share d F / (3V).
  const double d = 2.2 * radius + gap_pressed;
  const double middle =
      2.0 * (1.2 / 2.2) * d * bond_force / (4.0 * std::numbers::pi * r[1] * r[1] * r[1]);
  EXPECT_NEAR(engine.particle_pressure(1), middle, 1e-9 * middle);
}

}  // namespace
}  // namespace shapepress::simulate
