#pragma once
// The DEM engine for spheres: velocity Verlet for translation and rotation, Hertz–Mindlin
// contacts through a Verlet half list (neighbor_list.hpp), plane walls normal to z, gravity,
// periodic x/y, divergence detection. Deterministic: each contact's force is computed once and
// added to its two spheres in list order within fixed chunks of spheres (set by the sphere
// count, not the thread count); a contact whose partner lies in a later chunk goes through a
// per-contact array that the partner gathers in a fixed order (no atomics), so results are
// bit-identical for any thread count.
// How the contact laws, the Love–Weber particle stress, bonds and rigid clumps enter these loops
// and keep that property: docs/architecture.md, "Inside the engine".
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "simulate/bonds.hpp"
#include "simulate/clumps.hpp"
#include "simulate/contact_law.hpp"
#include "simulate/materials.hpp"
#include "simulate/neighbor_list.hpp"
#include "simulate/state.hpp"

namespace shapepress::simulate {

// A plane z = position. facing = +1: spheres live above it (bottom plate); -1: below (punch).
struct PlaneWall {
  double position = 0.0;  // m
  int facing = 1;
  double velocity = 0.0;  // m/s along z, set by the punch program
  int material = 0;
};

// Below these sizes a loop runs on one thread: on a loaded machine a parallel region's barrier
// can cost a scheduler time slice, far more than the work. Results are the same either way.
inline constexpr std::int64_t parallel_min_spheres = 1024;
inline constexpr std::int64_t parallel_min_pairs = 4096;

// Divergence of a bonded pair that does not take the contact law (contact_when_bonded false):
// an overlap beyond this fraction of the radii sum, centres nearer than a fifth of it. Such a
// pair is one elastic body whose bond may be pressed to well under its length (diagnostics.cpp).
inline constexpr double bond_only_overlap_limit = 0.8;

struct EngineSettings {
  double time_step = 0.0;                           // s
  std::array<double, 3> gravity = {0.0, 0.0, 0.0};  // m/s²
  double skin = 0.0;                                // m, Verlet skin
  double max_overlap_fraction = 0.5;  // divergence: overlap beyond this fraction of a radius
  int check_every = 100;              // steps between divergence checks
  // Love–Weber stress per sphere even when no pair uses the multi-contact law (snapshots).
  bool particle_stress = false;
  // Cundall's local (non-viscous) damping α in [0, 1) on every sphere's translation and
  // rotation (Potyondy & Cundall 2004 §2.1.4): each force and torque component F is applied
  // as F − α |F| sign(v) (locally_damped()). It removes energy only while the sphere is out of
  // balance, so a static equilibrium is the same with and without it; a bed loaded steadily is
  // not (the rubber sphere's curve moved by 2 % RMS at α = 0.7, docs/models.md), and it damps
  // rigid-body motion too, so it is not for flows or impacts. 0: off (the same bits as an engine
  // without it). Rigid clumps are not damped.
  double local_damping = 0.0;
  // Multiple time stepping (r-RESPA, Tuckerman, Berne & Martyna 1992): with bonds and n > 1,
  // each step of `time_step` integrates the bonds over n sub-steps of time_step / n between two
  // half kicks of the contacts, walls and gravity, which are evaluated once per step. The bonds
  // are the stiffest forces of a bonded bed (timestep.hpp) and the contacts the costly ones, so
  // the contacts take the step their own bound allows. 1: single-rate velocity Verlet (the
  // same bits as an engine without it). Not with local damping or rigid clumps.
  int bond_substeps = 1;
};

// Potyondy & Cundall 2004 §2.1.4: the force component f on a degree of freedom moving
// at v, less α |f| against the motion. Moving towards balance (f v > 0) a sphere gains
// (1 − α) of the work, moving away it pays (1 + α): each swing's energy falls by
// (1 − α)/(1 + α) in any potential.
inline double locally_damped(double f, double v, double alpha) {
  const double sign = static_cast<double>((v > 0.0) - (v < 0.0));
  return f - alpha * std::fabs(f) * sign;
}

// Components of a symmetric stress tensor as given per sphere (Pa), in XDMF's Tensor6 order.
inline constexpr int stress_components = 6;  // xx, xy, xz, yy, yz, zz

// Everything a restart needs beyond the sphere state (snapshot.cpp writes and reads it).
struct EngineCheckpoint {
  std::int64_t step = 0;
  double time = 0.0;
  std::vector<PlaneWall> walls;
  Vec3Array build_reference;                // positions at the last list build
  std::vector<double> build_wall_position;  // [wall] positions at the last list build
  // Touching contacts with their history, sorted by (first, second).
  std::vector<std::int32_t> first, second;
  std::vector<ContactHistory> history;
  std::vector<std::vector<ContactHistory>> wall_history;  // [wall][sphere]
  std::vector<double> wall_force;                         // [wall], z, on the wall
  std::vector<double> particle_pressure;  // per sphere, the last gather's; empty: not computed
  double energy_reference = 0.0;
  double work_in = 0.0;
  // With bond sub-steps (EngineSettings::bond_substeps): the bonds' and the slow forces' share of
  // the state's force and torque, fx fy fz tx ty tz per sphere each (empty for single-rate runs).
  std::vector<double> bond_force, slow_force;
  BondSet bonds;    // with their accumulated forces and moments (empty without BMS particles)
  ClumpSet clumps;  // bodies with their motion and last force and torque (empty without CMS)
};

struct EnergySummary {
  double kinetic = 0.0;        // translational + rotational, J
  double elastic = 0.0;        // Hertz normal + tangential springs, J
  double gravitational = 0.0;  // -Σ m g·x, J
};

class Engine {
 public:
  // Computes the initial forces (the first half-kick needs them). Checks that every material
  // pair that can meet has an interaction.
  // `bonds` (create_bonds) join the sub-spheres of BMS particles; `clumps` (add_clump) make
  // rigid bodies of the sub-spheres of CMS particles (InputError when a bond joins a clump's
  // sub-sphere: a clump is rigid).
  Engine(SphereState state, Box box, MaterialTable materials, std::vector<PlaneWall> walls,
         EngineSettings settings, BondSet bonds = {}, ClumpSet clumps = {});
  // Continues from a checkpoint: the forces in `state` are those of the step it was taken at.
  Engine(SphereState state, Box box, MaterialTable materials, EngineSettings settings,
         EngineCheckpoint checkpoint);

  // One velocity Verlet step (of bond sub-steps within it, EngineSettings::bond_substeps).
  // Throws ComputationError naming sphere and step on divergence.
  void step();
  // Runs the divergence checks now (step() runs them every settings.check_every steps).
  void check_divergence() const;

  const SphereState& state() const { return state_; }
  // Scenario set-up (launch velocities). Call rebase_energy() after changing the state: the
  // energy check must not count that change as energy from nowhere, and the packed copies of
  // radius, mass and inertia the force loops read are refreshed there.
  SphereState& mutable_state() { return state_; }
  // The bodies' motion, for scenario set-up and drags applied between steps (pack's settle);
  // the sub-spheres follow at the next step.
  ClumpSet& mutable_clumps() { return clumps_; }
  void rebase_energy();
  const Box& box() const { return box_; }
  const MaterialTable& materials() const { return materials_; }
  const EngineSettings& settings() const { return settings_; }
  std::vector<PlaneWall>& walls() { return walls_; }
  const std::vector<PlaneWall>& walls() const { return walls_; }
  std::int64_t step_index() const { return step_; }
  double time() const { return time_; }

  // z component of the force the spheres exert on wall k (< 0 on a loaded bottom plate).
  double wall_force(std::size_t k) const { return wall_force_[k]; }
  // Compressive load on wall k, > 0 when the spheres press on it.
  double wall_load(std::size_t k) const { return -walls_[k].facing * wall_force_[k]; }
  // Sphere–sphere contacts (overlap > 0) and sphere–wall contacts at the last force evaluation.
  std::int64_t sphere_contacts() const { return sphere_contacts_; }
  std::int64_t wall_contacts() const { return wall_contacts_; }
  // Number of contacts of each sphere (spheres and walls), for snapshots.
  std::vector<std::int32_t> contacts_per_sphere() const;
  EnergySummary energy() const;
  // Work done on the spheres by moving walls and by gravity since the start, J.
  double work_in() const { return work_in_; }
  std::int64_t list_builds() const { return list_builds_; }
  // Love–Weber stress of each sphere from the contacts and bonds of the last force evaluation
  // (a bond's force acts at the bond centre, so V σ summed over a body's sub-spheres is the
  // body's stress from its external contacts): the symmetric part of (1/V) Σ l ⊗ f,
  // stress_components per sphere, summed now (empty when the
  // engine does not compute particle stress: no multi-contact pair, settings.particle_stress
  // false). particle_pressure(i) is the p = -tr σ/3 the law reads next step.
  bool computes_particle_stress() const { return particle_stress_on_; }
  std::vector<double> particle_stress() const;
  double particle_pressure(std::size_t i) const { return pressure_[i]; }
  const BondSet& bonds() const { return bonds_; }
  const ClumpSet& clumps() const { return clumps_; }

  EngineCheckpoint checkpoint() const;

 private:
  void build_list(bool wrap);
  // The displacement field z -> offset + strain (z - origin) the rebuild test measures against.
  struct AffineDrift {
    double offset = 0.0, strain = 0.0, origin = 0.0;
  };
  AffineDrift list_affine_drift() const;
  // step()'s half kick and drift (with Cundall damping when `damped`); returns the largest
  // squared deviation from the drift field since the last list build.
  // `force` and `torque`: the forces of the kick (the state's, or the bonds' alone when
  // substepping), over a step of `dt`.
  template <bool damped>
  double kick_drift(const AffineDrift& drift, double dt, const double* const force[6]);
  // Rebuilds the list when a sphere may have moved into reach of a pair or wall it lacks.
  void rebuild_list_if_needed(double largest, const AffineDrift& drift);
  // Forces and torques of the current positions; `kick` > 0 also adds kick × F/m to the
  // velocities (the second half kick of velocity Verlet, fused into the gather).
  void compute_forces(double kick);
  // Multiple time stepping (EngineSettings::bond_substeps).
  bool substeps_bonds() const { return settings_.bond_substeps > 1 && !bonds_.empty(); }
  void step_with_bond_substeps();
  // The bonds' forces over one sub-step of `dt` into bond_force_, with `kick` × them added to
  // the velocities.
  void bond_substep_forces(double dt, double kick);
  // The slow forces (contacts, walls, gravity) with `kick` × them on the velocities, then the
  // state's force = slow + bonds.
  void slow_forces(double kick);
  void pack_spheres();  // geometry_ and motion_ from the state (step() fuses this into its drift)
  void pair_forces();
  void index_bonded_pairs();       // pair_bond_ for the current list
  void index_cross_chunk_pairs();  // cross_second_end_ for the current list
  void find_wall_candidates();     // wall_candidates_ at a list build
  // Per sphere: its contacts in fixed order, its bonds (unless `with_bonds` is false: bond
  // sub-steps kick them on their own), walls, gravity.
  void gather_forces(double kick, bool with_bonds = true);
  // Law: one of NormalLaws, or AnyNormalLaw (contact_law.hpp) for a scene mixing laws.
  template <bool stress_on, class Law>
  void pair_forces_with();
  template <bool stress_on, bool damped, class Law>
  void gather_forces_with(double kick, bool with_bonds);
  void require_material_pairs() const;
  void require_bond_substeps();  // and sizes the force shares
  void enable_particle_stress();
  void index_clumps();  // clumps_.index and the checks against bonds
  // The packed mass of every clump sub-sphere (motion_[8 i + 6]) for this evaluation's contact
  // damping: its clump's M over the clump's touching contacts with the same partner body
  // (clump_damping.cpp).
  void share_clump_damping_mass();

  SphereState state_;
  Box box_;
  MaterialTable materials_;
  std::vector<PlaneWall> walls_;
  EngineSettings settings_;
  std::int64_t step_ = 0;
  double time_ = 0.0;

  PairList pairs_;
  std::vector<ContactHistory> history_;
  Vec3Array build_reference_;
  std::vector<double> build_wall_position_;  // wall positions at the last list build
  double list_reach_ = 0.0;                  // 2 r_max + skin of the last build
  struct PairResult {
    double force[3];  // on second
    double torque_first[3];
    double torque_second[3];
  };
  // Compact: one result per touching pair, at slot 1 + its rank among the touching pairs of the
  // list; slot 0 holds zeros and is where every non-touching pair points. Only touching pairs
  // are written and read, so a sparse bed does not stream a result per list pair.
  std::vector<PairResult> pair_results_;
  std::vector<std::int32_t> pair_slot_;  // per list pair: its slot in pair_results_
  std::vector<double> geometry_;         // per sphere x, y, z, r (pair_forces)
  std::vector<double> motion_;           // per sphere predicted v, ω, then m, 1/I
  int sphere_material_ = -1;             // the spheres' one material, or -1 (pack_spheres)
  // One byte per pair: whether it touched at the last pair loop, so that a contact that opens
  // has its spring released; the pair loop writes no result for the others.
  std::vector<std::uint8_t> pair_touching_;
  std::vector<std::int32_t> touching_index_;  // per thread chunk: its touching pairs (pair loop)
  // The pair loop adds each contact's force and torques to both spheres directly when both lie
  // in one chunk of force_chunks_ consecutive sphere ranges (set by the sphere count, never by
  // the thread count, so every sum runs in the same order on any number of threads); a thread
  // owns whole chunks. A partner in a later chunk reads the pair's result in the gather:
  // cross_second_end_[i] ends the prefix of i's "second" pairs whose first lies in an earlier
  // chunk. With Love–Weber every touching pair's result is kept too, for the stress tensor on
  // demand (diagnostics.cpp).
  struct alignas(64) SphereSums {
    double force[3] = {0.0, 0.0, 0.0};
    double torque[3] = {0.0, 0.0, 0.0};
    double arm_force = 0.0;  // Σ rc Fn over the contacts (Love–Weber only)
  };
  // Chunk c holds spheres [chunk_start(c), chunk_start(c + 1)); thread `rank` of `team` takes
  // chunks [thread_chunk_start(rank, team), thread_chunk_start(rank + 1, team)) in both force
  // loops, so the gather reads the sums its own thread wrote.
  std::int64_t chunk_start(std::int64_t chunk) const {
    return static_cast<std::int64_t>(state_.size()) * chunk / force_chunks_;
  }
  std::int64_t thread_chunk_start(std::int64_t rank, std::int64_t team) const {
    return force_chunks_ * rank / team;
  }
  // A wall contact that opened: its spring, flag and force go back to zero.
  void release_wall_contact(std::size_t wall, std::size_t sphere);
  std::vector<SphereSums> sphere_sums_;
  std::vector<std::int32_t> cross_second_end_;
  std::int64_t force_chunks_ = 1;
  std::vector<std::vector<ContactHistory>> wall_history_;
  std::vector<std::vector<double>> wall_force_per_sphere_;  // [wall][sphere], z on the wall
  std::vector<std::vector<std::uint8_t>> wall_touching_;
  std::vector<double> wall_force_;
  // [wall]: the spheres, in index order, within r + skin of the wall at the last list build:
  // the only ones that can touch it before the next (Engine::step's rebuild test).
  std::vector<std::vector<std::int32_t>> wall_candidates_;
  std::vector<double> wall_chunk_force_;           // [chunk][wall], the gather's partial sums
  std::vector<std::int64_t> wall_chunk_contacts_;  // [chunk]
  // Love–Weber stress (header comment): per pair Fn and δ/2 of the last pair loop, per sphere
  // p (read by the next pair loop), per wall and sphere the tangential wall force (x, y).
  bool particle_stress_on_ = false;
  std::vector<double> pair_virial_;
  std::vector<double> pressure_;
  std::vector<std::vector<double>> wall_tangential_;
  std::int64_t sphere_contacts_ = 0;
  std::int64_t wall_contacts_ = 0;
  std::int64_t list_builds_ = 0;
  double energy_reference_ = 0.0;  // total energy at the start
  BondSet bonds_;
  // Per list pair: the index of its bond, or -1 (only filled when bonded pairs skip the contact
  // law, BondSet::contact_when_bonded false).
  std::vector<std::int32_t> pair_bond_;
  bool bond_increments_ = false;  // false for the forces at t = 0: no step has moved anything
  // With bond sub-steps: fx fy fz tx ty tz per sphere of the bonds and of the rest.
  std::vector<double> bond_force_, slow_force_;
  double work_in_ = 0.0;
  ClumpSet clumps_;
  std::vector<std::array<std::int64_t, 3>> clump_contacts_;  // share_clump_damping_mass scratch
};

}  // namespace shapepress::simulate
