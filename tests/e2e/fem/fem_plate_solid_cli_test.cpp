// `fem-plate` on a closed mesh (the 3D model) from the command line, and a generated particle's
// BMS template calibrated against its own FEM curve along its long and its short axis (issue 26),
// at reduced size: a coarse mesh, few sub-spheres, few calibration runs. An Avicel body of the
// bed study with the shipped calibrated bonds against its FEM, and with Table 4's (issue 20). And
// the bad inputs: an open mesh, a self-intersecting mesh and a missing gmsh exit 2 naming the file
// or the program.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "analysis/curves.hpp"
#include "common/csv.hpp"
#include "geometry/icosphere.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using testing::fresh_directory;
using ::testing::HasSubstr;
using testing::run_shapepress;
using testing::shell_quoted;

// text with its first `what` replaced by `with` (a test failure when it has none).
std::string replaced(const std::string& text, const std::string& what, const std::string& with) {
  const std::size_t at = text.find(what);
  EXPECT_NE(at, std::string::npos) << what;
  if (at == std::string::npos) return text;
  return text.substr(0, at) + with + text.substr(at + what.size());
}

nlohmann::json facts_of(const fs::path& run) {
  std::ifstream in(run / "run.json");
  return nlohmann::json::parse(in)["facts"];
}

std::string particle_config(const fs::path& mesh, const std::string& axis, const std::string& unit,
                            double max_deformation, int increments, int arc_elements = 3) {
  return fmt::format(R"(
[particle]
mesh = "{}"
mesh_unit = "{}"
axis = "{}"
youngs_modulus = "18.5 MPa"
poisson_ratio = 0.46
[plate]
max_deformation = {}
[fem]
arc_elements = {}
coarse_arc_elements = 0
increments = {}
)",
                     mesh.string(), unit, axis, max_deformation, arc_elements, increments);
}

TEST(FemPlateSolidCli, RefusesOpenAndSelfIntersectingMeshesAndAMissingGmsh) {
  const fs::path dir = fresh_directory("fem_solid_bad");
  geometry::TriangleMesh ball = geometry::icosphere(2);
  geometry::write_mesh(ball, dir / "ball.stl");
  geometry::TriangleMesh open = ball;
  open.triangles.pop_back();
  geometry::write_mesh(open, dir / "open.stl");
  // Two balls through each other: closed and manifold, but the surfaces cross.
  geometry::TriangleMesh crossing = ball;
  const auto offset = static_cast<std::int32_t>(ball.vertices.size());
  for (const geometry::Vec3& v : ball.vertices)
    crossing.vertices.push_back(v + geometry::Vec3(0.5, 0.0, 0.0));
  for (const auto& t : ball.triangles)
    crossing.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  geometry::write_mesh(crossing, dir / "crossing.off");

  const auto press = [&](const std::string& mesh, const std::string& extra) {
    testing::write_text(dir / (mesh + ".toml"),
                        particle_config(dir / mesh, "short", "1 mm", 0.05, 1));
    return run_shapepress("--quiet fem-plate --config " + shell_quoted(dir / (mesh + ".toml")) +
                          " --out " + shell_quoted(dir / ("run_" + mesh)) + extra);
  };
  auto r = press("open.stl", "");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("open.stl"));
  EXPECT_THAT(r.output, HasSubstr("open, 3 edges border one triangle only"));
  r = press("crossing.off", "");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("crossing.off"));
  EXPECT_THAT(r.output, HasSubstr("self-intersecting"));
  r = press("ball.stl", " --gmsh no-such-gmsh");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no-such-gmsh"));
  EXPECT_THAT(r.output, HasSubstr("gmsh"));
  EXPECT_THAT(r.output, HasSubstr("install-deps"));
  // [sphere] and [particle] together: one particle is pressed.
  testing::write_text(dir / "both.toml",
                      particle_config(dir / "ball.stl", "short", "1 mm", 0.05, 1) +
                          "[sphere]\nradius = \"1 mm\"\n");
  r = run_shapepress("fem-plate --config " + shell_quoted(dir / "both.toml") + " --out " +
                     shell_quoted(dir / "both"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("[sphere] and [particle]"));
}

// generate → fill (a BMS template of 60 sub-spheres) → fem-plate along the long and the short
// axis (2 elements per 45° at the plates, to 6 %) → calibrate the bond modulus of the template
// against each FEM curve over 2–6 %.
TEST(FemPlateSolidCli, GeneratedParticleCalibratedAgainstItsOwnFem) {
  const fs::path dir = fresh_directory("fem_solid_calibrate");
  const std::string data = std::string(SHAPEPRESS_TEST_DATA) + "/geometry/";
  auto r = run_shapepress("--quiet generate --targets " + data +
                          "paper_box_targets.toml --count 1 --seed 4 --out " +
                          shell_quoted(dir / "shapes"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path mesh = dir / "shapes" / "particle_0000.stl";
  r = run_shapepress("--quiet fill " + shell_quoted(mesh) + " --count 60 --out " +
                     shell_quoted(dir / "templates.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;

  const std::string shipped =
      testing::read_text(testing::repository_root() / "pipelines/configs/rubber-sphere.toml");
  // The shipped rubber BMS, its [sphere] radius and the sphere fill's keys replaced by the
  // template; to 6 % deformation.
  std::string config = shipped;
  config.replace(config.find("radius = \"10 mm\"\n"), 17, "");
  for (const char* key :
       {"count = 545\n", "lattice = \"carved\"\n", "placement = \"inside\"\n", "seed = 1\n"})
    config.replace(config.find(key), std::string(key).size(), "");
  config.replace(config.find("max_deformation = 0.4"), 21, "max_deformation = 0.06");
  config.replace(config.find("ramp = 0.1"), 10, "ramp = 0.02");
  config.replace(config.find("[bms]\n"), 6,
                 fmt::format("[bms]\ntemplates = \"{}\"\n", (dir / "templates.h5").string()));
  testing::write_text(dir / "bms.toml", config);

  for (const std::string axis : {"long", "short"}) {
    const fs::path fem = dir / ("fem_" + axis);
    testing::write_text(dir / (axis + ".toml"), particle_config(mesh, axis, "1 m", 0.06, 3, 2));
    r = run_shapepress("--quiet fem-plate --config " + shell_quoted(dir / (axis + ".toml")) +
                       " --out " + shell_quoted(fem));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json facts = facts_of(fem);
    for (const char* kept : {"particle.inp", "particle.dat", "particle.frd", "particle.msh",
                             "particle.geo", "particle.stl", "force.csv"})
      EXPECT_TRUE(fs::exists(fem / kept)) << kept;
    EXPECT_EQ(facts.at("axis"), axis);
    EXPECT_GT(facts.at("cpu_s").get<double>(), 0.0);

    r = run_shapepress("--quiet calibrate --config " + shell_quoted(dir / "bms.toml") +
                       " --reference " + shell_quoted(fem) +
                       " --fit modulus --from 0.02 --to 0.06 --max-evaluations 5 --out " +
                       shell_quoted(dir / ("cal_" + axis)));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const CsvTable evaluations = read_csv(dir / ("cal_" + axis) / "evaluations.csv");
    const auto rms = evaluations.column("rms_relative");
    ASSERT_GE(rms.size(), 3u);
    const double best = *std::min_element(rms.begin(), rms.end());
    std::printf(
        "%s axis: FEM height %.4g m, %.3g s CPU; BMS template calibrated: RMS relative "
        "error %.4f (start %.4f) over 2-6 %%\n",
        axis.c_str(), facts.at("height_m").get<double>(), facts.at("cpu_s").get<double>(), best,
        rms.front());
    EXPECT_LT(best, rms.front());  // the optimiser improved on the start
    // The calibrated config presses the template along the FEM run's axis, in the mesh's frame.
    const std::string calibrated = testing::read_text(dir / ("cal_" + axis) / "calibrated.toml");
    EXPECT_THAT(calibrated, HasSubstr("axis = \"direction\""));
    const auto& direction = facts.at("axis_direction");
    EXPECT_THAT(
        calibrated,
        HasSubstr(fmt::format("direction = [{}", direction[0].get<double>()).substr(0, 16)));
  }
}

// The shipped calibration of the Avicel BMS bodies' bonds (issue 20) held to its figures: one of
// the bed study's three shapes at the bed's size (fem-avicel-particle.toml), filled with 80
// sub-spheres as the study does, pressed along its long axis by the FEM and by the plate rig
// (plate-avicel-bms.toml). With the shipped Ē the body's force over 2–6 % is within 20 % RMS of
// the FEM's (measured: 12.6 %; the six shape–axis curves of the calibration lie 11–51 % from
// theirs, docs/measurements.md); with Table 4's k̄n, k̄s it is two orders of magnitude softer
// (measured: 1/900 at 6 %), which no Ē near the calibrated one gives.
TEST(FemPlateSolidCli, AvicelBodyWithTheCalibratedBondsMeetsItsFemAndTable4sBondsDoNot) {
  const fs::path dir = fresh_directory("fem_avicel_body");
  const fs::path configs = testing::repository_root() / "pipelines" / "configs";
  auto r = run_shapepress("--quiet generate --targets " + std::string(SHAPEPRESS_TEST_DATA) +
                          "/geometry/avicel_ph200_projected.toml --count 3 --seed 7 --out " +
                          shell_quoted(dir / "shapes"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_shapepress("--quiet fill " + shell_quoted(dir / "shapes") +
                     "/particle_000*.stl --kind bms --count 80 --lattice random --mesh-unit "
                     "\"2.5 m\" --out " +
                     shell_quoted(dir / "templates.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;

  // The shipped FEM config for particle_0001 along its long axis, in 3 increments to 6 % (the
  // forces at 2, 4, 6 % are those of the shipped 6 increments to 0.05 %).
  std::string fem_config = replaced(
      testing::read_text(configs / "fem-avicel-particle.toml"), "\"shapes/particle_0000.stl\"",
      fmt::format("\"{}\"", (dir / "shapes" / "particle_0001.stl").string()));
  fem_config = replaced(fem_config, "increments = 6", "increments = 3");
  testing::write_text(dir / "fem.toml", fem_config);
  r = run_shapepress("--quiet fem-plate --config " + shell_quoted(dir / "fem.toml") + " --out " +
                     shell_quoted(dir / "fem"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json facts = facts_of(dir / "fem");
  ASSERT_EQ(facts.at("axis"), "long");
  const auto& d = facts.at("axis_direction");

  // The rig's Ē is the compaction config's, which the study presses.
  const std::string rig = testing::read_text(configs / "plate-avicel-bms.toml");
  const std::string bed = testing::read_text(configs / "avicel-ph200-bms-calibrated.toml");
  const auto modulus_line = [](const std::string& text) {
    const std::size_t at = text.find("\nmodulus = ");
    return at == std::string::npos ? std::string() : text.substr(at, text.find('\n', at + 1) - at);
  };
  ASSERT_FALSE(modulus_line(rig).empty());
  EXPECT_EQ(modulus_line(rig), modulus_line(bed));

  // Both plates' mean: the anchors hold the FEM particle at its centroid (models.md).
  const auto mean_force = [](const fs::path& csv) {
    const CsvTable t = read_csv(csv);
    analysis::Curve c{t.finite_column("deformation"), t.finite_column("top_force_N"), csv.string()};
    const auto bottom = t.finite_column("bottom_force_N");
    for (std::size_t k = 0; k < c.y.size(); ++k)
      c.y[k] = 0.5 * (c.y[k] + bottom[k]);
    return c;
  };
  const analysis::Curve fem = mean_force(dir / "fem" / "force.csv");
  const auto press = [&](const std::string& name, const std::string& bond) {
    std::string config =
        replaced(rig, "\"templates.h5\"", fmt::format("\"{}\"", (dir / "templates.h5").string()));
    config = replaced(config, "\"particle_0000\"", "\"particle_0001\"");
    config = replaced(config, "axis = \"long\"",
                      fmt::format("axis = \"direction\"\ndirection = [{}, {}, {}]",
                                  d[0].get<double>(), d[1].get<double>(), d[2].get<double>()));
    if (!bond.empty()) {  // Table 4's k̄n, k̄s in place of the modulus and the shear ratio
      config = replaced(config, modulus_line(config), fmt::format("\n{}", bond));
      config = replaced(config, "\nshear_ratio = 1.125", "");
    }
    testing::write_text(dir / (name + ".toml"), config);
    const auto run = run_shapepress("--quiet --threads 1 plate --config " +
                                    shell_quoted(dir / (name + ".toml")) +
                                    " --particle bms --out " + shell_quoted(dir / name));
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return mean_force(dir / name / "force.csv");
  };
  const analysis::Curve calibrated = press("calibrated", "");
  const analysis::CurveDifference error = analysis::compare_curves(calibrated, fem, 0.02, 0.06);
  const analysis::Curve table4 =
      press("table4", "normal_stiffness = \"8e8 N/m^3\"\nshear_stiffness = \"9e8 N/m^3\"\n");
  const double table4_ratio = table4.y.back() / fem.y.back();
  std::printf(
      "Avicel body along its long axis: FEM %.4g N at 6 %% (%.3g s CPU); calibrated "
      "bonds RMS %.4f over 2-6 %%; Table 4's bonds %.3g of the FEM at 6 %%\n",
      fem.y.back(), facts.at("cpu_s").get<double>(), error.rms_relative, table4_ratio);
  EXPECT_LT(error.rms_relative, 0.20);
  EXPECT_LT(table4_ratio, 0.01);
}

}  // namespace
}  // namespace shapepress
