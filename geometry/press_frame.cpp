#include "geometry/press_frame.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "common/error.hpp"
#include "geometry/mesh_checks.hpp"

namespace shapepress::geometry {
namespace {

// Edges used by one triangle only (border) and by more than two (non-manifold).
struct EdgeUse {
  std::size_t border = 0, non_manifold = 0;
};
EdgeUse edge_use(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> count;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  EdgeUse use;
  for (const auto& [edge, n] : count) {
    if (n == 1) ++use.border;
    if (n > 2) ++use.non_manifold;
  }
  return use;
}

}  // namespace

const char* press_axis_name(PressAxis axis) {
  switch (axis) {
    case PressAxis::short_axis:
      return "short";
    case PressAxis::middle_axis:
      return "middle";
    case PressAxis::long_axis:
      return "long";
    case PressAxis::direction:
      return "direction";
  }
  return "";
}

Mat3 press_frame(const Mat3& axes, PressAxis axis, const std::array<double, 3>& direction) {
  Mat3 frame;
  // Cyclic permutations of a right-handed triad stay right-handed.
  switch (axis) {
    case PressAxis::short_axis:  // the largest moment: the axis the solid is thinnest along
      frame << axes.col(0).transpose(), axes.col(1).transpose(), axes.col(2).transpose();
      return frame;
    case PressAxis::middle_axis:
      frame << axes.col(2).transpose(), axes.col(0).transpose(), axes.col(1).transpose();
      return frame;
    case PressAxis::long_axis:  // the smallest moment
      frame << axes.col(1).transpose(), axes.col(2).transpose(), axes.col(0).transpose();
      return frame;
    case PressAxis::direction:
      break;
  }
  const Vec3 z = Vec3(direction[0], direction[1], direction[2]).normalized();
  // x: the principal axis least aligned with z, made orthogonal to it.
  int least = 0;
  for (int k = 1; k < 3; ++k)
    if (std::fabs(axes.col(k).dot(z)) < std::fabs(axes.col(least).dot(z))) least = k;
  const Vec3 x = (axes.col(least) - axes.col(least).dot(z) * z).normalized();
  frame << x.transpose(), z.cross(x).transpose(), z.transpose();
  return frame;
}

PressedParticle pressed_particle(const std::filesystem::path& path, double unit, PressAxis axis,
                                 const std::array<double, 3>& direction) {
  TriangleMesh mesh = read_mesh(path);
  scale_mesh(mesh, unit);
  const std::string name = path.string();
  const EdgeUse use = edge_use(mesh);
  if (use.border > 0)
    throw InputError(fmt::format(
        "mesh '{}': open, {} edges border one triangle only: the FEM meshes the volume a closed "
        "surface bounds (close it first, e.g. by `shapepress describe`'s repairs)",
        name, use.border));
  if (use.non_manifold > 0)
    throw InputError(
        fmt::format("mesh '{}': not a 2-manifold, {} edges join more than two "
                    "triangles",
                    name, use.non_manifold));
  const MeshCheck check = check_mesh(mesh);
  if (!check.manifold || !check.closed)
    throw InputError(fmt::format("mesh '{}': not a closed 2-manifold surface", name));
  if (check.self_intersecting)
    throw InputError(fmt::format(
        "mesh '{}': self-intersecting (triangles cross each other): it bounds no single solid",
        name));
  if (signed_volume(mesh) < 0.0)
    throw InputError(fmt::format("mesh '{}': inside out (its triangles face inwards)", name));
  if (axis == PressAxis::direction && Vec3(direction[0], direction[1], direction[2]).norm() == 0.0)
    throw InputError(fmt::format("particle.direction: a zero vector gives no pressing axis"));

  MassProperties mass = mesh_mass_properties(mesh);
  PressedParticle particle;
  particle.centroid = mass.centre;
  particle.volume = mass.volume;
  particle.frame = press_frame(mass.principal_axes, axis, direction);
  particle.surface = mesh;
  particle.top = -std::numeric_limits<double>::infinity();
  particle.bottom = std::numeric_limits<double>::infinity();
  for (Vec3& v : particle.surface.vertices) {
    v = particle.frame * (v - mass.centre);
    particle.top = std::max(particle.top, v.z());
    particle.bottom = std::min(particle.bottom, v.z());
  }
  return particle;
}

std::array<double, 2> contact_curvature_radii(const TriangleMesh& surface, bool top, double depth) {
  const double sign = top ? 1.0 : -1.0;
  std::size_t pole = 0;
  for (std::size_t i = 1; i < surface.vertices.size(); ++i)
    if (sign * surface.vertices[i].z() > sign * surface.vertices[pole].z()) pole = i;
  const Vec3 apex = surface.vertices[pole];
  // w = c0 + c1 x + c2 y + a x² + b xy + c y², w the depth below the apex: the curvature tensor
  // is [[2a, b], [b, 2c]], its eigenvalues the principal curvatures 1/R.
  std::vector<Vec3> near;
  for (const Vec3& v : surface.vertices)
    if (sign * (apex.z() - v.z()) <= depth) near.push_back(v - apex);
  if (near.size() < 6) {
    std::vector<Vec3> all;
    for (const Vec3& v : surface.vertices)
      all.push_back(v - apex);
    std::sort(all.begin(), all.end(),
              [&](const Vec3& a, const Vec3& b) { return sign * a.z() > sign * b.z(); });
    all.resize(std::min<std::size_t>(all.size(), 10));
    near = all;
  }
  Eigen::MatrixXd a(near.size(), 6);
  Eigen::VectorXd w(near.size());
  for (std::size_t i = 0; i < near.size(); ++i) {
    const double x = near[i].x(), y = near[i].y();
    a.row(i) << 1.0, x, y, x * x, x * y, y * y;
    w(i) = -sign * near[i].z();
  }
  const Eigen::VectorXd c = a.colPivHouseholderQr().solve(w);
  Eigen::Matrix2d curvature;
  curvature << 2.0 * c(3), c(4), c(4), 2.0 * c(5);
  const Eigen::Vector2d k = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(curvature).eigenvalues();
  const auto radius = [](double kappa) {
    return kappa > 0.0 ? 1.0 / kappa : std::numeric_limits<double>::infinity();
  };
  return {radius(k(0)), radius(k(1))};  // ascending curvature: R1 ≥ R2
}

}  // namespace shapepress::geometry
