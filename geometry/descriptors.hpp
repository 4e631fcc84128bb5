#pragma once
// 3D shape descriptors of a closed mesh (Giannis et al. 2023, Eqs. 8–9): L ≥ I ≥ S the sides of
// CGAL's minimum-volume oriented bounding box (seeded, so deterministic), ASR = S/L, elongation
// I/L, flatness S/I, Wadell sphericity, convexity; and the 2D projected aspect ratio (Feret min /
// Feret max of silhouettes in random directions), which is what an image of the particle
// measures and so what must match the images.
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "geometry/mesh.hpp"

namespace shapepress::geometry {

struct OrientedBox {
  Vec3 lengths = Vec3::Zero();   // L ≥ I ≥ S, m
  Mat3 axes = Mat3::Identity();  // columns: directions of L, I, S
  Vec3 centre = Vec3::Zero();
};
// Minimum-volume oriented box (CGAL Optimal_bounding_box, over the convex hull).
OrientedBox minimum_oriented_box(const std::vector<Vec3>& points, std::uint64_t seed = 1);

// Indices of the points that are vertices of their convex hull (invariant under affine maps).
std::vector<std::size_t> convex_hull_vertices(const std::vector<Vec3>& points);
double convex_hull_volume(const std::vector<Vec3>& points);

// Feret min / Feret max of the orthogonal projection of `points` along `direction` (of their
// 2D convex hull, which is all a silhouette's Feret diameters depend on).
struct Feret {
  double min = 0.0, max = 0.0;
  double ratio() const { return max > 0.0 ? min / max : 0.0; }
};
Feret projected_feret(const std::vector<Vec3>& points, const Vec3& direction);

struct DescribeOptions {
  int directions = 64;  // random viewing directions for the projected ASR
  std::uint64_t seed = 1;
};

struct ShapeDescriptors {
  double volume_m3 = 0.0, area_m2 = 0.0;
  double L_m = 0.0, I_m = 0.0, S_m = 0.0;
  double asr = 0.0, elongation = 0.0, flatness = 0.0;  // S/L, I/L, S/I (Eqs. 8–9)
  double sphericity = 0.0;                             // Wadell: π^(1/3) (6V)^(2/3) / A
  double convexity = 0.0;                              // V / V(convex hull)
  double volume_equivalent_diameter_m = 0.0;
  // Projected-area equivalent circle diameter averaged over directions, by Cauchy's formula
  // (mean projected area = A/4 for convex bodies): sqrt(A/π).
  double projected_equivalent_diameter_m = 0.0;
  std::vector<double> projected_asr;  // one per direction
  double projected_asr_mean = 0.0, projected_asr_std = 0.0;
};

ShapeDescriptors describe(const TriangleMesh& mesh, const DescribeOptions& options = {});

// The scalar descriptors (all but projected_asr) in one order, by the names of describe's CSV
// columns and of generate's checkpoint keys, and each one's field of `d`.
inline constexpr std::size_t descriptor_scalar_count = 14;
extern const std::array<std::string_view, descriptor_scalar_count> descriptor_scalar_names;
std::array<double*, descriptor_scalar_count> descriptor_scalars(ShapeDescriptors& d);

}  // namespace shapepress::geometry
