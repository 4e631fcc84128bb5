// The paper's rubber sphere (Table 1: R 10 mm, E 18.5 MPa, ν 0.46) by `fem-plate` (issue 26):
// a compressible neo-Hookean sphere between rigid frictionless plates, CalculiX, axisymmetric.
//
// Default suite (reduced, to 10 %, 24 and 16 elements per 45°): the mesh is converged (the two
// within 1 % from 5 % deformation, where fem-plate states it) and the curve meets Hertz in the
// small-deformation limit: F/F_Hertz, fitted linearly in √(Δ/2R) = a/R (the order of the finite
// sphere's first correction, Tatara's Boussinesq term, models.md) over the rows from 1 to 5 %,
// extrapolates to 1 within 2 % (0.995 to 1.002 at 24, 32 and 48 elements per 45°). At finite
// deformation the finite sphere is stiffer than Hertz's half-space: the ratio at 5 % is printed,
// not held to Hertz's 2 % (it is near +10 %, docs/measurements.md, as Tatara's +16 % says it should
// be). Full validation (SHAPEPRESS_FULL_VALIDATION=1): the shipped config to 40 %, mesh-converged
// within 1 % from 5 %, and the difference from Tatara's curve printed at 5/10/20/30/40 %.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "analysis/sphere_plates.hpp"
#include "common/csv.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using testing::fresh_directory;
using testing::run_shapepress;
using testing::shell_quoted;

const analysis::ElasticSphere rubber{0.01, 18.5e6, 0.46};

bool full_validation() {
  const char* value = std::getenv("SHAPEPRESS_FULL_VALIDATION");
  return value != nullptr && std::string(value) == "1";
}

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

struct FemRun {
  CsvTable force;
  nlohmann::json facts;
};

FemRun press(const std::string& name, const std::string& config_text) {
  const fs::path dir = fresh_directory("fem_" + name);
  testing::write_text(dir / "fem.toml", config_text);
  const auto result =
      run_shapepress("--quiet fem-plate --config " + shell_quoted(dir / "fem.toml") + " --out " +
                     shell_quoted(dir / "run"));
  EXPECT_EQ(result.exit_code, 0) << result.output;
  return {read_csv(dir / "run" / "force.csv"), read_json(dir / "run" / "run.json")["facts"]};
}

// F/F_Hertz = c0 + c1 √ε by least squares over the force.csv rows with 1 % ≤ ε ≤ 5 %: c0 is
// the small-deformation limit, c1 the finite particle's first correction.
struct HertzLimit {
  double limit = 0.0, slope = 0.0;
  int rows = 0;
};
HertzLimit hertz_limit(const CsvTable& force) {
  const auto& deformation = force.column("deformation");
  const auto& f = force.column("top_force_N");
  const auto& hertz = force.column("hertz_force_N");
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < deformation.size(); ++i) {
    if (deformation[i] < 0.01 - 1e-12 || deformation[i] > 0.05 + 1e-12) continue;
    const double x = std::sqrt(deformation[i]), y = f[i] / hertz[i];
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  HertzLimit fit;
  fit.rows = static_cast<int>(n);
  fit.slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  fit.limit = (sy - fit.slope * sx) / n;
  return fit;
}

const std::string rubber_sphere = R"(
[sphere]
radius = "10 mm"
youngs_modulus = "18.5 MPa"
poisson_ratio = 0.46
material_model = "neo-hookean"
)";

TEST(RubberSphereFem, MeetsHertzAtSmallDeformationAndIsMeshConverged) {
  const FemRun run = press("small", rubber_sphere + R"(
[plate]
max_deformation = 0.1
[fem]
arc_elements = 24
coarse_arc_elements = 16
increments = 10
)");
  ASSERT_TRUE(run.facts.at("completed").get<bool>());
  const double difference = run.facts.at("mesh_difference_max").get<double>();
  std::printf("mesh difference 16 vs 24 per 45 deg, 5-10 %%: %+.3f %%\n", 100.0 * difference);
  EXPECT_LE(std::fabs(difference), 0.01);  // the issue's mesh convergence criterion

  const auto& deformation = run.force.column("deformation");
  const auto& force = run.force.column("top_force_N");
  const auto& hertz = run.force.column("hertz_force_N");
  for (std::size_t i = 0; i < deformation.size(); ++i)
    EXPECT_NEAR(hertz[i], analysis::hertz_plate_force(rubber, 0.02 * deformation[i]),
                1e-9 * hertz[i] + 1e-12);
  const HertzLimit fit = hertz_limit(run.force);
  ASSERT_EQ(fit.rows, 5);
  const double limit = fit.limit, slope = fit.slope;
  const double at_5 = force[5] / hertz[5];
  ASSERT_NEAR(deformation[5], 0.05, 1e-12);
  std::printf(
      "F/F_Hertz -> %.4f at zero deformation (slope %.3f per sqrt(eps)); %.4f at 5 %%; "
      "Tatara's %.4f\n",
      limit, slope, at_5,
      analysis::tatara_plate_force(rubber, 1e-3) / analysis::hertz_plate_force(rubber, 1e-3));
  EXPECT_NEAR(limit, 1.0, 0.02);  // Hertz is the small-deformation limit
  EXPECT_GT(slope, 0.0);          // a finite sphere stiffens away from it (Tatara)
}

// Spheroids of the same rubber pressed along their axis of revolution (a = 10 mm, c = 15 mm
// prolate and 7 mm oblate): the plates touch the pole, whose two principal radii of curvature
// are both a²/c, so Hertz's sphere of that radius is the small-deformation limit. Measured
// limits 0.996 (prolate) and 0.980 (oblate, whose force rises fastest: it is thin along the
// plates' axis); within 3 %.
TEST(RubberSphereFem, SpheroidsMeetHertzForThePoleCurvature) {
  for (const char* polar : {"15 mm", "7 mm"}) {
    const FemRun run = press(std::string("spheroid_") + polar[0] + polar[1], fmt::format(R"(
[sphere]
radius = "10 mm"
polar_radius = "{}"
youngs_modulus = "18.5 MPa"
poisson_ratio = 0.46
[plate]
max_deformation = 0.05
[fem]
arc_elements = 24
coarse_arc_elements = 0
increments = 5
)",
                                                                                         polar));
    const double c = std::stod(polar) * 1e-3;
    EXPECT_NEAR(run.facts.at("pole_curvature_radius_m").get<double>(), 0.01 * 0.01 / c, 1e-15);
    const auto& deformation = run.force.column("deformation");
    const auto& hertz = run.force.column("hertz_force_N");
    const analysis::ElasticSphere pole{0.01 * 0.01 / c, 18.5e6, 0.46};
    EXPECT_NEAR(hertz.back(), analysis::hertz_plate_force(pole, 2 * c * deformation.back()),
                1e-9 * hertz.back());
    const HertzLimit fit = hertz_limit(run.force);
    ASSERT_EQ(fit.rows, 5);
    std::printf("spheroid c = %s: F/F_Hertz(R = a^2/c) -> %.4f at zero deformation (slope %.3f)\n",
                polar, fit.limit, fit.slope);
    EXPECT_NEAR(fit.limit, 1.0, 0.03) << polar;
  }
}

TEST(RubberSphereFem, FullCurveToFortyPercentBesideTatara) {
  if (!full_validation()) GTEST_SKIP() << "SHAPEPRESS_FULL_VALIDATION=1 runs the 40 % curve";
  std::ifstream shipped(testing::repository_root() / "pipelines/configs/fem-rubber-sphere.toml");
  const std::string config((std::istreambuf_iterator<char>(shipped)),
                           std::istreambuf_iterator<char>());
  const FemRun run = press("full", config);
  ASSERT_TRUE(run.facts.at("completed").get<bool>());
  const double difference = run.facts.at("mesh_difference_max").get<double>();
  std::printf("mesh difference over 5-40 %%: %+.3f %%\n", 100.0 * difference);
  EXPECT_LE(std::fabs(difference), 0.01);
  const auto& forces = run.facts.at("force_N_at_deformation");
  for (const double eps : {0.05, 0.1, 0.2, 0.3, 0.4}) {
    const double fem = forces.at(fmt::format("{:g}", eps)).get<double>();
    const double tatara = analysis::tatara_plate_force(rubber, 0.02 * eps);
    std::printf("%2.0f %%: FEM %.4g N, Tatara %.4g N (%+.1f %%), Hertz %.4g N\n", 100 * eps, fem,
                tatara, 100.0 * (fem / tatara - 1.0),
                analysis::hertz_plate_force(rubber, 0.02 * eps));
    EXPECT_GT(fem, analysis::hertz_plate_force(rubber, 0.02 * eps));
  }
}

}  // namespace
}  // namespace shapepress
