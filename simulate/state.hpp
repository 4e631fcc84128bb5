#pragma once
// The sub-sphere state as a structure of arrays: each hot quantity is its own contiguous array of
// doubles (docs/architecture.md), so the contact loop and the integrator stream through memory.
// body[i] names the particle a sub-sphere belongs to: for plain spheres it is the sphere's own
// index; bonded agglomerates (BMS) and rigid clumps (CMS) give several sub-spheres one body id,
// which is how the contact loop knows which pairs are bonded or rigidly joined.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "simulate/staggered_allocator.hpp"

namespace shapepress::simulate {

// A per-sphere array. Each starts at its own offset within a page (staggered_allocator.hpp): the
// integrator streams some twenty of them at once.
template <class T>
using SphereArray = std::vector<T, StaggeredAllocator<T>>;

template <class T>
SphereArray<T> to_sphere_array(const std::vector<T>& values) {
  return SphereArray<T>(values.begin(), values.end());
}

struct Vec3Array {
  SphereArray<double> x, y, z;
  void resize(std::size_t n, double value = 0.0) {
    x.assign(n, value);
    y.assign(n, value);
    z.assign(n, value);
  }
  void push_back(double a, double b, double c) {
    x.push_back(a);
    y.push_back(b);
    z.push_back(c);
  }
  std::size_t size() const { return x.size(); }
  friend bool operator==(const Vec3Array&, const Vec3Array&) = default;
};

struct SphereState {
  Vec3Array position;          // m
  Vec3Array velocity;          // m/s
  Vec3Array angular_velocity;  // rad/s
  Vec3Array force;             // N, from the last force evaluation
  Vec3Array torque;            // N·m
  SphereArray<double> radius;  // m
  SphereArray<double> mass;    // kg
  SphereArray<double> inverse_mass;
  SphereArray<double> inverse_inertia;  // solid sphere: I = 2/5 m r²
  SphereArray<std::int32_t> material;
  SphereArray<std::int32_t> body;
  // m: the volume-equivalent radius of the particle the sphere belongs to (its shape's volume);
  // a plain sphere's own radius. Read by contacts between bodies (Interaction::contact_radius).
  SphereArray<double> body_radius;

  std::size_t size() const { return radius.size(); }
  // A solid sphere at rest; its body id is its own index.
  void add_sphere(double x, double y, double z, double r, double density, int material_index);
};

// The simulation box: periodic in x and y over [0, length_x) × [0, length_y) when periodic,
// bounded in z by the walls. length ≤ 0 means not periodic in that direction.
struct Box {
  double length_x = 0.0;
  double length_y = 0.0;
  bool periodic_x() const { return length_x > 0.0; }
  bool periodic_y() const { return length_y > 0.0; }
};

}  // namespace shapepress::simulate
