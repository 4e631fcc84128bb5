#pragma once
// Rigid clumps of overlapping sub-spheres: the conventional multi-sphere (CMS) particle of the
// paper's §2.4. Sub-spheres keep fixed offsets in the body frame, never interact with each other,
// and take their motion from the body; the body moves under the sum of its sub-spheres' contact
// forces and their torques about its centre of mass.
//
// Mass and inertia belong to the *union* of the sub-spheres (overlaps counted once), integrated
// on a voxel grid (geometry::union_mass_properties; the paper uses Monte Carlo for the same
// reason). The body frame is the principal frame, so the rotation is integrated by the
// principal-axis splitting of rigid_body.hpp.
//
// How the engine uses a ClumpSet (engine.hpp):
// - sub-spheres carry no mass of their own in SphereState (mass = 1/m = 1/I = 0), so the plain
//   per-sphere kick–drift leaves their velocities alone; gravity acts on the body, once (the
//   gather's weight of a sub-sphere's packed mass is taken off again in the clump sum);
// - the pair loop and the wall contacts see a sub-sphere as a sphere moving with the body, of
//   the mass its contacts' restitution damping needs: the clump's M over the number k of the
//   clump's touching contacts with the same partner body (Engine::share_clump_damping_mass,
//   clump_damping.cpp). One contact damps with M, as LIGGGHTS' multisphere and Yade give every
//   clump member, so a clump–clump impact rebounds with the input e; k contacts with one
//   partner damp together as one contact of their summed stiffness, √(K M). M/n for every
//   sub-sphere, as before, damped a single contact √n times too little (e = 0.352 rebounded
//   at 0.90 with n = 89); M for every contact damps k of them √k times too much (600 contacts
//   under the plates made the step unstable);
// - after the per-sphere gather the clump sums force and torque over its sub-spheres in index
//   order (the same bits for any thread count), kicks the body and sets the sub-spheres' velocity
//   v + ω × r and angular velocity ω.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "simulate/rigid_body.hpp"
#include "simulate/state.hpp"

namespace shapepress::simulate {

// The union of a clump's sub-spheres per unit density, in the frame its centres were given in.
struct ClumpGeometry {
  double volume = 0.0;                    // m³
  Vector3 centre = {0.0, 0.0, 0.0};       // centre of mass, m
  Vector3 principal_moments = {0, 0, 0};  // m⁵ (× density: kg m²), ascending
  Quaternion axes;                        // rotates principal (body) axes into the given frame
};

// Voxel integration of the union on `cells` cells along the longest side of its box.
// InputError naming `name` when the clump is empty, has a sub-sphere of radius ≤ 0 or zero
// volume, or when its sub-spheres do not form one overlapping cluster (a clump is one rigid
// particle: two groups that do not touch would move as one body through empty space).
ClumpGeometry clump_geometry(std::span<const Vector3> centres, std::span<const double> radii,
                             const std::string& name, int cells = 128);

struct ClumpSet {
  // Per clump: its sub-spheres are the sphere indices [first, last), contiguous.
  std::vector<std::int32_t> first, last;
  std::vector<double> mass;    // kg
  std::vector<double> volume;  // m³, of the union
  Vec3Array centre;            // centre of mass, m
  Vec3Array velocity;          // of the centre of mass, m/s
  std::vector<RigidRotation> rotation;
  // Force and torque about the centre of the last evaluation (contacts + gravity), N and N m.
  Vec3Array force, torque;
  // Per sub-sphere, in clump order (clump c's are [member_start(c), …) of length last - first):
  // the body-frame offset of the sub-sphere centre from the centre of mass.
  Vec3Array offset;

  // Derived by index() (not saved).
  std::vector<std::int32_t> clump_of;  // per sphere: its clump, -1 for a plain sphere
  std::vector<std::int32_t> member_start;
  Vec3Array arm;  // per sub-sphere, world-frame offset at the last placement

  std::size_t size() const { return first.size(); }
  bool empty() const { return first.empty(); }
  // Checks the ranges against `state` (InputError) and fills the derived arrays.
  void index(std::size_t sphere_count);
  // ω of clump c in the world frame.
  Vector3 angular_velocity(std::size_t c) const { return simulate::angular_velocity(rotation[c]); }
};

// Appends a clump to `state` and `clumps`: sub-spheres at the given world centres (their body
// offsets from the union's principal frame), of one material, the body of the union's mass and
// inertia at `density`, at rest. The sub-spheres are placed back from the body (centre + R
// offset) so the state is exactly what the engine will keep. Returns the clump's index.
std::size_t add_clump(SphereState& state, ClumpSet& clumps, std::span<const Vector3> centres,
                      std::span<const double> radii, double density, int material,
                      const std::string& name, int cells = 128);

// Appends a clump whose mass properties are known (a template's, scaled), without integrating
// them again: sub-spheres at `body_centres` in the body frame (centre of mass at the origin, axes
// the principal axes), the body at `centre` turned by `orientation` (body axes → world), of
// `mass`, union `volume` and `principal_inertia` (kg m² about the body axes), at rest.
// InputError naming `name` for a mass, volume or moment that is not > 0.
std::size_t add_rigid_clump(SphereState& state, ClumpSet& clumps,
                            std::span<const Vector3> body_centres, std::span<const double> radii,
                            const Vector3& centre, const Quaternion& orientation, double mass,
                            double volume, const Vector3& principal_inertia, int material,
                            const std::string& name);

// The least mass a sub-sphere of clump c can bring to its contacts' damping, M / (sub-sphere
// count): all of them touching one partner (the time step's damping-rate bound).
inline double clump_damping_mass(const ClumpSet& clumps, std::size_t c) {
  return clumps.mass[c] / static_cast<double>(clumps.last[c] - clumps.first[c]);
}

// Engine steps (engine.cpp calls these; clumps.cpp explains each).
// First half kick of the body and its drift and free rotation over dt.
void advance_clumps(ClumpSet& clumps, double dt);
// Sub-sphere positions, velocities and angular velocities from the bodies, and the packed
// copies the pair loop reads (4 doubles per sphere of geometry, 8 of motion: predicted
// end-of-step v, ω, then the clump's mass, shared per contact before the pair loop, and the
// clump's largest 1/I). Returns the largest
// squared displacement of a sub-sphere since `reference` (the list build positions).
double place_clump_spheres(ClumpSet& clumps, SphereState& state, double* geometry, double* motion,
                           double half_dt, const Vec3Array& reference);
// Sums the sub-spheres' forces and torques (gathered into `state`) per clump about its centre,
// adds gravity (taking off the packed mass × g the per-sphere gather added, `motion`), applies
// the second half kick `kick` (0: none) and sets the sub-sphere velocities from the body.
void gather_clump_forces(ClumpSet& clumps, SphereState& state, const double* motion,
                         const std::array<double, 3>& g, double kick);
// Translational + rotational kinetic energy of the bodies, J.
double clump_kinetic_energy(const ClumpSet& clumps);
// Moves clump centres into [0, L) in the periodic directions and their sub-spheres with them
// (list builds only, as wrap_positions for plain spheres).
void wrap_clumps(ClumpSet& clumps, SphereState& state, const Box& box);

}  // namespace shapepress::simulate
