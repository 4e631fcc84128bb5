#pragma once
// Potyondy–Cundall parallel bonds between the sub-spheres of one bonded multi-sphere (BMS)
// particle (Potyondy & Cundall 2004, Int. J. Rock Mech. Min. Sci. 41; paper §2.3; models.md
// "Bonded multi-sphere"). A bond is a short elastic beam of radius R̄ = λ̄ min(ri, rj) between
// two sphere centres that carries a normal force, a shear force, a twisting and a bending moment:
//   A = π R̄²,  I = π R̄⁴/4,  J = π R̄⁴/2
//   ΔFn = k̄n A Δun,   ΔFs = -k̄s A Δus,   ΔMt = -k̄s J Δθt,   ΔMb = -k̄n I Δθb
// Forces and moments are accumulated incrementally and turned with the pair every step: the
// shear force and bending moment into the current plane normal to the bond keeping their length
// (the axis' tilt, as LIGGGHTS turns its tangential history), then about the bond by the pair's
// mean spin θ = dt (ωi + ωj)·n / 2 (as Yade's ScGeom), so a rigid turn of a loaded body leaves
// them fixed in the body. Optional strengths break a bond for good when
// σmax = -Fn/A + |Mb| R̄/I ≥ σc or τmax = |Fs|/A + |Mt| R̄/J ≥ τc; compression never breaks one.
// The bond model (bond_models.hpp) says whether the modes stay elastic (P&C's bond, the default)
// or yield and harden, each mode's trial increment then returned to its yield limit before the
// strength test.
//
// The engine evaluates bonds like contacts: one pass computes each bond's force once into a
// per-bond result, then each sphere gathers its bonds in a fixed order (after its contacts), so
// results do not depend on the thread count. The whole state lives in BondSet and goes into
// snapshots (snapshot.cpp) so a restart continues bit-identically.
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "simulate/bond_models.hpp"
#include "simulate/state.hpp"

namespace shapepress::simulate {

// What a user states about the bonds of a particle kind (paper Table 1; P&C 2004 Table 1).
struct BondParameters {
  // Stiffness per unit bond area, k̄n and k̄s [N/m³]. With `modulus` > 0 the normal stiffness is
  // instead k̄n = Ē/(ri + rj) per bond (P&C 2004 §2.2.2: the bond's Young's modulus Ē stays the
  // same whatever the sub-sphere size) and k̄s = k̄n · shear_ratio.
  double normal_stiffness = 1.15e6;
  double shear_stiffness = 1.25e6;
  double modulus = 0.0;  // Ē [Pa], 0: use normal_stiffness/shear_stiffness as given
  // Ē as a fraction of the solid modulus of the body's material (its loading_modulus, else its
  // Young's modulus), resolved into `modulus` by the config reader: the bonds of a body
  // calibrated against its own FEM at one modulus follow the material's (docs/models.md, "One
  // material"). 0: Ē (or k̄n, k̄s) stated.
  double modulus_fraction = 0.0;
  double shear_ratio = 1.0;        // k̄s/k̄n when `modulus` is used
  double radius_multiplier = 1.0;  // λ̄
  double tensile_strength = std::numeric_limits<double>::infinity();  // σc [Pa]
  double shear_strength = std::numeric_limits<double>::infinity();    // τc [Pa]
  // Viscous damping of every bond mode as a fraction of the critical damping of the pair,
  // c = 2 ζ √(k m*) (rotational: √(k I*)). P&C 2004 use local damping instead; a bond damper
  // acts on relative motion only, so it does not slow a rigid-body motion of the particle.
  double damping_ratio = 0.0;
  // Whether bonded sub-spheres that overlap also interact through the contact law (P&C 2004:
  // the parallel bond acts in parallel with the contact; the paper's §2.3 reads "bonded model for
  // non-contacting particles, Hertz–Mindlin for contacting ones": both, so true).
  bool contact_when_bonded = true;
  // The constitutive model of every bond, with its parameters (bond_models.hpp).
  BondModelChoice model = ElasticBond{};
  void check() const;  // InputError naming the bad field
};

// The bonds of a run, structure of arrays, sorted by (first, second), first < second.
struct BondSet {
  std::vector<std::int32_t> first, second;
  // Constants per bond.
  std::vector<double> radius;            // R̄ [m]
  std::vector<double> normal_spring;     // k̄n A [N/m]
  std::vector<double> shear_spring;      // k̄s A [N/m]
  std::vector<double> twist_spring;      // k̄s J [N m/rad]
  std::vector<double> bend_spring;       // k̄n I [N m/rad]
  std::vector<double> tensile_strength;  // σc [Pa], +inf: unbreakable
  std::vector<double> shear_strength;    // τc [Pa]
  std::vector<double> damping_ratio;     // ζ
  // History per bond (saved in snapshots), one array per component: the bond loop's blocks read
  // and write it in place, several bonds per instruction. Each array starts at its own offset in
  // a page (SphereArray): the loop streams some thirty of them at once.
  struct History {
    SphereArray<double> length;        // centre distance at the last evaluation [m]
    SphereArray<double> normal_force;  // Fn on `second` along n (i→j), > 0 compressive [N]
    Vec3Array shear_force;             // Fs on `second` [N], world frame
    SphereArray<double> twist_moment;  // Mt on `second` along n [N m]
    Vec3Array bend_moment;             // Mb on `second` [N m], world frame
    // The bond model's history, field k of its history_fields in model_fields[k] (one per mode:
    // normal, shear, twist, bending), zeros for a model without history.
    std::array<SphereArray<double>, bond_model_history_size> model_fields;
    std::size_t size() const { return length.size(); }
    void resize(std::size_t n);  // new bonds at rest, of length 0
    friend bool operator==(const History&, const History&) = default;
    // One bond's history as a record, for reading.
    struct Record {
      double length, normal_force, shear_force[3], twist_moment, bend_moment[3];
    };
    Record at(std::size_t b) const {
      return {length[b],
              normal_force[b],
              {shear_force.x[b], shear_force.y[b], shear_force.z[b]},
              twist_moment[b],
              {bend_moment.x[b], bend_moment.y[b], bend_moment.z[b]}};
    }
  };
  History history;
  std::vector<std::uint8_t> intact;
  bool contact_when_bonded = true;
  BondModelChoice model = ElasticBond{};  // one model for every bond of the run

  // Results of the last evaluation (not saved: recomputed from the state on restart), one array
  // per component as the history.
  struct Results {
    Vec3Array force;  // on second (first gets the negative)
    // The torque on each end, [0] first, [1] second: the gather picks it by the end's bit.
    std::array<Vec3Array, 2> torque;
    // (x_second - x_first) · force, nearest image: each end's Love–Weber term is its share of it
    // (forces.cpp), so the gather does not recompute the separation per bond end.
    SphereArray<double> separation_force;
    void resize(std::size_t n);  // zeros
    // One bond's result as a record, for reading.
    struct Record {
      double force[3], torque_first[3], torque_second[3], separation_force;
    };
    Record at(std::size_t b) const {
      const Vec3Array &first = torque[0], &second = torque[1];
      return {{force.x[b], force.y[b], force.z[b]},
              {first.x[b], first.y[b], first.z[b]},
              {second.x[b], second.y[b], second.z[b]},
              separation_force[b]};
    }
  };
  Results result;
  // What the bond loop reads per bond besides the ends (derived by index(), not saved): each
  // end's share of the centre distance up to the bond centre, [0] ri/(ri + rj) and [1]
  // rj/(ri + rj) (so the arms cost a multiplication), and per mode (normal, shear, twist,
  // bending) the spring and the damper coefficient 2ζ√(k m*) (√(k I*) for the turns); for a
  // yielding model, per mode its limit at κ = 0 (ElasticPlasticBond::yield_limits; empty
  // otherwise).
  struct Constants {
    std::array<SphereArray<double>, 2> arm;
    std::array<SphereArray<double>, 4> spring, damping;
    std::array<SphereArray<double>, 4> yield_limit;
  };
  Constants constants;
  bool breakable = false;  // whether any bond can break (skips the strength test)
  bool yields = false;     // whether the model's modes yield (bond_model_yields)
  // H of a yielding model (derived by index()): a mode's plastic modulus is H times its spring.
  double hardening_ratio = 0.0;
  // Whether every bond has dampers, and whether some have and some not (the bond loop's blocks
  // take one kind at a time).
  bool damped = false, damping_mix = false;
  // Per-sphere gather lists (CSR), as PairList: entries 2·bond + (0 first, 1 second) in
  // increasing bond index.
  std::vector<std::int32_t> gather_offset;
  std::vector<std::int32_t> gather;

  std::size_t size() const { return first.size(); }
  bool empty() const { return first.empty(); }
  std::int64_t intact_count() const;
  // Fills gather_offset/gather for the spheres of `state`, `constants` (the dampers from the
  // masses and inertias), and sizes `result`. Call it again after changing a constant.
  void index(const SphereState& state);
};

// Bonds by paper Eq. 10, |xi - xj| < (ri + rj) m_b, between sub-spheres of the same body only,
// with every sub-sphere of a body of more than one sphere bonded to at least one other:
// InputError naming the particle (`body_names[body]` when given, else "particle <body id>") and
// the sub-sphere otherwise, and when m_b ≤ 1 (touching spheres would not bond).
BondSet create_bonds(const SphereState& state, double bond_multiplier,
                     const BondParameters& parameters,
                     const std::vector<std::string>& body_names = {});

// Bonds between the given pairs (i < j, sorted), as a packing stores them: each carries the
// normal force k̄n A (rest length − centre distance) of its stored rest length (> 0 compressive),
// no shear and no moments. InputError naming the pair when an index is out of range, a pair is
// not i < j or not sorted, or a rest length is not > 0.
BondSet bonds_from_pairs(const SphereState& state,
                         std::span<const std::array<std::int32_t, 2>> pairs,
                         std::span<const double> rest_length, const BondParameters& parameters);

// Below this many bonds the bond loop runs on one thread. The threshold is the engine's
// (engine.hpp): on a loaded machine a parallel region's barrier can cost a scheduler slice, far
// more than the bonds of a plate rig (docs/models.md, "Where the time goes": threads). Results
// are the same either way.
inline constexpr std::int64_t parallel_min_bonds = 4096;

// One evaluation of every intact bond (parallel over bonds, each written once). `motion` holds
// per sphere the predicted end-of-step v, ω (8 doubles per sphere, as Engine::pair_forces packs
// it) for the dampers; the spring increments use the half-step velocities in `state`, which are
// what moved the spheres over the step. Bonds that reach a strength break here.
void compute_bond_forces(BondSet& bonds, const SphereState& state, const double* motion,
                         const Box& box, double dt, bool first_evaluation);

// What the gather reads of a BondSet's results, its arrays' addresses taken once per gather
// rather than once per sphere.
struct BondGather {
  const std::int32_t* offset;
  const std::int32_t* entries;
  const double* force[3];
  const double* torque[2][3];  // [end][axis], end 0 first, 1 second
  const double* arm[2];        // [end]: the end's share of the separation (Love–Weber)
  const double* separation_force;
  explicit BondGather(const BondSet& bonds)
      : offset(bonds.gather_offset.data()),
        entries(bonds.gather.data()),
        force{bonds.result.force.x.data(), bonds.result.force.y.data(),
              bonds.result.force.z.data()},
        torque{{bonds.result.torque[0].x.data(), bonds.result.torque[0].y.data(),
                bonds.result.torque[0].z.data()},
               {bonds.result.torque[1].x.data(), bonds.result.torque[1].y.data(),
                bonds.result.torque[1].z.data()}},
        arm{bonds.constants.arm[0].data(), bonds.constants.arm[1].data()},
        separation_force(bonds.result.separation_force.data()) {}
};

// Adds the bond forces and torques of sphere i (its bonds in fixed order). A broken bond's
// result is zero (compute_bond_forces clears it), so it adds nothing and needs no test. The end
// picks the force's sign (-F on `first`; a product by -1 is exact, so f + (-1)·F is f - F) and
// the torque's array, without a branch: which end a sphere is flips from bond to bond.
// With `with_arm`, also adds Σ share × Fsep to `arm_force`: the bonds' part of the sub-sphere's
// Love–Weber stress (bond_arm_force's sum, in the same order).
template <bool with_arm = false>
inline void gather_bond_forces(const BondGather& g, std::int64_t i, double f[3], double t[3],
                               double* arm_force = nullptr) {
  constexpr double sign_of_end[2] = {-1.0, 1.0};
  double arm_sum = 0.0;
  for (std::int32_t e = g.offset[i]; e < g.offset[i + 1]; ++e) {
    const std::int32_t entry = g.entries[e];
    const std::int32_t b = entry >> 1, end = entry & 1;
    const double sign = sign_of_end[end];
    f[0] += sign * g.force[0][b], f[1] += sign * g.force[1][b], f[2] += sign * g.force[2][b];
    t[0] += g.torque[end][0][b], t[1] += g.torque[end][1][b], t[2] += g.torque[end][2][b];
    if constexpr (with_arm) arm_sum += g.arm[end][b] * g.separation_force[b];
  }
  if constexpr (with_arm) *arm_force += arm_sum;
}

// Bond b's damper coefficients per mode (normal, shear, twist, bending): 2ζ√(k m*) with m* the
// pair's reduced mass, 2ζ√(k I*) for the turns; zeros without dampers. What the bond loop's
// dampers apply (BondSet::index) and what the stability estimate takes (bond_spectrum.cpp).
std::array<double, 4> bond_damper_coefficients(const BondSet& bonds, std::size_t b,
                                               const SphereState& state);

// Elastic energy held by the intact bonds, Σ Fn²/2kn + |Fs|²/2ks + Mt²/2kt + |Mb|²/2kb [J].
double bond_elastic_energy(const BondSet& bonds);

// Bound on the shortest oscillation period of the bonded network (translation and rotation of
// the sub-spheres): Gershgorin's bound on the largest eigenvalue ω² of the mass-normalised bond
// stiffness matrix, shortened by √(1+ζ²) − ζ for the bond dampers. Returns 2π/ω_max [s], +inf
// without bonds. The time step takes a fraction of
// it (timestep.hpp), as it takes a fraction of the Rayleigh time for contacts.
double bond_oscillation_period(const BondSet& bonds, const SphereState& state);

// The bonded network's highest angular frequency ω_max [rad/s]: the square root of the largest
// eigenvalue of M^-1/2 K M^-1/2, K the intact bonds' stiffness linearised about the present state
// (each bond a normal, shear, twist and bending spring, the shear acting at the bond's centre, as
// advance_springs integrates them), by Lanczos iteration from a fixed start vector; the largest
// Ritz value approaches it from below. Gershgorin's bound (bond_oscillation_period) is a bound on
// the same number and at least as large. 0 without intact bonds. (bond_spectrum.cpp)
double bond_top_frequency(const BondSet& bonds, const SphereState& state, const Box& box);

// The largest damping rate of the bond dampers [1/s]: the largest eigenvalue of M^-1/2 C M^-1/2,
// C the dampers' matrix (the springs' structure with the coefficients 2ζ√(k m*)), by the same
// iteration. 0 without dampers.
double bond_top_damping_rate(const BondSet& bonds, const SphereState& state, const Box& box);

// The margin on the estimated stability limit: the Ritz values are lower bounds, and a loaded
// bed's contacts add their stiffness to the same sub-spheres' modes.
inline constexpr double bond_stability_margin = 0.9;

// The longest step velocity Verlet takes stably through the bonds with the engine's dampers:
// bond_stability_margin × 2(√(γ² + ω²) − γ)/ω², ω of bond_top_frequency and γ of
// bond_top_damping_rate (2/ω undamped, 1/γ for dampers alone; bond_spectrum.cpp says why).
// +inf without intact bonds.
double bond_stability_step(const BondSet& bonds, const SphereState& state, const Box& box);

}  // namespace shapepress::simulate
