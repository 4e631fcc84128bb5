// `fem-plate` with the solid's von Mises plasticity (CalculiX *PLASTIC) and an unloading step
// (issue 37, item 2), against closed forms:
//  - a cube between frictionless plates is in uniaxial compression: its true stress follows
//    σ = σy + H εp past yield (εp the logarithmic plastic strain), its section grows as the
//    plastic flow keeps the volume, and unloading is elastic, so the force falls to zero when the
//    logarithmic strain is back at εp: a residual approach L (1 − exp(−εp));
//  - an elastic sphere unloaded retraces its loading curve and keeps no deformation.
// Coarse meshes: seconds of CalculiX each (the cube's stress is uniform, which quadratic
// tetrahedra represent exactly at any size).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/csv.hpp"
#include "geometry/mesh.hpp"
#include "tests/support/command.hpp"
#include "tests/support/fem_run.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using testing::fresh_directory;
using testing::run_shapepress;
using testing::shell_quoted;

using testing::FemRun;
using testing::press;

// A cube of edge `edge` (mesh units) centred on the origin, its faces split into 2 × 2 squares
// so that the surface has vertices inside each face too.
fs::path cube_stl(const fs::path& dir, double edge) {
  geometry::TriangleMesh mesh;
  const double h = 0.5 * edge;
  // Each face: a 3 × 3 grid of vertices, u × v = the outward normal.
  const auto face = [&](const geometry::Vec3& normal, const geometry::Vec3& u,
                        const geometry::Vec3& v) {
    const auto first = static_cast<std::int32_t>(mesh.vertices.size());
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        mesh.vertices.push_back(h * (normal + (i - 1) * u + (j - 1) * v));
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const std::int32_t a = first + j * 3 + i, b = a + 1, c = a + 4, d = a + 3;
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      }
  };
  const geometry::Vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  face(z, x, y);
  face(-z, y, x);
  face(x, y, z);
  face(-x, z, y);
  face(y, z, x);
  face(-y, x, z);
  // Merge the shared edge and corner vertices: the mesh must be closed and 2-manifold.
  geometry::TriangleMesh merged;
  std::vector<std::int32_t> index(mesh.vertices.size());
  for (std::size_t k = 0; k < mesh.vertices.size(); ++k) {
    std::size_t m = 0;
    while (m < merged.vertices.size() && (merged.vertices[m] - mesh.vertices[k]).norm() > 1e-9)
      ++m;
    if (m == merged.vertices.size()) merged.vertices.push_back(mesh.vertices[k]);
    index[k] = static_cast<std::int32_t>(m);
  }
  for (const auto& t : mesh.triangles)
    merged.triangles.push_back({index[t[0]], index[t[1]], index[t[2]]});
  const fs::path path = dir / "cube.stl";
  fs::create_directories(dir);
  geometry::write_mesh(merged, path);
  return path;
}

// Uniaxial compression of an elastic–plastic bar with linear isotropic hardening, finite strain:
// at the logarithmic strain e (compressive, > 0) the plastic strain is εp = (E e − σy)/(E + H)
// once E e > σy, the true stress σ = E (e − εp), and the section A0 exp(εp + 2ν σ/E) (plastic
// flow keeps the volume; the elastic strain widens the section by ν of it each way).
double uniaxial_force(double e, double area, double youngs, double poisson, double yield,
                      double hardening, double* plastic_strain = nullptr) {
  const double ep = std::max(0.0, (youngs * e - yield) / (youngs + hardening));
  const double stress = youngs * (e - ep);
  if (plastic_strain != nullptr) *plastic_strain = ep;
  return stress * area * std::exp(ep + 2.0 * poisson * stress / youngs);
}

void cube_in_uniaxial_compression(const std::string& name, double hardening, double tolerance) {
  const double edge = 10e-3, youngs = 1e9, poisson = 0.3, yield = 10e6;  // m, Pa
  const double max_deformation = 0.05;
  const fs::path dir = fresh_directory("fem_plastic_cube_" + name);
  const FemRun run =
      press(dir, fmt::format(R"(
[particle]
mesh = "{}"
mesh_unit = "1 mm"
axis = "direction"
direction = [0, 0, 1]
youngs_modulus = "1 GPa"
poisson_ratio = 0.3
material_model = "linear-elastic"
yield_stress = "10 MPa"
hardening_modulus = {}
[plate]
max_deformation = {}
unload = true
[fem]
arc_elements = 2
coarse_arc_elements = 0
increments = 10
)",
                             cube_stl(dir, 10.0).string(), hardening, max_deformation));
  ASSERT_TRUE(run.facts.at("completed").get<bool>());
  EXPECT_EQ(run.facts.at("yield_stress_Pa").get<double>(), yield);
  const auto& step = run.force.column("step");
  const auto& deformation = run.force.column("deformation");
  const auto& top = run.force.column("top_force_N");
  const auto& bottom = run.force.column("bottom_force_N");
  double largest = 0.0, peak_plastic_strain = 0.0;
  for (std::size_t i = 1; i < deformation.size() && step[i] == 1; ++i) {
    const double e = -std::log(1.0 - deformation[i]);
    const double exact =
        uniaxial_force(e, edge * edge, youngs, poisson, yield, hardening, &peak_plastic_strain);
    const double fem = 0.5 * (top[i] + bottom[i]);
    std::printf("cube %s: deformation %.3f: FEM %.6g N, closed form %.6g N: %+.3f %%\n",
                name.c_str(), deformation[i], fem, exact, 100.0 * (fem / exact - 1.0));
    largest = std::max(largest, std::fabs(fem / exact - 1.0));
  }
  EXPECT_LE(largest, tolerance);
  // The unloading is elastic: the force falls to zero where the logarithmic strain is εp.
  const double residual = 1.0 - std::exp(-peak_plastic_strain);
  const double fem_residual = run.facts.at("residual_deformation").get<double>();
  std::printf(
      "cube %s: residual deformation FEM %.6g, closed form %.6g (εp %.6g); CPU %.3g s, "
      "%d C3D10\n",
      name.c_str(), fem_residual, residual, peak_plastic_strain,
      run.facts.at("cpu_s").get<double>(), run.facts.at("elements").get<int>());
  EXPECT_NEAR(fem_residual, residual, tolerance * residual);
  const double peak = uniaxial_force(-std::log(1.0 - max_deformation), edge * edge, youngs, poisson,
                                     yield, hardening);
  EXPECT_NEAR(run.facts.at("peak_force_N").get<double>(), peak, tolerance * peak);
}

TEST(PlasticFem, CubeFollowsTheHardeningLineAndKeepsItsPlasticStrain) {
  cube_in_uniaxial_compression("hardening", 1e8, 0.01);
}

TEST(PlasticFem, PerfectlyPlasticCubeFlowsAtTheYieldStress) {
  cube_in_uniaxial_compression("perfect", 0.0, 0.01);
}

TEST(PlasticFem, ElasticSphereUnloadsAlongItsLoadingCurve) {
  const fs::path dir = fresh_directory("fem_elastic_unload");
  const FemRun run = press(dir, R"(
[sphere]
radius = "1 mm"
youngs_modulus = "1 GPa"
poisson_ratio = 0.3
material_model = "linear-elastic"
[plate]
max_deformation = 0.05
unload = true
[fem]
arc_elements = 8
coarse_arc_elements = 0
increments = 5
)");
  ASSERT_TRUE(run.facts.at("completed").get<bool>());
  const auto& step = run.force.column("step");
  const auto& force = run.force.column("top_force_N");
  ASSERT_EQ(step.size(), 11u);  // the undeformed row, 5 loading, 5 unloading
  // Row 5 + k unloads to the deformation of row 5 − k. Measured: within 0.31 % of the peak
  // force (0.048 N of 15.6 N at 2 %): the penalty contact's nodes close and open one by one,
  // and an increment sees the set of the iteration it converges in.
  for (std::size_t k = 1; k <= 4; ++k) {
    EXPECT_EQ(step[5 + k], 2.0);
    EXPECT_NEAR(force[5 + k], force[5 - k], 5e-3 * force[5]) << k;
  }
  EXPECT_EQ(force[10], 0.0);
  // Elastic: the force is gone only where the plates first touched. The secant through the last
  // two rows with force lands inside the last increment (Hertz's F ∝ Δ^1.5 is convex: above 0).
  const double residual = run.facts.at("residual_deformation").get<double>();
  EXPECT_NEAR(run.facts.at("residual_resolution").get<double>(), 0.01, 1e-9);
  EXPECT_GE(residual, 0.0);
  EXPECT_LT(residual, 0.01);
  EXPECT_NEAR(run.facts.at("peak_force_N").get<double>(), force[5], 1e-12 * force[5]);
}

}  // namespace
}  // namespace shapepress
