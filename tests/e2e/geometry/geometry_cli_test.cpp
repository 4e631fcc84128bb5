// The geometry stages as a user runs them: exit codes, messages, files, determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "geometry/icosphere.hpp"
#include "geometry/templates_file.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress::geometry {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::run_shapepress;
using shapepress::testing::write_text;
namespace fs = std::filesystem;

const std::string data = std::string(SHAPEPRESS_TEST_DATA) + "/geometry/";

// Rows of a CSV with text columns (read_csv takes numbers only): the cells of `column`.
std::vector<std::string> csv_column(const fs::path& path, const std::string& column) {
  std::vector<std::string> cells;
  for (const auto& row : shapepress::testing::text_rows(path))
    cells.push_back(row.at(column));
  return cells;
}

TEST(GeometryCli, GenerateDescribeFillChain) {
  const fs::path dir = fresh_directory("geometry_chain");
  auto r = run_shapepress("--quiet generate --targets " + data + "paper_box_targets.toml " +
                          "--count 3 --seed 4 --out " + (dir / "shapes").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto elongation = csv_column(dir / "shapes" / "shapes.csv", "elongation");
  ASSERT_EQ(elongation.size(), 3u);
  // Each particle's target is drawn with a 5 % spread around 0.84 and then met to 2e-3.
  for (const std::string& e : elongation)
    EXPECT_NEAR(std::stod(e), 0.84, 0.2);
  const std::string mesh = (dir / "shapes" / "particle_0000.stl").string();
  r = run_shapepress("describe " + mesh + " --out " + (dir / "d.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(csv_column(dir / "d.csv", "asr").size(), 1u);
  r = run_shapepress("--quiet fill " + mesh + " --count 200 --out " + (dir / "t.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto templates = read_templates(dir / "t.h5");
  ASSERT_EQ(templates.size(), 1u);
  EXPECT_EQ(templates[0].body.centres.size(), 200u);
  EXPECT_TRUE(templates[0].quality.connected);
  EXPECT_FALSE(templates[0].body.bonds.empty());
  // Body frame: the template's centre of mass is the origin.
  Vec3 mean = Vec3::Zero();
  for (const Vec3& c : templates[0].body.centres)
    mean += c / 200.0;
  EXPECT_LT(mean.norm(), 1e-9 * templates[0].body.radii[0]);  // rounding of a mean only
  // Each stage's run.json: in the folder (generate), beside the output file (describe, fill).
  const auto json = [](const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
  };
  const nlohmann::json generated = json(dir / "shapes" / "run.json");
  EXPECT_EQ(generated["stage"], "generate");
  EXPECT_EQ(generated["facts"]["particles"], 3);
  EXPECT_EQ(generated["facts"]["seed"], 4);
  EXPECT_EQ(generated["inputs"][0]["role"], "targets");
  EXPECT_EQ(json(dir / "d.csv.run.json")["facts"]["meshes"], 1);
  const nlohmann::json filled = json(dir / "t.h5.run.json");
  EXPECT_EQ(filled["stage"], "fill");
  EXPECT_EQ(filled["facts"]["particle_kind"], "bms");
  EXPECT_EQ(filled["facts"]["sub_spheres"], nlohmann::json::array({200}));
  EXPECT_EQ(filled["inputs"][0]["path"], mesh);
}

TEST(GeometryCli, SameSeedSameTemplatesAndMeshes) {
  const fs::path dir = fresh_directory("geometry_determinism");
  for (const char* run : {"a", "b"}) {
    auto r = run_shapepress("--quiet generate --targets " + data + "paper_box_targets.toml " +
                            "--count 2 --seed 9 --out " + (dir / run).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_shapepress("--quiet fill --kind cms --count 40 " +
                       (dir / run / "particle_0001.stl").string() + " --out " +
                       (dir / run / "t.h5").string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  auto bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(bytes(dir / "a" / "particle_0001.stl"), bytes(dir / "b" / "particle_0001.stl"));
  // HDF5 files carry a creation time in their provenance: compare the datasets instead.
  const auto a = read_templates(dir / "a" / "t.h5");
  const auto b = read_templates(dir / "b" / "t.h5");
  ASSERT_EQ(a.size(), 1u);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(a[0].body.centres, b[0].body.centres);
  EXPECT_EQ(a[0].body.radii, b[0].body.radii);
  EXPECT_EQ(a[0].mass.volume, b[0].mass.volume);
}

TEST(GeometryCli, AnalyticShapesForTheBmsStudies) {
  const fs::path dir = fresh_directory("geometry_analytic");
  const auto r = run_shapepress(
      "--quiet fill --sphere 1cm --ellipsoid 1cm,8.4mm,8mm --count 545 "
      "--out " +
      (dir / "t.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto templates = read_templates(dir / "t.h5");
  ASSERT_EQ(templates.size(), 2u);
  for (const auto& t : templates)
    EXPECT_EQ(t.body.centres.size(), 545u);  // paper §3.1 count
}

TEST(GeometryCli, BadInputsExitTwoAndNameTheCause) {
  const fs::path dir = fresh_directory("geometry_bad");
  // Inside-out mesh.
  TriangleMesh m = icosphere(2);
  for (auto& t : m.triangles)
    std::swap(t[0], t[1]);
  scale_mesh(m, 1e-4);
  write_mesh(m, dir / "inverted.stl");
  auto r = run_shapepress("fill " + (dir / "inverted.stl").string() + " --out " +
                          (dir / "t.h5").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("inverted.stl"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("inside-out"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "t.h5"));
  // Missing file, unknown target key, bad option value.
  r = run_shapepress("describe " + (dir / "nothing.stl").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("nothing.stl"), std::string::npos) << r.output;
  std::ofstream(dir / "targets.toml") << "[fourier]\nD3 = 0.03\nD8 = 0.01\n[asr]\nmean = 0.8\n"
                                         "[size]\nx10_m = 5e-5\nx50_m = 1e-4\nx90 = 2e-4\n";
  r = run_shapepress("generate --targets " + (dir / "targets.toml").string() + " --out " +
                     (dir / "s").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("x90"), std::string::npos) << r.output;
  r = run_shapepress("fill --sphere 1mm --bond-multiplier 2 --out " + (dir / "t.h5").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("m_b"), std::string::npos) << r.output;
  // A mesh in millimetres read as metres is fine; one in metres read as nanometres is tiny.
  write_mesh(icosphere(2), dir / "ball.stl");
  r = run_shapepress("describe " + (dir / "ball.stl").string() + " --mesh-unit 1nm");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("tiny"), std::string::npos) << r.output;
}

TEST(GeometryCli, OpenMeshIsRepairedAndReported) {
  const fs::path dir = fresh_directory("geometry_open");
  TriangleMesh m = icosphere(3);
  m.triangles.erase(m.triangles.begin() + 3);  // a triangular hole
  scale_mesh(m, 1e-4);
  write_mesh(m, dir / "open.stl");
  const auto r = run_shapepress("describe " + (dir / "open.stl").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("repaired"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace shapepress::geometry
