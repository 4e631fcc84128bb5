// The pieces of the FEM plate rig that need no solver: the quarter-disc mesh, the neo-Hookean
// constants, the deck's switches and the reading of CalculiX's totals.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "common/error.hpp"
#include "fem/calculix_deck.hpp"
#include "fem/calculix_process.hpp"
#include "fem/quarter_disc_mesh.hpp"
#include "tests/support/files.hpp"

namespace shapepress::fem {
namespace {

double quad_area(const QuarterDiscMesh& mesh, const std::array<int, 4>& q) {
  double twice = 0.0;
  for (int k = 0; k < 4; ++k) {
    const auto& a = mesh.nodes[q[k] - 1];
    const auto& b = mesh.nodes[q[(k + 1) % 4] - 1];
    twice += a[0] * b[1] - b[0] * a[1];
  }
  return 0.5 * twice;
}

TEST(QuarterDiscMesh, FillsTheQuarterDiscWithCounterClockwiseQuads) {
  const double radius = 0.01;
  const int n = 8;
  const QuarterDiscMesh mesh = quarter_disc_mesh(radius, n);
  const int m = static_cast<int>(std::ceil(0.6 * n));
  EXPECT_EQ(mesh.quads.size(), static_cast<std::size_t>(n * n + 2 * n * m));
  double area = 0.0;
  for (const auto& q : mesh.quads) {
    const double a = quad_area(mesh, q);
    EXPECT_GT(a, 0.0);  // CAX4 needs counter-clockwise nodes
    area += a;
  }
  // The arc is a polygon of 2n chords of at most the coarsest arc step (45°·(1 − (1 − 1/n)^1.5)):
  // the area it misses is below R²/2 · Σ (θ − sin θ) < 0.5 % of πR²/4 here.
  const double quarter = std::numbers::pi * radius * radius / 4.0;
  EXPECT_LT(area, quarter);
  EXPECT_GT(area, 0.995 * quarter);
  EXPECT_EQ(mesh.arc_faces.size(), static_cast<std::size_t>(2 * n));
  for (const auto& [element, face] : mesh.arc_faces) {
    const auto& q = mesh.quads[element - 1];
    for (int node : {q[face - 1], q[face % 4]})
      EXPECT_NEAR(std::hypot(mesh.nodes[node - 1][0], mesh.nodes[node - 1][1]), radius,
                  1e-12 * radius);
  }
  for (int node : mesh.axis_nodes)
    EXPECT_EQ(mesh.nodes[node - 1][0], 0.0);
  for (int node : mesh.equator_nodes)
    EXPECT_EQ(mesh.nodes[node - 1][1], 0.0);
  EXPECT_EQ(mesh.axis_nodes.size(), static_cast<std::size_t>(n + m + 1));
  EXPECT_EQ(mesh.equator_nodes.size(), static_cast<std::size_t>(n + m + 1));
  EXPECT_EQ(mesh.nodes[mesh.pole_node - 1][0], 0.0);
  EXPECT_NEAR(mesh.nodes[mesh.pole_node - 1][1], radius, 1e-15);
  // Graded towards the pole: its arc element is smaller than the uniform 45°/n step.
  EXPECT_LT(pole_element_size(mesh), radius * std::numbers::pi / 4.0 / n);
}

TEST(QuarterDiscMesh, StretchesToASpheroidWithItsArcOnTheEllipse) {
  const double a = 0.01, c = 0.015;
  const QuarterDiscMesh mesh = stretched_to_spheroid(quarter_disc_mesh(a, 6), c);
  EXPECT_EQ(mesh.polar_radius, c);
  EXPECT_NEAR(mesh.nodes[mesh.pole_node - 1][1], c, 1e-15);
  for (const auto& [element, face] : mesh.arc_faces) {
    const auto& node = mesh.nodes[mesh.quads[element - 1][face - 1] - 1];
    EXPECT_NEAR(std::pow(node[0] / a, 2) + std::pow(node[1] / c, 2), 1.0, 1e-12);
  }
  const std::string deck = plate_deck(mesh, FemPlateConfig{});
  EXPECT_NE(deck.find("PLATE,2,2,-6\n"), std::string::npos);  // Δ/2 = 0.4 c, in mm
}

TEST(QuarterDiscMesh, RejectsTooFewElements) {
  EXPECT_THROW(quarter_disc_mesh(0.01, 1), InputError);
  EXPECT_THROW(quarter_disc_mesh(-1.0, 8), InputError);
}

TEST(NeoHooke, ConstantsGiveTheSmallStrainModuli) {
  const double e = 18.5e6, nu = 0.46;
  const NeoHookeConstants c = neo_hooke_constants(e, nu);
  const double shear = 2.0 * c.c10, bulk = 2.0 / c.d1;
  EXPECT_NEAR(shear, e / (2.0 * (1.0 + nu)), 1e-9 * e);
  EXPECT_NEAR(bulk, e / (3.0 * (1.0 - 2.0 * nu)), 1e-9 * e);
  EXPECT_NEAR(9.0 * bulk * shear / (3.0 * bulk + shear), e, 1e-9 * e);  // E back from K, μ
}

TEST(PlateDeck, StatesTheMaterialLawAndTheGeometry) {
  FemPlateConfig config;
  config.youngs_modulus = 18.5e6;
  config.poisson_ratio = 0.46;
  config.arc_elements = 4;
  const QuarterDiscMesh mesh = quarter_disc_mesh(config.radius, config.arc_elements);
  const std::string neo = plate_deck(mesh, config);
  EXPECT_NE(neo.find("*HYPERELASTIC,NEO HOOKE"), std::string::npos);
  EXPECT_NE(neo.find("*STEP,NLGEOM"), std::string::npos);
  EXPECT_EQ(neo.find("*FRICTION"), std::string::npos);
  // The plate moves Δ/2 = max_deformation · R (in mm) down.
  EXPECT_NE(neo.find("PLATE,2,2,-4\n"), std::string::npos);
  config.material = MaterialModel::linear_elastic;
  config.nonlinear_geometry = false;
  config.friction = 0.3;
  const std::string linear = plate_deck(mesh, config);
  EXPECT_NE(linear.find("*ELASTIC\n18.5,0.46"), std::string::npos);
  EXPECT_EQ(linear.find("NLGEOM"), std::string::npos);
  EXPECT_NE(linear.find("*FRICTION\n0.3,"), std::string::npos);
}

TEST(CalculixResults, ReadsTheTotalsOfANodeSet) {
  const auto dat = shapepress::testing::fresh_directory("fem_totals") / "totals.dat";
  std::ofstream(dat) << "\n                        S T E P       1\n\n\n"
                        " total force (fx,fy,fz) for set PLATE and time  0.2500000E-01\n\n"
                        "        5.522026E-30 -4.922492E-03  2.524355E-29\n"
                        " displacements (vx,vy,vz) for set POLE and time  0.2500000E-01\n\n"
                        "        30  1.0E-10 -2.0E-01  0.0E+00\n"
                        " total force (fx,fy,fz) for set PLATE and time  0.5000000E-01\n\n"
                        "        1.0E-29 -9.844984E-03 -2.524355E-29\n";
  const std::vector<NodeSetTotal> totals = read_total_forces(dat, "plate");
  ASSERT_EQ(totals.size(), 2u);
  EXPECT_DOUBLE_EQ(totals[0].step_time, 0.025);
  EXPECT_DOUBLE_EQ(totals[0].fy, -4.922492e-3);
  EXPECT_DOUBLE_EQ(totals[1].step_time, 0.05);
  EXPECT_DOUBLE_EQ(totals[1].fy, -9.844984e-3);
  std::filesystem::remove(dat);
  EXPECT_THROW(read_total_forces(dat, "PLATE"), InputError);
}

}  // namespace
}  // namespace shapepress::fem
