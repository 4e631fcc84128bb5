#include "geometry/mesh_distance.hpp"

#include <memory>
#include <mutex>

#include <fmt/format.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>

#include "common/error.hpp"

namespace shapepress::geometry {

SignedDistance mesh_distance(const TriangleMesh& mesh, int resolution, std::string name) {
  static std::once_flag initialised;
  std::call_once(initialised, [] { openvdb::initialize(); });
  if (resolution < 8 || resolution > 2048)
    throw InputError(fmt::format("resolution {} must be in [8, 2048] voxels", resolution));
  const Aabb box = bounding_box(mesh.vertices);
  const double extent = box.size().maxCoeff();
  if (!(extent > 0.0)) throw InputError(fmt::format("mesh '{}' has zero size", name));
  // OpenVDB works in coordinates where the mesh's longest side is 1: its transforms reject
  // micrometre voxels as singular, and float vertices keep their relative precision this way.
  const double scale = 1.0 / extent;
  const double voxel = 1.0 / resolution;
  std::vector<openvdb::Vec3s> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) {
    const Vec3 q = (p - box.lower) * scale;
    points.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()),
                        static_cast<float>(q.z()));
  }
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    triangles.emplace_back(static_cast<unsigned>(t[0]), static_cast<unsigned>(t[1]),
                           static_cast<unsigned>(t[2]));
  const auto transform = openvdb::math::Transform::createLinearTransform(voxel);
  constexpr float exterior_band = 4.0f;  // voxels outside: enough for gradients at the surface
  const float interior_band = std::numeric_limits<float>::max();  // the whole interior
  openvdb::FloatGrid::Ptr grid = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(
      *transform, points, triangles, std::vector<openvdb::Vec4I>{}, exterior_band, interior_band);
  std::shared_ptr<const openvdb::FloatGrid> shared = grid;
  SignedDistance shape;
  const Vec3 lower = box.lower;
  shape.distance = [shared, lower, scale](const Vec3& p) {
    const Vec3 q = (p - lower) * scale;
    const openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> sampler(
        *shared);
    return static_cast<double>(sampler.wsSample(openvdb::Vec3R(q.x(), q.y(), q.z()))) / scale;
  };
  shape.bounds = box;
  shape.description = fmt::format("mesh '{}' ({} voxels across)", name, resolution);
  return shape;
}

}  // namespace shapepress::geometry
