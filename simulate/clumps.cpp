#include "simulate/clumps.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "common/error.hpp"
#include "geometry/sphere_fill.hpp"
#include "geometry/template_quality.hpp"
#include "simulate/neighbor_list.hpp"

namespace shapepress::simulate {
namespace {

// The unit quaternion of a proper rotation matrix (Shepperd's method: the largest of the four
// candidates under the square root, so no division by a small number).
Quaternion quaternion_from(const geometry::Mat3& r) {
  const double trace = r(0, 0) + r(1, 1) + r(2, 2);
  Quaternion q;
  if (trace > std::max({r(0, 0), r(1, 1), r(2, 2)})) {
    const double s = 2.0 * std::sqrt(1.0 + trace);
    q = {0.25 * s, (r(2, 1) - r(1, 2)) / s, (r(0, 2) - r(2, 0)) / s, (r(1, 0) - r(0, 1)) / s};
  } else if (r(0, 0) >= r(1, 1) && r(0, 0) >= r(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + r(0, 0) - r(1, 1) - r(2, 2));
    q = {(r(2, 1) - r(1, 2)) / s, 0.25 * s, (r(0, 1) + r(1, 0)) / s, (r(0, 2) + r(2, 0)) / s};
  } else if (r(1, 1) >= r(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + r(1, 1) - r(0, 0) - r(2, 2));
    q = {(r(0, 2) - r(2, 0)) / s, (r(0, 1) + r(1, 0)) / s, 0.25 * s, (r(1, 2) + r(2, 1)) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 + r(2, 2) - r(0, 0) - r(1, 1));
    q = {(r(1, 0) - r(0, 1)) / s, (r(0, 2) + r(2, 0)) / s, (r(1, 2) + r(2, 1)) / s, 0.25 * s};
  }
  return normalized(q);
}

Vector3 cross(const Vector3& a, const Vector3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

}  // namespace

ClumpGeometry clump_geometry(std::span<const Vector3> centres, std::span<const double> radii,
                             const std::string& name, int cells) {
  if (centres.empty() || centres.size() != radii.size())
    throw InputError(
        fmt::format("clump {}: no sub-spheres (or centres and radii differ in count)", name));
  std::vector<geometry::Vec3> c;
  std::vector<double> r(radii.begin(), radii.end());
  for (std::size_t i = 0; i < centres.size(); ++i) {
    if (!(radii[i] > 0.0) || !std::isfinite(radii[i]))
      throw InputError(
          fmt::format("clump {}: sub-sphere {} has radius {} m: a sub-sphere of "
                      "zero volume is no part of a rigid body",
                      name, i, radii[i]));
    c.emplace_back(centres[i][0], centres[i][1], centres[i][2]);
  }
  // One rigid particle: the overlap graph (|xi - xj| < ri + rj) must be connected.
  const std::vector<int> component =
      geometry::connected_components(c.size(), geometry::pairs_within(c, r, 1.0));
  const int groups = 1 + *std::max_element(component.begin(), component.end());
  if (groups > 1) {
    const auto apart = std::find(component.begin(), component.end(), 1) - component.begin();
    throw InputError(fmt::format(
        "clump {}: its {} sub-spheres form {} separate groups (sub-sphere {} does not overlap "
        "the group of sub-sphere 0): an overlapping fill must be connected to be one rigid body",
        name, c.size(), groups, apart));
  }
  const geometry::MassProperties u = geometry::union_mass_properties(c, r, cells);
  if (!(u.volume > 0.0))
    throw InputError(fmt::format("clump {}: the union of its sub-spheres has zero volume", name));
  ClumpGeometry out;
  out.volume = u.volume;
  out.centre = {u.centre.x(), u.centre.y(), u.centre.z()};
  out.principal_moments = {u.principal_moments.x(), u.principal_moments.y(),
                           u.principal_moments.z()};
  out.axes = quaternion_from(u.principal_axes);  // columns: the principal axes, right-handed
  for (double& moment : out.principal_moments)
    if (!(moment > 0.0))
      throw InputError(
          fmt::format("clump {}: a principal moment of inertia is {} (the union "
                      "is thinner than one integration cell)",
                      name, moment));
  return out;
}

void ClumpSet::index(std::size_t sphere_count) {
  clump_of.assign(sphere_count, -1);
  member_start.assign(size() + 1, 0);
  for (std::size_t c = 0; c < size(); ++c) {
    if (first[c] < 0 || last[c] <= first[c] || static_cast<std::size_t>(last[c]) > sphere_count)
      throw InputError(
          fmt::format("clump {}: sub-sphere range [{}, {}) is not within the {} "
                      "spheres",
                      c, first[c], last[c], sphere_count));
    for (std::int32_t i = first[c]; i < last[c]; ++i) {
      if (clump_of[i] >= 0)
        throw InputError(fmt::format("clumps {} and {} share sphere {}", clump_of[i], c, i));
      clump_of[i] = static_cast<std::int32_t>(c);
    }
    member_start[c + 1] = member_start[c] + (last[c] - first[c]);
  }
  if (offset.size() != static_cast<std::size_t>(member_start.back()))
    throw InputError("clumps: the sub-sphere offsets do not match the sub-sphere ranges");
  arm.resize(offset.size());
}

std::size_t add_clump(SphereState& state, ClumpSet& clumps, std::span<const Vector3> centres,
                      std::span<const double> radii, double density, int material,
                      const std::string& name, int cells) {
  if (!(density > 0.0)) throw InputError(fmt::format("clump {}: density must be > 0", name));
  const ClumpGeometry g = clump_geometry(centres, radii, name, cells);
  const std::size_t c = clumps.size();
  const auto begin = static_cast<std::int32_t>(state.size());
  clumps.first.push_back(begin);
  clumps.last.push_back(begin + static_cast<std::int32_t>(centres.size()));
  clumps.mass.push_back(density * g.volume);
  clumps.volume.push_back(g.volume);
  clumps.centre.push_back(g.centre[0], g.centre[1], g.centre[2]);
  clumps.velocity.push_back(0.0, 0.0, 0.0);
  clumps.force.push_back(0.0, 0.0, 0.0);
  clumps.torque.push_back(0.0, 0.0, 0.0);
  RigidRotation rotation;
  rotation.orientation = g.axes;
  for (int k = 0; k < 3; ++k)
    rotation.principal_inertia[k] = density * g.principal_moments[k];
  clumps.rotation.push_back(rotation);
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const Vector3 world = {centres[i][0] - g.centre[0], centres[i][1] - g.centre[1],
                           centres[i][2] - g.centre[2]};
    const Vector3 body = rotate_to_body(g.axes, world);
    clumps.offset.push_back(body[0], body[1], body[2]);
    const Vector3 arm = rotate_to_world(g.axes, body);
    // No own mass (header): the body carries it.
    state.add_sphere(g.centre[0] + arm[0], g.centre[1] + arm[1], g.centre[2] + arm[2], radii[i],
                     0.0, material);
    state.body.back() = begin;
  }
  clumps.index(state.size());
  return c;
}

std::size_t add_rigid_clump(SphereState& state, ClumpSet& clumps,
                            std::span<const Vector3> body_centres, std::span<const double> radii,
                            const Vector3& centre, const Quaternion& orientation, double mass,
                            double volume, const Vector3& principal_inertia, int material,
                            const std::string& name) {
  if (!(mass > 0.0 && volume > 0.0 && principal_inertia[0] > 0.0 && principal_inertia[1] > 0.0 &&
        principal_inertia[2] > 0.0))
    throw InputError(fmt::format("clump {}: mass, volume and principal moments must be > 0", name));
  if (body_centres.empty() || body_centres.size() != radii.size())
    throw InputError(fmt::format("clump {}: needs sub-spheres, one radius each", name));
  const std::size_t c = clumps.size();
  const auto begin = static_cast<std::int32_t>(state.size());
  clumps.first.push_back(begin);
  clumps.last.push_back(begin + static_cast<std::int32_t>(body_centres.size()));
  clumps.mass.push_back(mass);
  clumps.volume.push_back(volume);
  clumps.centre.push_back(centre[0], centre[1], centre[2]);
  clumps.velocity.push_back(0.0, 0.0, 0.0);
  clumps.force.push_back(0.0, 0.0, 0.0);
  clumps.torque.push_back(0.0, 0.0, 0.0);
  RigidRotation rotation;
  rotation.orientation = normalized(orientation);
  rotation.principal_inertia = principal_inertia;
  clumps.rotation.push_back(rotation);
  for (std::size_t i = 0; i < body_centres.size(); ++i) {
    const Vector3& body = body_centres[i];
    clumps.offset.push_back(body[0], body[1], body[2]);
    const Vector3 arm = rotate_to_world(rotation.orientation, body);
    state.add_sphere(centre[0] + arm[0], centre[1] + arm[1], centre[2] + arm[2], radii[i], 0.0,
                     material);
    state.body.back() = begin;
  }
  clumps.index(state.size());
  return c;
}

// Velocity Verlet for the centre (half kick with the last force, drift) and, for the rotation,
// the half kick of L with the last torque and the free rotation over dt (rigid_body.hpp); the
// second half kicks come in gather_clump_forces.
void advance_clumps(ClumpSet& clumps, double dt) {
  const double half = 0.5 * dt;
  for (std::size_t c = 0; c < clumps.size(); ++c) {
    const double im = half / clumps.mass[c];
    clumps.velocity.x[c] += clumps.force.x[c] * im;
    clumps.velocity.y[c] += clumps.force.y[c] * im;
    clumps.velocity.z[c] += clumps.force.z[c] * im;
    clumps.centre.x[c] += dt * clumps.velocity.x[c];
    clumps.centre.y[c] += dt * clumps.velocity.y[c];
    clumps.centre.z[c] += dt * clumps.velocity.z[c];
    kick_rotation(clumps.rotation[c], {half * clumps.torque.x[c], half * clumps.torque.y[c],
                                       half * clumps.torque.z[c]});
    rotate_free(clumps.rotation[c], dt);
  }
}

double place_clump_spheres(ClumpSet& clumps, SphereState& s, double* geometry, double* motion,
                           double half_dt, const Vec3Array& reference) {
  double largest = 0.0;
  for (std::size_t c = 0; c < clumps.size(); ++c) {
    const RigidRotation& body = clumps.rotation[c];
    const Vector3 x = {clumps.centre.x[c], clumps.centre.y[c], clumps.centre.z[c]};
    const Vector3 v = {clumps.velocity.x[c], clumps.velocity.y[c], clumps.velocity.z[c]};
    const Vector3 omega = angular_velocity(body);
    // The pair loop's damping reads the end-of-step velocities predicted with the last force,
    // as for plain spheres (forces.cpp, pack_spheres).
    const double im = half_dt / clumps.mass[c];
    const Vector3 v_end = {v[0] + im * clumps.force.x[c], v[1] + im * clumps.force.y[c],
                           v[2] + im * clumps.force.z[c]};
    RigidRotation predicted = body;
    kick_rotation(predicted, {half_dt * clumps.torque.x[c], half_dt * clumps.torque.y[c],
                              half_dt * clumps.torque.z[c]});
    const Vector3 omega_end = angular_velocity(predicted);
    const Vector3& inertia = body.principal_inertia;
    const double inverse_inertia = 1.0 / std::min({inertia[0], inertia[1], inertia[2]});
    const double damping_mass = clumps.mass[c];  // shared per contact before the pair loop
    for (std::int32_t i = clumps.first[c], m = clumps.member_start[c]; i < clumps.last[c];
         ++i, ++m) {
      const Vector3 r = rotate_to_world(
          body.orientation, {clumps.offset.x[m], clumps.offset.y[m], clumps.offset.z[m]});
      clumps.arm.x[m] = r[0], clumps.arm.y[m] = r[1], clumps.arm.z[m] = r[2];
      const Vector3 spin = cross(omega, r), spin_end = cross(omega_end, r);
      s.position.x[i] = x[0] + r[0], s.position.y[i] = x[1] + r[1], s.position.z[i] = x[2] + r[2];
      s.velocity.x[i] = v[0] + spin[0], s.velocity.y[i] = v[1] + spin[1];
      s.velocity.z[i] = v[2] + spin[2];
      s.angular_velocity.x[i] = omega[0], s.angular_velocity.y[i] = omega[1];
      s.angular_velocity.z[i] = omega[2];
      double* g = geometry + 4 * static_cast<std::size_t>(i);
      g[0] = s.position.x[i], g[1] = s.position.y[i], g[2] = s.position.z[i], g[3] = s.radius[i];
      double* mo = motion + 8 * static_cast<std::size_t>(i);
      mo[0] = v_end[0] + spin_end[0], mo[1] = v_end[1] + spin_end[1];
      mo[2] = v_end[2] + spin_end[2];
      mo[3] = omega_end[0], mo[4] = omega_end[1], mo[5] = omega_end[2];
      mo[6] = damping_mass, mo[7] = inverse_inertia;
      const double dx = s.position.x[i] - reference.x[i], dy = s.position.y[i] - reference.y[i],
                   dz = s.position.z[i] - reference.z[i];
      largest = std::max(largest, dx * dx + dy * dy + dz * dz);
    }
  }
  return largest;
}

void gather_clump_forces(ClumpSet& clumps, SphereState& s, const double* motion,
                         const std::array<double, 3>& g, double kick) {
  for (std::size_t c = 0; c < clumps.size(); ++c) {
    // Fixed sub-sphere order: the same sum for any thread count.
    Vector3 f = {0.0, 0.0, 0.0}, t = {0.0, 0.0, 0.0};
    for (std::int32_t i = clumps.first[c], m = clumps.member_start[c]; i < clumps.last[c];
         ++i, ++m) {
      // The per-sphere gather added the sub-sphere's packed (damping) mass times g: taken off
      // here, so gravity acts once, at the centre of mass, and makes no torque.
      const double share = motion[8 * static_cast<std::size_t>(i) + 6];
      const Vector3 fi = {s.force.x[i] - share * g[0], s.force.y[i] - share * g[1],
                          s.force.z[i] - share * g[2]};
      const Vector3 moment = cross({clumps.arm.x[m], clumps.arm.y[m], clumps.arm.z[m]}, fi);
      for (int k = 0; k < 3; ++k)
        f[k] += fi[k];
      t[0] += s.torque.x[i] + moment[0];
      t[1] += s.torque.y[i] + moment[1];
      t[2] += s.torque.z[i] + moment[2];
    }
    const double mass = clumps.mass[c];
    for (int k = 0; k < 3; ++k)
      f[k] += mass * g[k];
    clumps.force.x[c] = f[0], clumps.force.y[c] = f[1], clumps.force.z[c] = f[2];
    clumps.torque.x[c] = t[0], clumps.torque.y[c] = t[1], clumps.torque.z[c] = t[2];
    if (kick > 0.0) {
      const double im = kick / mass;
      clumps.velocity.x[c] += f[0] * im;
      clumps.velocity.y[c] += f[1] * im;
      clumps.velocity.z[c] += f[2] * im;
      kick_rotation(clumps.rotation[c], {kick * t[0], kick * t[1], kick * t[2]});
    }
    // The sub-spheres move with the body (snapshots, energy, the next step's drift).
    const Vector3 v = {clumps.velocity.x[c], clumps.velocity.y[c], clumps.velocity.z[c]};
    const Vector3 omega = clumps.angular_velocity(c);
    for (std::int32_t i = clumps.first[c], m = clumps.member_start[c]; i < clumps.last[c];
         ++i, ++m) {
      const Vector3 spin = cross(omega, {clumps.arm.x[m], clumps.arm.y[m], clumps.arm.z[m]});
      s.velocity.x[i] = v[0] + spin[0], s.velocity.y[i] = v[1] + spin[1];
      s.velocity.z[i] = v[2] + spin[2];
      s.angular_velocity.x[i] = omega[0], s.angular_velocity.y[i] = omega[1];
      s.angular_velocity.z[i] = omega[2];
    }
  }
}

double clump_kinetic_energy(const ClumpSet& clumps) {
  double energy = 0.0;
  for (std::size_t c = 0; c < clumps.size(); ++c) {
    const double v2 = clumps.velocity.x[c] * clumps.velocity.x[c] +
                      clumps.velocity.y[c] * clumps.velocity.y[c] +
                      clumps.velocity.z[c] * clumps.velocity.z[c];
    energy += 0.5 * clumps.mass[c] * v2 + rotational_energy(clumps.rotation[c]);
  }
  return energy;
}

void wrap_clumps(ClumpSet& clumps, SphereState& s, const Box& box) {
  for (std::size_t c = 0; c < clumps.size(); ++c) {
    clumps.centre.x[c] = wrapped(clumps.centre.x[c], box.length_x);
    clumps.centre.y[c] = wrapped(clumps.centre.y[c], box.length_y);
    // Sub-spheres follow their centre (they may lie outside [0, L): the list takes any image).
    for (std::int32_t i = clumps.first[c], m = clumps.member_start[c]; i < clumps.last[c];
         ++i, ++m) {
      s.position.x[i] = clumps.centre.x[c] + clumps.arm.x[m];
      s.position.y[i] = clumps.centre.y[c] + clumps.arm.y[m];
    }
  }
}

}  // namespace shapepress::simulate
