#include "fem/tet_mesh.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "common/atomic_file.hpp"
#include "common/child_process.hpp"
#include "common/error.hpp"

namespace shapepress::fem {
namespace {

using geometry::Vec3;

// Corner pairs of the C3D10 midside nodes 5–10 (0-based corners).
constexpr std::array<std::array<int, 2>, 6> c3d10_edges = {
    {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}};
// C3D4/C3D10 faces by corner (CalculiX manual, "C3D4"): 1: 1-2-3, 2: 1-4-2, 3: 2-4-3, 4: 3-4-1.
constexpr std::array<std::array<int, 3>, 4> c3d10_faces = {
    {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}}};

// Gmsh's size field: `at_plates` within `band` of z = top or z = bottom, growing linearly to
// `elsewhere` over the next band (Threshold on a MathEval distance to the nearer plate).
std::string geo_script(const std::filesystem::path& stl, const TetSizes& sizes_mm, double top_mm,
                       double bottom_mm, const std::vector<Vec3>& embedded_mm) {
  std::string geo = fmt::format(
      "// shapepress fem-plate: the particle's volume as 10-node tetrahedra (the deck's units)\n"
      "Merge \"{}\";\n"
      "ClassifySurfaces{{40 * Pi / 180, 1, 1, Pi}};\n"
      "CreateGeometry;\n"
      "Surface Loop(1) = Surface{{:}};\n"
      "Volume(1) = {{1}};\n",
      stl.string());
  for (std::size_t i = 0; i < embedded_mm.size(); ++i)
    geo += fmt::format(
        "Point({0}) = {{{1:.12g}, {2:.12g}, {3:.12g}, {4:.12g}}};\n"
        "Point{{{0}}} In Volume{{1}};\n",
        100000 + i, embedded_mm[i].x(), embedded_mm[i].y(), embedded_mm[i].z(), sizes_mm.elsewhere);
  geo += fmt::format(
      "Field[1] = MathEval;\n"
      "Field[1].F = \"Min({0:.12g} - z, z - ({1:.12g}))\";\n"
      "Field[2] = Threshold;\n"
      "Field[2].InField = 1;\n"
      "Field[2].SizeMin = {2:.12g};\n"
      "Field[2].SizeMax = {3:.12g};\n"
      "Field[2].DistMin = {4:.12g};\n"
      "Field[2].DistMax = {5:.12g};\n"
      "Background Field = 2;\n"
      "Mesh.MeshSizeExtendFromBoundary = 0;\n"
      "Mesh.MeshSizeFromPoints = 0;\n"
      "Mesh.MeshSizeFromCurvature = 0;\n"
      "Mesh.ElementOrder = 2;\n"
      "Mesh.HighOrderOptimize = 0;\n"
      "Mesh.Optimize = 1;\n",
      top_mm, bottom_mm, sizes_mm.at_plates, sizes_mm.elsewhere, sizes_mm.band,
      2.0 * sizes_mm.band);
  return geo;
}

ChildEnd run_gmsh(const std::string& program, const std::filesystem::path& geo,
                  const std::filesystem::path& msh, const std::filesystem::path& log) {
  return run_child(
      {{program, "-3", geo.string(), "-format", "msh22", "-o", msh.string(), "-nt", "1"},
       "the mesher",
       "install Debian's gmsh: scripts/install-deps.sh, or name the program with "
       "--gmsh",
       {},
       {},
       log});
}

// Gmsh puts a boundary edge's midside node on its rebuilt surface; where an edge runs along the
// seam of two patches of that surface the node can land far off the edge (seen: 0.4 of its
// length on a sphere, whose true sag is h²/8R, a few hundredths), and the element's Jacobian
// turns negative. Such a node goes back to the edge's midpoint: a straight edge there.
void straighten_stray_midside_nodes(TetMesh& mesh) {
  constexpr double stray = 0.25;  // × the edge's length
  for (const std::array<int, 10>& e : mesh.elements)
    for (std::size_t k = 0; k < c3d10_edges.size(); ++k) {
      const Vec3& a = mesh.nodes[e[c3d10_edges[k][0]]];
      const Vec3& b = mesh.nodes[e[c3d10_edges[k][1]]];
      Vec3& mid = mesh.nodes[e[4 + k]];
      if ((mid - 0.5 * (a + b)).norm() > stray * (b - a).norm()) mid = 0.5 * (a + b);
    }
}

// det J of a C3D10 element at natural coordinates (r, s, t) (L1 = 1 − r − s − t, L2 = r, L3 = s,
// L4 = t; quadratic shape functions L(2L − 1) at the corners, 4 La Lb at the midside nodes).
double jacobian_determinant(const TetMesh& mesh, const std::array<int, 10>& e, double r, double s,
                            double t) {
  const std::array<double, 4> l = {1.0 - r - s - t, r, s, t};
  const std::array<Vec3, 4> dl = {Vec3(-1, -1, -1), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();  // rows: d/dr, d/ds, d/dt of x
  for (int i = 0; i < 4; ++i)
    jacobian += (4.0 * l[i] - 1.0) * dl[i] * mesh.nodes[e[i]].transpose();
  for (std::size_t k = 0; k < c3d10_edges.size(); ++k) {
    const int a = c3d10_edges[k][0], b = c3d10_edges[k][1];
    jacobian += 4.0 * (l[a] * dl[b] + l[b] * dl[a]) * mesh.nodes[e[4 + k]].transpose();
  }
  return jacobian.determinant();
}

// A curved element whose Jacobian is not positive at a corner or an integration point (CalculiX
// stops: "nonpositive jacobian") gets straight edges, whose Jacobian is the corner tetrahedron's
// and positive. Its neighbours share those nodes, so the check runs again until none is left.
void straighten_inverted_elements(TetMesh& mesh) {
  constexpr double a = 0.1381966011250105, b = 0.5854101966249685;  // 4-point Gauss rule
  const std::array<Vec3, 8> points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
                                      Vec3(a, a, a), Vec3(b, a, a), Vec3(a, b, a), Vec3(a, a, b)};
  for (int pass = 0; pass < 10; ++pass) {
    bool changed = false;
    for (const std::array<int, 10>& e : mesh.elements) {
      bool inverted = false;
      for (const Vec3& p : points)
        inverted = inverted || jacobian_determinant(mesh, e, p.x(), p.y(), p.z()) <= 0.0;
      if (!inverted) continue;
      for (std::size_t k = 0; k < c3d10_edges.size(); ++k)
        mesh.nodes[e[4 + k]] =
            0.5 * (mesh.nodes[e[c3d10_edges[k][0]]] + mesh.nodes[e[c3d10_edges[k][1]]]);
      changed = true;
    }
    if (!changed) return;
  }
}

}  // namespace

std::array<int, 3> face_corners(const std::array<int, 10>& element, int face) {
  const auto& f = c3d10_faces[static_cast<std::size_t>(face - 1)];
  return {element[f[0]], element[f[1]], element[f[2]]};
}

TetMesh read_gmsh_tetrahedra(const std::filesystem::path& msh, double scale) {
  std::ifstream in(msh);
  if (!in) throw ComputationError(fmt::format("{}: Gmsh wrote no mesh", msh.string()));
  TetMesh mesh;
  std::map<long, int> index;  // Gmsh node tag -> 0-based
  std::string line;
  while (std::getline(in, line)) {
    if (line.starts_with("$Nodes")) {
      long count = 0;
      in >> count;
      for (long i = 0; i < count; ++i) {
        long tag = 0;
        Vec3 p;
        in >> tag >> p.x() >> p.y() >> p.z();
        index[tag] = static_cast<int>(mesh.nodes.size());
        mesh.nodes.push_back(scale * p);
      }
    } else if (line.starts_with("$Elements")) {
      long count = 0;
      in >> count;
      std::getline(in, line);
      for (long i = 0; i < count && std::getline(in, line); ++i) {
        std::istringstream fields(line);
        long tag = 0, type = 0, tags = 0;
        fields >> tag >> type >> tags;
        if (type != 11) continue;  // 10-node tetrahedron
        for (long t = 0; t < tags; ++t)
          fields >> tag;
        std::array<int, 10> gmsh{};
        for (int& n : gmsh) {
          long node = 0;
          fields >> node;
          n = index.at(node);
        }
        mesh.elements.push_back(gmsh);
      }
    }
  }
  if (!in.eof() && in.fail())
    throw ComputationError(fmt::format("{}: malformed Gmsh mesh", msh.string()));
  for (std::array<int, 10>& e : mesh.elements) {
    // Gmsh's 10-node tetrahedron has its last two midside nodes on edges 3–4 and 2–4 (gmsh.info,
    // "Node ordering"), C3D10 on 2–4 and 3–4.
    std::swap(e[8], e[9]);
    const Vec3& a = mesh.nodes[e[0]];
    if ((mesh.nodes[e[1]] - a).cross(mesh.nodes[e[2]] - a).dot(mesh.nodes[e[3]] - a) < 0.0) {
      // Corners 2 and 3 swapped: edges 1–2 and 3–1 trade places, as do 2–4 and 3–4.
      std::swap(e[1], e[2]);
      std::swap(e[4], e[6]);
      std::swap(e[8], e[9]);
    }
  }
  straighten_stray_midside_nodes(mesh);
  straighten_inverted_elements(mesh);
  return mesh;
}

std::vector<std::pair<int, int>> boundary_faces(const TetMesh& mesh) {
  std::map<std::array<int, 3>, std::pair<int, int>> once;
  std::map<std::array<int, 3>, int> count;
  for (std::size_t e = 0; e < mesh.elements.size(); ++e)
    for (int face = 1; face <= 4; ++face) {
      std::array<int, 3> key = face_corners(mesh.elements[e], face);
      std::sort(key.begin(), key.end());
      if (++count[key] == 1) once[key] = {static_cast<int>(e), face};
    }
  std::vector<std::pair<int, int>> faces;
  for (const auto& [key, n] : count)
    if (n == 1) faces.push_back(once[key]);
  std::sort(faces.begin(), faces.end());
  return faces;
}

TetMesh tetrahedral_mesh(const geometry::TriangleMesh& surface, const TetSizes& sizes,
                         const std::vector<Vec3>& embedded, const std::filesystem::path& folder,
                         const std::string& job, const std::string& program, double units_per_m) {
  // Gmsh works in the deck's unit: its tolerances are relative but its defaults assume
  // engineering magnitudes.
  const double mm = units_per_m;
  geometry::TriangleMesh in_mm = surface;
  geometry::scale_mesh(in_mm, mm);
  double top = -1e300, bottom = 1e300;
  for (const Vec3& v : in_mm.vertices)
    top = std::max(top, v.z()), bottom = std::min(bottom, v.z());
  const std::filesystem::path stl = std::filesystem::absolute(folder / (job + ".stl"));
  const std::filesystem::path geo = std::filesystem::absolute(folder / (job + ".geo"));
  const std::filesystem::path msh = std::filesystem::absolute(folder / (job + ".msh"));
  const std::filesystem::path log = std::filesystem::absolute(folder / (job + "-gmsh.log"));
  geometry::write_mesh(in_mm, stl);
  std::vector<Vec3> embedded_mm;
  for (const Vec3& p : embedded)
    embedded_mm.push_back(mm * p);
  const TetSizes sizes_mm{mm * sizes.at_plates, mm * sizes.elsewhere, mm * sizes.band};
  write_file_atomically(geo, geo_script(stl, sizes_mm, top, bottom, embedded_mm));
  std::filesystem::remove(msh);
  const ChildEnd end = run_gmsh(program, geo, msh, log);
  if (end.exit_code != 0 || !std::filesystem::exists(msh))
    throw ComputationError(fmt::format("Gmsh could not mesh the particle's volume ({}): see {}",
                                       end.how(), log.string()));
  TetMesh mesh = read_gmsh_tetrahedra(msh, 1.0 / mm);
  if (mesh.elements.empty())
    throw ComputationError(
        fmt::format("Gmsh made no 10-node tetrahedra of the particle: see {}", log.string()));
  for (const Vec3& p : embedded) {
    int best = 0;
    for (int i = 1; i < static_cast<int>(mesh.nodes.size()); ++i)
      if ((mesh.nodes[i] - p).squaredNorm() < (mesh.nodes[best] - p).squaredNorm()) best = i;
    mesh.anchors.push_back(best);
  }
  return mesh;
}

}  // namespace shapepress::fem
