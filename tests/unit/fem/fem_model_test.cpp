// The pieces of the FEM plate rig that need no solver: the quarter-disc mesh, the neo-Hookean
// constants, the deck's switches, the plasticity keys, the reading of CalculiX's totals and of
// the unloading curve.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "common/config.hpp"
#include "common/error.hpp"
#include "fem/calculix_deck.hpp"
#include "fem/calculix_process.hpp"
#include "fem/fem_plate.hpp"
#include "fem/fem_plate_config.hpp"
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

std::string_view after(const std::string& text, const std::string& marker) {
  const std::size_t at = text.find(marker);
  return at == std::string::npos ? std::string_view() : std::string_view(text).substr(at);
}

TEST(PlateDeck, WritesPlasticityAndTheUnloadingStepOnlyWhenAsked) {
  FemPlateConfig config;
  config.youngs_modulus = 1e9;
  config.poisson_ratio = 0.3;
  config.material = MaterialModel::linear_elastic;
  config.arc_elements = 4;
  const QuarterDiscMesh mesh = quarter_disc_mesh(config.radius, config.arc_elements);
  const std::string elastic = plate_deck(mesh, config);
  EXPECT_EQ(elastic.find("*PLASTIC"), std::string::npos);
  EXPECT_EQ(elastic.find("*STEP"), elastic.rfind("*STEP"));  // one step
  config.yield_stress = 50e6;
  config.hardening_modulus = 2e8;
  config.unload = true;
  const std::string plastic = plate_deck(mesh, config);
  // In MPa: σy = 50, and at εp = 10 the line reaches 50 + 200 × 10.
  EXPECT_TRUE(
      after(plastic, "*ELASTIC").starts_with("*ELASTIC\n1000,0.3\n*PLASTIC\n50,0\n2050,10\n"))
      << plastic;
  // The second step takes the plate back to where it first touched, and prints the same.
  const std::string_view second = after(plastic, "*END STEP\n*STEP");
  ASSERT_FALSE(second.empty());
  EXPECT_NE(second.find("*BOUNDARY\nPLATE,2,2,0\n"), std::string_view::npos);
  EXPECT_NE(second.find("*NODE PRINT,NSET=PLATE,TOTALS=ONLY\nRF\n"), std::string_view::npos);
  // Perfectly plastic: one point.
  config.hardening_modulus = 0.0;
  EXPECT_TRUE(after(plate_deck(mesh, config), "*PLASTIC").starts_with("*PLASTIC\n50,0\n*"));
}

FemPlateConfig sphere_config(const std::string& extra) {
  return read_fem_plate_config(ConfigTable::parse(
      "[sphere]\nradius = \"1 mm\"\nyoungs_modulus = \"1 GPa\"\npoisson_ratio = 0.3\n" + extra,
      "fem.toml"));
}

void expect_input_error_naming(const std::string& extra, const std::string& name) {
  try {
    sphere_config(extra);
    ADD_FAILURE() << "no error for " << extra;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

TEST(FemPlateConfig, ReadsPlasticityAndRejectsWhatCalculixCannotRun) {
  const FemPlateConfig elastic = sphere_config("");
  EXPECT_FALSE(elastic.plastic());
  EXPECT_FALSE(elastic.unload);
  const FemPlateConfig plastic = sphere_config(
      "material_model = \"linear-elastic\"\nyield_stress = \"40 MPa\"\nhardening_modulus = "
      "\"0.1 GPa\"\n[plate]\nunload = true\n");
  ASSERT_TRUE(plastic.plastic());
  EXPECT_DOUBLE_EQ(*plastic.yield_stress, 40e6);
  EXPECT_DOUBLE_EQ(plastic.hardening_modulus, 1e8);
  EXPECT_TRUE(plastic.unload);
  // The effective config reads back to the same values.
  const FemPlateConfig again =
      read_fem_plate_config(ConfigTable::parse(fem_plate_config_toml(plastic), "effective.toml"));
  EXPECT_EQ(again.yield_stress, plastic.yield_stress);
  EXPECT_EQ(again.hardening_modulus, plastic.hardening_modulus);
  EXPECT_TRUE(again.unload);
  EXPECT_EQ(fem_plate_config_toml(elastic).find("yield_stress"), std::string::npos);
  // *PLASTIC extends *ELASTIC only; the neo-Hookean default cannot yield.
  expect_input_error_naming("yield_stress = \"40 MPa\"\n", "sphere.material_model");
  expect_input_error_naming("material_model = \"linear-elastic\"\nyield_stress = \"-4 MPa\"\n",
                            "yield_stress");
  expect_input_error_naming("material_model = \"linear-elastic\"\nhardening_modulus = 1e8\n",
                            "hardening_modulus");
  expect_input_error_naming(
      "material_model = \"linear-elastic\"\nyield_stress = 4e7\nhardening_modulus = -1\n",
      "hardening_modulus");
}

FemPlateRow row(int step, double deformation, double force) {
  FemPlateRow r;
  r.step = step;
  r.deformation = deformation;
  r.approach = 0.002 * deformation;  // a 2 mm particle
  r.force = force;
  return r;
}

TEST(Unloading, TheResidualIsWhereTheUnloadingForceFallsToZero) {
  FemPlateRun run;
  run.rows = {row(1, 0.0, 0.0), row(1, 0.1, 5.0),  row(1, 0.2, 8.0), row(2, 0.15, 6.0),
              row(2, 0.1, 2.0), row(2, 0.05, 0.0), row(2, 0.0, 0.0)};
  UnloadingResult u = unloading_result(run);
  EXPECT_DOUBLE_EQ(u.peak_force, 8.0);
  // The secant through (0.15, 6) and (0.1, 2) reaches zero at 0.075, inside (0.05, 0.1).
  EXPECT_NEAR(u.residual_deformation, 0.075, 1e-12);
  EXPECT_NEAR(u.residual_approach, 0.002 * 0.075, 1e-15);
  EXPECT_NEAR(u.resolution, 0.05, 1e-12);
  // A secant that would cross beyond the first row without force is held at that row.
  run.rows[4].force = 5.5;
  u = unloading_result(run);
  EXPECT_NEAR(u.residual_deformation, 0.05, 1e-12);
  // The plates never let go: no residual to state.
  run.rows.resize(5);
  EXPECT_TRUE(std::isnan(unloading_result(run).residual_deformation));
  // The loading curve alone is what force_at interpolates.
  run.rows = {row(1, 0.0, 0.0), row(1, 0.2, 8.0), row(2, 0.1, 2.0)};
  EXPECT_DOUBLE_EQ(force_at(run, 0.1), 4.0);
  EXPECT_TRUE(std::isnan(force_at(run, 0.3)));
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
