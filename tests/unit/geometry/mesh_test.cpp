#include "geometry/mesh.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>

#include "common/error.hpp"
#include "geometry/icosphere.hpp"
#include "geometry/mesh_checks.hpp"
#include "tests/support/files.hpp"

namespace shapepress::geometry {
namespace {

std::filesystem::path temp(const std::string& name) {
  static const std::filesystem::path folder = shapepress::testing::fresh_directory("geometry_mesh");
  return folder / name;
}

TriangleMesh unit_cube() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  m.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                 {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  return m;
}

TEST(Mesh, CubeMassPropertiesAreExact) {
  const MassProperties p = mesh_mass_properties(unit_cube());
  EXPECT_NEAR(p.volume, 1.0, 1e-14);
  EXPECT_NEAR((p.centre - Vec3(0.5, 0.5, 0.5)).norm(), 0.0, 1e-14);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(p.principal_moments[k], 1.0 / 6.0, 1e-14);  // m a²/6
  EXPECT_NEAR(surface_area(unit_cube()), 6.0, 1e-14);
}

TEST(Mesh, IcosphereConvergesToTheSphere) {
  const TriangleMesh m = icosphere(4);
  EXPECT_EQ(m.vertices.size(), 2562u);
  EXPECT_EQ(m.triangles.size(), 5120u);
  // Inscribed polyhedron: volume slightly below 4π/3 (0.3 % at level 4).
  EXPECT_NEAR(signed_volume(m) / (4.0 / 3.0 * std::numbers::pi), 1.0, 5e-3);
  EXPECT_LT(signed_volume(m), 4.0 / 3.0 * std::numbers::pi);
}

TEST(Mesh, BinaryStlOffPlyRoundTrip) {
  const TriangleMesh m = icosphere(2);
  for (const char* ext : {".stl", ".off", ".ply"}) {
    const auto path = temp(std::string("roundtrip") + ext);
    write_mesh(m, path);
    const TriangleMesh back = read_mesh(path);
    EXPECT_EQ(back.triangles.size(), m.triangles.size()) << ext;
    EXPECT_EQ(back.vertices.size(), m.vertices.size()) << ext;  // STL corners merged again
    // STL stores floats: volume to float precision.
    EXPECT_NEAR(signed_volume(back), signed_volume(m), 1e-6) << ext;
    std::filesystem::remove(path);
  }
}

TEST(Mesh, AsciiStlIsRead) {
  const auto path = temp("ascii.stl");
  {
    std::ofstream out(path);
    const TriangleMesh cube = unit_cube();
    out << "solid cube\n";
    for (const auto& t : cube.triangles) {
      out << " facet normal 0 0 0\n  outer loop\n";
      for (auto id : t) {
        const Vec3& p = cube.vertices[static_cast<std::size_t>(id)];
        out << "   vertex " << p.x() << ' ' << p.y() << ' ' << p.z() << "\n";
      }
      out << "  endloop\n endfacet\n";
    }
    out << "endsolid cube\n";
  }
  const TriangleMesh m = read_mesh(path);
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_NEAR(signed_volume(m), 1.0, 1e-12);
  std::filesystem::remove(path);
}

TEST(Mesh, UnreadableFilesNameTheFile) {
  const auto path = temp("garbage.stl");
  { std::ofstream(path) << "not a mesh"; }
  try {
    read_mesh(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("garbage.stl"), std::string::npos);
  }
  EXPECT_THROW(read_mesh(temp("missing.stl")), InputError);
  EXPECT_THROW(read_mesh(temp("x.obj")), InputError);
  std::filesystem::remove(path);
}

TEST(MeshChecks, ValidMeshPassesUnchanged) {
  std::vector<std::string> repairs;
  const TriangleMesh m = prepare_mesh(icosphere(3), "ball", &repairs);
  EXPECT_TRUE(repairs.empty());
  EXPECT_TRUE(check_mesh(m).valid());
  EXPECT_NEAR(signed_volume(m), signed_volume(icosphere(3)), 1e-12);
}

TEST(MeshChecks, OpenMeshIsClosedAndSaysSo) {
  TriangleMesh m = icosphere(2);
  m.triangles.pop_back();  // a one-triangle hole
  EXPECT_FALSE(check_mesh(m).closed);
  std::vector<std::string> repairs;
  const TriangleMesh fixed = prepare_mesh(m, "holed", &repairs);
  ASSERT_FALSE(repairs.empty());
  EXPECT_NE(repairs.back().find("hole"), std::string::npos);
  EXPECT_TRUE(check_mesh(fixed).valid());
}

TEST(MeshChecks, BadOrientationIsMadeConsistent) {
  TriangleMesh m = icosphere(2);
  std::swap(m.triangles[3][0], m.triangles[3][1]);  // one flipped triangle
  std::vector<std::string> repairs;
  const TriangleMesh fixed = prepare_mesh(m, "flipped", &repairs);
  EXPECT_FALSE(repairs.empty());
  EXPECT_GT(signed_volume(fixed), 0.0);
}

void expect_refused(const TriangleMesh& m, const std::string& cause) {
  try {
    prepare_mesh(m, "bad.stl", nullptr);
    FAIL() << "accepted a mesh that is " << cause;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("bad.stl"), std::string::npos) << message;
    EXPECT_NE(message.find(cause), std::string::npos) << message;
  }
}

TEST(MeshChecks, InsideOutTinyDegenerateAndSelfIntersectingAreRefused) {
  TriangleMesh inside_out = icosphere(2);
  for (auto& t : inside_out.triangles)
    std::swap(t[0], t[1]);
  expect_refused(inside_out, "inside-out");
  TriangleMesh tiny = icosphere(2);
  scale_mesh(tiny, 1e-10);
  expect_refused(tiny, "tiny");
  TriangleMesh flat = icosphere(2);
  for (Vec3& v : flat.vertices)
    v.z() = 0.0;
  expect_refused(flat, "");  // folded onto a plane: refused (degenerate or self-intersecting)
  TriangleMesh two = icosphere(2);
  TriangleMesh other = icosphere(2);
  translate_mesh(other, Vec3(0.5, 0, 0));
  const auto offset = static_cast<std::int32_t>(two.vertices.size());
  two.vertices.insert(two.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (auto t : other.triangles)
    two.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  expect_refused(two, "self-intersecting");
  TriangleMesh few;
  few.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  few.triangles = {{0, 1, 2}};
  expect_refused(few, "degenerate");
}

}  // namespace
}  // namespace shapepress::geometry
