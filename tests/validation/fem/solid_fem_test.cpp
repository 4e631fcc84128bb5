// `fem-plate` on a closed mesh: the 3D model of quadratic tetrahedra (issue 26).
//
// Default suite (coarse meshes, seconds of CalculiX each):
//  - the rubber sphere of Table 1 (R 10 mm, E 18.5 MPa, ν 0.46) as a 3D mesh against the
//    axisymmetric model from 4 to 10 % deformation: the two models of one sphere agree;
//  - a triaxial ellipsoid (semi-axes 12, 10, 8 mm) pressed along its short and its long axis: the
//    principal axes are found, the Hertz column is Hertz's elliptical contact for the pole's
//    principal curvatures, and the FEM force's ratio to it extrapolates to 1 at zero deformation
//    (F/F_Hertz = c0 + c1 √ε over the rows from 1 to 5 %, as the axisymmetric spheroid check).
// Full validation (SHAPEPRESS_FULL_VALIDATION=1): the sphere at a finer mesh to 10 %.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "analysis/sphere_plates.hpp"
#include "common/csv.hpp"
#include "geometry/icosphere.hpp"
#include "tests/support/command.hpp"
#include "tests/support/fem_run.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using testing::fresh_directory;
using testing::run_shapepress;
using testing::shell_quoted;

constexpr double youngs_modulus = 18.5e6, poisson_ratio = 0.46;

bool full_validation() {
  const char* value = std::getenv("SHAPEPRESS_FULL_VALIDATION");
  return value != nullptr && std::string(value) == "1";
}

using testing::FemRun;
using testing::press;

// An ellipsoid (mm) as a fine icosphere mesh: level 5, edges of about 1/30 of the radius, so the
// facets are well inside the contact radius at 1 % deformation (0.1 R).
fs::path ellipsoid_stl(const fs::path& dir, const geometry::Vec3& semi_axes_mm) {
  const fs::path path = dir / "ellipsoid.stl";
  geometry::write_mesh(geometry::ellipsoid_mesh(semi_axes_mm, 5), path);
  return path;
}

std::string solid_config(const fs::path& mesh, const std::string& axis, double max_deformation,
                         int increments, int arc_elements, int coarse_arc_elements) {
  return fmt::format(R"(
[particle]
mesh = "{}"
mesh_unit = "1 mm"
axis = "{}"
youngs_modulus = "18.5 MPa"
poisson_ratio = 0.46
[plate]
max_deformation = {}
[fem]
arc_elements = {}
coarse_arc_elements = {}
increments = {}
)",
                     mesh.string(), axis, max_deformation, arc_elements, coarse_arc_elements,
                     increments);
}

// F/F_Hertz = c0 + c1 √ε by least squares over the rows with 1 % ≤ ε ≤ 5 %.
struct HertzLimit {
  double limit = 0.0, slope = 0.0;
  int rows = 0;
};
HertzLimit hertz_limit(const CsvTable& force) {
  const auto& deformation = force.column("deformation");
  const auto& top = force.column("top_force_N");
  const auto& bottom = force.column("bottom_force_N");
  const auto& hertz = force.column("hertz_force_N");
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < deformation.size(); ++i) {
    if (deformation[i] < 0.01 - 1e-12 || deformation[i] > 0.05 + 1e-12) continue;
    const double x = std::sqrt(deformation[i]), y = 0.5 * (top[i] + bottom[i]) / hertz[i];
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  HertzLimit fit;
  fit.rows = static_cast<int>(n);
  fit.slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  fit.limit = (sy - fit.slope * sx) / n;
  return fit;
}

double mean_force(const CsvTable& force, std::size_t row) {
  return 0.5 * (force.column("top_force_N")[row] + force.column("bottom_force_N")[row]);
}

void sphere_against_axisymmetric(const std::string& name, int arc_elements, int coarse,
                                 double max_deformation, int increments, double from,
                                 double tolerance) {
  const fs::path dir = fresh_directory("fem_solid_sphere_" + name);
  const FemRun solid =
      press(dir / "solid", solid_config(ellipsoid_stl(dir, {10.0, 10.0, 10.0}), "short",
                                        max_deformation, increments, arc_elements, coarse));
  const FemRun axisymmetric = press(dir / "axisymmetric", fmt::format(R"(
[sphere]
radius = "10 mm"
youngs_modulus = "18.5 MPa"
poisson_ratio = 0.46
[plate]
max_deformation = {}
[fem]
arc_elements = 24
coarse_arc_elements = 0
increments = {}
)",
                                                                      max_deformation, increments));
  ASSERT_TRUE(solid.facts.at("completed").get<bool>());
  EXPECT_EQ(solid.facts.at("model"), "solid");
  EXPECT_EQ(solid.facts.at("element_type"), "C3D10");
  EXPECT_NEAR(solid.facts.at("height_m").get<double>(), 0.02, 1e-6);
  const auto& deformation = solid.force.column("deformation");
  const auto& reference = axisymmetric.force.column("top_force_N");
  ASSERT_EQ(deformation.size(), reference.size());
  double largest = 0.0;
  for (std::size_t i = 0; i < deformation.size(); ++i) {
    if (deformation[i] < from - 1e-12) continue;
    const double difference = mean_force(solid.force, i) / reference[i] - 1.0;
    std::printf("sphere %s: %4.1f %%: 3D %.4g N (%d C3D10), axisymmetric %.4g N: %+.2f %%\n",
                name.c_str(), 100.0 * deformation[i], mean_force(solid.force, i),
                solid.facts.at("elements").get<int>(), reference[i], 100.0 * difference);
    largest = std::max(largest, std::fabs(difference));
  }
  std::printf("sphere %s: mesh difference (coarse %d against %d) %+.2f %%, CPU %.3g s + %.3g s\n",
              name.c_str(), coarse, arc_elements,
              100.0 * solid.facts.at("mesh_difference_max").get<double>(),
              solid.facts.at("cpu_s").get<double>(), solid.facts.at("coarse_cpu_s").get<double>());
  EXPECT_LE(largest, tolerance);
  // The anchors hold a symmetric particle without reaction: the two plates carry one force.
  EXPECT_LE(solid.facts.at("plate_force_imbalance_max").get<double>(), 0.05);
}

TEST(SolidFem, SphereAgreesWithTheAxisymmetricModel) {
  // Measured: +2 to +5 % from 4 to 10 % at 3 per 45° (the coarse mesh is stiff where the contact
  // spans few elements); within 6 %.
  sphere_against_axisymmetric("coarse", 3, 2, 0.1, 5, 0.04, 0.06);
}

TEST(SolidFem, SphereAgreesWithTheAxisymmetricModelFiner) {
  if (!full_validation()) GTEST_SKIP() << "SHAPEPRESS_FULL_VALIDATION=1 runs the finer mesh";
  // Measured at 6 per 45° (2099 C3D10, 41 s CPU): −0.2 to +0.7 % from 4 to 10 %.
  sphere_against_axisymmetric("fine", 6, 4, 0.1, 10, 0.04, 0.02);
}

void ellipsoid_against_hertz(const std::string& axis, int arc_elements, double tolerance) {
  const geometry::Vec3 semi_axes(12.0, 10.0, 8.0);  // mm
  const fs::path dir = fresh_directory("fem_solid_ellipsoid_" + axis);
  const FemRun run =
      press(dir, solid_config(ellipsoid_stl(dir, semi_axes), axis, 0.05, 5, arc_elements, 0));
  ASSERT_TRUE(run.facts.at("completed").get<bool>());
  // Short: z (8 mm); long: x (12 mm). The pole's principal radii are the other two squared over
  // this one (x²/a² + … = 1 near the pole: z = c − x²/(2a²/c) − y²/(2b²/c)).
  const int along = axis == "short" ? 2 : 0;
  const auto& direction = run.facts.at("axis_direction");
  EXPECT_NEAR(std::fabs(direction[along].get<double>()), 1.0, 1e-6) << direction;
  const double c = semi_axes[along] * 1e-3;
  EXPECT_NEAR(run.facts.at("height_m").get<double>(), 2.0 * c, 1e-3 * c);
  std::array<double, 2> radii{};
  for (int k = 0, j = 0; k < 3; ++k)
    if (k != along) radii[static_cast<std::size_t>(j++)] = std::pow(semi_axes[k] * 1e-3, 2) / c;
  const double modulus = youngs_modulus / (1.0 - poisson_ratio * poisson_ratio);
  const auto& deformation = run.force.column("deformation");
  const auto& hertz = run.force.column("hertz_force_N");
  for (std::size_t i = 1; i < deformation.size(); ++i) {
    // Each pole takes half the approach (symmetry).
    const double exact =
        analysis::hertz_elliptic_contact_force(modulus, radii[0], radii[1], c * deformation[i]);
    // The column's curvatures are fitted to the mesh: within 2 % of the ellipsoid's.
    EXPECT_NEAR(hertz[i], exact, 0.02 * exact) << deformation[i];
  }
  const HertzLimit fit = hertz_limit(run.force);
  ASSERT_EQ(fit.rows, 5);
  std::printf(
      "ellipsoid 12 x 10 x 8 mm along its %s axis (R' = %.4g mm, R'' = %.4g mm): F/F_Hertz -> "
      "%.4f at zero deformation (slope %.3f); %d C3D10, CPU %.3g s\n",
      axis.c_str(), 1e3 * radii[0], 1e3 * radii[1], fit.limit, fit.slope,
      run.facts.at("elements").get<int>(), run.facts.at("cpu_s").get<double>());
  EXPECT_NEAR(fit.limit, 1.0, tolerance);
}

// At 3 elements per 45° of the pole's smaller radius the contact at 1 % spans about one element
// and the coarse tetrahedra are stiff: the limit comes out 10–15 % high (measured 1.154 along the
// short axis, 1.106 along the long one; 1.10 at 4 per 45° along the short axis), so the default
// suite holds it within 20 % — a Hertz of the wrong curvature (the sphere of the pole's distance
// c) would be 37 % off along the short axis. (At 6 per 45° CalculiX stopped in the first
// increment on a nonpositive Jacobian: no finer check yet.)
TEST(SolidFem, TriaxialEllipsoidInitialStiffnessMeetsHertz) {
  ellipsoid_against_hertz("short", 3, 0.2);
  ellipsoid_against_hertz("long", 3, 0.2);
}

}  // namespace
}  // namespace shapepress
