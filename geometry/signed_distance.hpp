#pragma once
// One shape interface for every sub-sphere filler: a signed distance (negative inside, metres)
// and a box that contains the shape. Analytic spheres and ellipsoids and voxelised meshes
// (mesh_distance.hpp) are all SignedDistance values, so the BMS and CMS fillers are one code
// path whatever the shape came from.
#include <functional>
#include <string>

#include "geometry/mesh.hpp"

namespace shapepress::geometry {

struct SignedDistance {
  std::function<double(const Vec3&)> distance;  // < 0 inside; thread-safe to call
  Aabb bounds;                                  // contains every point with distance <= 0
  std::string description;                      // "sphere r=1e-4 m", "mesh a.stl (voxel 2e-6 m)"

  double operator()(const Vec3& p) const { return distance(p); }
  // Central-difference gradient with step h (outward unit normal on the surface).
  Vec3 gradient(const Vec3& p, double h) const;
};

SignedDistance sphere_distance(double radius, const Vec3& centre = Vec3::Zero());
// Exact Euclidean distance to an axis-aligned ellipsoid (semi-axes a ≥ 0 along x, y, z), by
// bisection on the closest-point parameter (Eberly, "Distance from a point to an ellipse, an
// ellipsoid, or a hyperellipsoid", 2013).
SignedDistance ellipsoid_distance(const Vec3& semi_axes, const Vec3& centre = Vec3::Zero());

// Points on the zero level set: cell centres of a grid of `cells` per longest side that lie
// within one cell of the surface, projected onto it along the gradient (two Newton steps).
std::vector<Vec3> surface_samples(const SignedDistance& shape, int cells);

}  // namespace shapepress::geometry
