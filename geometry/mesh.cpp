#include "geometry/mesh.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "common/atomic_file.hpp"
#include "common/error.hpp"

namespace shapepress::geometry {
namespace {

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("mesh '{}': cannot open the file", path.string()));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

TriangleMesh soup_from_corners(const std::vector<Vec3>& corners) {
  TriangleMesh soup;
  soup.vertices = corners;
  for (std::size_t t = 0; t + 2 < corners.size(); t += 3)
    soup.triangles.push_back({static_cast<std::int32_t>(t), static_cast<std::int32_t>(t + 1),
                              static_cast<std::int32_t>(t + 2)});
  return merge_duplicate_vertices(soup);
}

TriangleMesh read_binary_stl(const std::string& bytes) {
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  std::vector<Vec3> corners;
  corners.reserve(3 * std::size_t{count});
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* record = bytes.data() + 84 + 50 * std::size_t{t};
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      std::memcpy(xyz, record + 12 + 12 * k, 12);  // after the 12-byte normal
      corners.emplace_back(xyz[0], xyz[1], xyz[2]);
    }
  }
  return soup_from_corners(corners);
}

TriangleMesh read_ascii_stl(const std::string& text, const std::filesystem::path& path) {
  std::istringstream in(text);
  std::vector<Vec3> corners;
  std::string word;
  while (in >> word) {
    if (word != "vertex") continue;
    Vec3 p;
    if (!(in >> p.x() >> p.y() >> p.z()))
      throw InputError(fmt::format("mesh '{}': an ASCII STL 'vertex' line without three numbers",
                                   path.string()));
    corners.push_back(p);
  }
  if (corners.size() % 3 != 0)
    throw InputError(fmt::format("mesh '{}': {} vertices is not a whole number of triangles",
                                 path.string(), corners.size()));
  return soup_from_corners(corners);
}

TriangleMesh read_stl(const std::filesystem::path& path) {
  const std::string bytes = read_bytes(path);
  if (bytes.size() >= 84) {
    std::uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    if (bytes.size() == 84 + 50 * std::size_t{count}) return read_binary_stl(bytes);
  }
  if (bytes.rfind("solid", 0) == 0) return read_ascii_stl(bytes, path);
  throw InputError(fmt::format(
      "mesh '{}': neither a binary STL (size 84 + 50 x triangles) nor an ASCII STL ('solid ...')",
      path.string()));
}

// OFF and ASCII PLY share the shape "vertex count, face count, vertices, faces".
TriangleMesh read_indexed(std::istream& in, std::size_t vertex_count, std::size_t face_count,
                          const std::filesystem::path& path) {
  TriangleMesh mesh;
  std::string line;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    if (!std::getline(in, line)) break;
    std::istringstream row(line);
    Vec3 p;
    if (!(row >> p.x() >> p.y() >> p.z())) {
      --v;
      if (in.eof()) break;
      continue;  // blank or comment line
    }
    mesh.vertices.push_back(p);
  }
  std::size_t faces = 0;
  for (; faces < face_count && std::getline(in, line);) {
    std::istringstream row(line);
    long long n = 0;
    if (!(row >> n)) continue;
    // A face has at least three corners and no more than there are vertices (a corrupt count
    // must not size an allocation).
    if (n < 3 || static_cast<std::size_t>(n) > std::max<std::size_t>(mesh.vertices.size(), 3))
      throw InputError(fmt::format("mesh '{}': face {} has {} corners", path.string(), faces, n));
    std::vector<std::int32_t> ids(static_cast<std::size_t>(n));
    for (auto& id : ids)
      if (!(row >> id))
        throw InputError(fmt::format("mesh '{}': face {} lists fewer than its {} corners",
                                     path.string(), faces, n));
    for (auto id : ids)
      if (id < 0 || static_cast<std::size_t>(id) >= mesh.vertices.size())
        throw InputError(fmt::format("mesh '{}': face {} refers to vertex {} of {}", path.string(),
                                     faces, id, mesh.vertices.size()));
    for (std::size_t k = 1; k + 1 < ids.size(); ++k)  // fan-triangulate polygons
      mesh.triangles.push_back({ids[0], ids[k], ids[k + 1]});
    ++faces;
  }
  if (faces != face_count)
    throw InputError(fmt::format("mesh '{}': {} faces announced, {} found (a truncated file?)",
                                 path.string(), face_count, faces));
  if (mesh.vertices.size() != vertex_count)
    throw InputError(fmt::format("mesh '{}': {} vertices announced, {} found", path.string(),
                                 vertex_count, mesh.vertices.size()));
  return mesh;
}

TriangleMesh read_off(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("mesh '{}': cannot open the file", path.string()));
  std::string magic;
  std::size_t nv = 0, nf = 0, ne = 0;
  if (!(in >> magic) || magic != "OFF" || !(in >> nv >> nf >> ne))
    throw InputError(fmt::format("mesh '{}': expected an 'OFF' header with counts", path.string()));
  std::string rest;
  std::getline(in, rest);
  return read_indexed(in, nv, nf, path);
}

TriangleMesh read_ply(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("mesh '{}': cannot open the file", path.string()));
  std::string line;
  std::size_t nv = 0, nf = 0;
  bool ascii = false;
  while (std::getline(in, line) && line.rfind("end_header", 0) != 0) {
    std::istringstream row(line);
    std::string a, b;
    row >> a >> b;
    if (a == "format") ascii = (b == "ascii");
    if (a == "element" && b == "vertex") row >> nv;
    if (a == "element" && b == "face") row >> nf;
  }
  if (!ascii)
    throw InputError(fmt::format("mesh '{}': only ASCII PLY is read (convert binary PLY to STL)",
                                 path.string()));
  return read_indexed(in, nv, nf, path);
}

}  // namespace

TriangleMesh merge_duplicate_vertices(const TriangleMesh& soup) {
  auto key = [](const Vec3& p) { return std::array<double, 3>{p.x(), p.y(), p.z()}; };
  std::map<std::array<double, 3>, std::int32_t> index;
  TriangleMesh mesh;
  std::vector<std::int32_t> remap(soup.vertices.size(), -1);
  for (const auto& t : soup.triangles) {
    std::array<std::int32_t, 3> out{};
    for (int k = 0; k < 3; ++k) {
      const auto old_id = static_cast<std::size_t>(t[static_cast<std::size_t>(k)]);
      if (remap[old_id] < 0) {
        auto [it, inserted] = index.try_emplace(key(soup.vertices[old_id]),
                                                static_cast<std::int32_t>(mesh.vertices.size()));
        if (inserted) mesh.vertices.push_back(soup.vertices[old_id]);
        remap[old_id] = it->second;
      }
      out[static_cast<std::size_t>(k)] = remap[old_id];
    }
    mesh.triangles.push_back(out);
  }
  return mesh;
}

TriangleMesh read_mesh(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path))
    throw InputError(fmt::format("mesh '{}': no such file", path.string()));
  const std::string ext = lower_extension(path);
  TriangleMesh mesh;
  if (ext == ".stl")
    mesh = read_stl(path);
  else if (ext == ".off")
    mesh = read_off(path);
  else if (ext == ".ply")
    mesh = read_ply(path);
  else
    throw InputError(fmt::format("mesh '{}': unknown extension '{}', expected .stl, .off or .ply",
                                 path.string(), ext));
  if (mesh.triangles.empty())
    throw InputError(fmt::format("mesh '{}': contains no triangles", path.string()));
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (!mesh.vertices[v].allFinite())
      throw InputError(fmt::format("mesh '{}': vertex {} is not finite ({} {} {})", path.string(),
                                   v, mesh.vertices[v].x(), mesh.vertices[v].y(),
                                   mesh.vertices[v].z()));
  return mesh;
}

void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  AtomicOutputFile file(path);
  std::ostream& out = file.stream();
  if (ext == ".stl") {
    char header[80] = {};
    std::snprintf(header, sizeof header, "shapepress binary STL");
    out.write(header, 80);
    const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
    out.write(reinterpret_cast<const char*>(&count), 4);
    for (const auto& t : mesh.triangles) {
      const Vec3& a = mesh.vertices[static_cast<std::size_t>(t[0])];
      const Vec3& b = mesh.vertices[static_cast<std::size_t>(t[1])];
      const Vec3& c = mesh.vertices[static_cast<std::size_t>(t[2])];
      const Vec3 n = (b - a).cross(c - a).normalized();
      float record[12];
      const Vec3* points[4] = {&n, &a, &b, &c};
      for (int p = 0; p < 4; ++p)
        for (int k = 0; k < 3; ++k)
          record[3 * p + k] = static_cast<float>((*points[p])[k]);
      out.write(reinterpret_cast<const char*>(record), sizeof record);
      const std::uint16_t attribute = 0;
      out.write(reinterpret_cast<const char*>(&attribute), 2);
    }
  } else if (ext == ".off" || ext == ".ply") {
    if (ext == ".off") {
      out << "OFF\n" << mesh.vertices.size() << ' ' << mesh.triangles.size() << " 0\n";
    } else {
      out << "ply\nformat ascii 1.0\nelement vertex " << mesh.vertices.size()
          << "\nproperty double x\nproperty double y\nproperty double z\nelement face "
          << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
    }
    for (const Vec3& p : mesh.vertices)
      out << fmt::format("{:.17g} {:.17g} {:.17g}\n", p.x(), p.y(), p.z());
    for (const auto& t : mesh.triangles)
      out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  } else {
    throw InputError(
        fmt::format("output mesh '{}': unknown extension '{}', expected .stl, .off "
                    "or .ply",
                    path.string(), ext));
  }
  file.commit();
}

double signed_volume(const TriangleMesh& mesh) {
  return mesh_mass_properties(mesh).volume;
}

double surface_area(const TriangleMesh& mesh) {
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    area += 0.5 * (mesh.vertices[static_cast<std::size_t>(t[1])] - a)
                      .cross(mesh.vertices[static_cast<std::size_t>(t[2])] - a)
                      .norm();
  }
  return area;
}

Aabb bounding_box(const std::vector<Vec3>& points) {
  Aabb box;
  if (points.empty()) return box;
  box.lower = box.upper = points.front();
  for (const Vec3& p : points) {
    box.lower = box.lower.cwiseMin(p);
    box.upper = box.upper.cwiseMax(p);
  }
  return box;
}

MassProperties mesh_mass_properties(const TriangleMesh& mesh) {
  // Tetrahedra (o, a, b, c) from a reference point o near the mesh, to keep cancellation small
  // for micrometre meshes far from the origin. Second moments of a tetrahedron with one corner
  // at o: det/120 (Σ v vᵀ + s sᵀ), s = a + b + c.
  const Aabb box = bounding_box(mesh.vertices);
  const Vec3 o = 0.5 * (box.lower + box.upper);
  double volume = 0.0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[static_cast<std::size_t>(t[0])] - o;
    const Vec3 b = mesh.vertices[static_cast<std::size_t>(t[1])] - o;
    const Vec3 c = mesh.vertices[static_cast<std::size_t>(t[2])] - o;
    const double det = a.dot(b.cross(c));
    const Vec3 s = a + b + c;
    volume += det / 6.0;
    first += det / 24.0 * s;
    second += det / 120.0 *
              (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  MassProperties props;
  props.volume = volume;
  if (volume == 0.0) return props;
  const Vec3 centre_from_o = first / volume;
  props.centre = o + centre_from_o;
  const Mat3 about_centre = second - volume * centre_from_o * centre_from_o.transpose();
  props.inertia = about_centre.trace() * Mat3::Identity() - about_centre;
  diagonalise(props);
  return props;
}

void diagonalise(MassProperties& properties) {
  Eigen::SelfAdjointEigenSolver<Mat3> solver(properties.inertia);
  properties.principal_moments = solver.eigenvalues();
  properties.principal_axes = solver.eigenvectors();
  if (properties.principal_axes.determinant() < 0.0)
    properties.principal_axes.col(2) = -properties.principal_axes.col(2);
}

void scale_mesh(TriangleMesh& mesh, double scale) {
  for (Vec3& p : mesh.vertices)
    p *= scale;
}

void translate_mesh(TriangleMesh& mesh, const Vec3& shift) {
  for (Vec3& p : mesh.vertices)
    p += shift;
}

}  // namespace shapepress::geometry
