#pragma once
// The single-particle rig: one particle between two plates, the top plate approaching at a
// prescribed speed (docs/stages.md, "plate"). The particle is one Hertz sphere (classical
// DEM), a bonded multi-sphere agglomerate (BMS, paper §3.1) or a rigid clump of overlapping
// sub-spheres (CMS, paper §3.3). Quasi-static when the speed is
// small against the particle's wave speed: every row carries the kinetic energy and the work
// the plates did, so a run shows that it was.
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>
#include "analysis/curves.hpp"
#include "scenarios/namespaces.hpp"

#include "simulate/bonds.hpp"
#include "simulate/clumps.hpp"
#include "simulate/engine.hpp"
#include "simulate/materials.hpp"
#include "simulate/snapshot.hpp"
#include "simulate/state.hpp"
#include "simulate/work_count.hpp"

namespace shapepress::scenarios {

struct PlateSetup {
  double radius = 0.0;  // m, of the sphere (of the shape a BMS particle fills)
  int sphere_material = 0;
  int plate_material = 0;
  double speed = 0.0;  // m/s, top plate approach speed
  // Deformation (approach / 2R) over which the top plate speeds up from rest to `speed`, with
  // v = speed sin²(π t / 2 t_ramp) (no jump in velocity or acceleration at the touch, so the
  // first sub-spheres are not knocked in and no wave is launched); 0: full speed at the touch.
  double ramp = 0.0;
  // Both plates approach, each at speed/2 (same approach rate, so the same cost): the particle's
  // centre stays at rest instead of being carried at speed/2, which takes the rigid-body share
  // out of the kinetic energy and halves every plate–sub-sphere impact speed.
  bool symmetric = false;
  // Approach speed at max_deformation: after the ramp the speed rises linearly in deformation
  // from `speed` to this. The work done grows as about Δ^2.5 while the kinetic energy of the
  // approach goes as v², so a speed that rises with Δ keeps KE / work as small as a slow start
  // needs, at a fraction of the steps. 0: `speed` throughout.
  double final_speed = 0.0;
  double max_deformation = 0.01;  // total approach / 2R at the end
  int records = 50;               // rows, evenly spaced in approach
  // After max_deformation the plates go back to where they first touched, at the loading's
  // speed for the same approach (after its sin² ramp, from rest at the turn), and `records` more
  // rows are recorded, evenly spaced in approach down to 0: the unloading curve, and the
  // approach at which the particle lets go of the plates (what stays of its deformation).
  bool unload = false;
  // Copies of the particle pressed one on another along the axis, each its own body (its own
  // bonds, its own body radius): the contact between two particles measured as what the stack
  // adds to `stack` times one particle's compliance. The deformation is the approach over the
  // stack's height 2R × stack.
  int stack = 1;
  // Rows of the whole run: the loading's, and as many again when unloading.
  int total_records() const { return unload ? 2 * records : records; }
  // The height the deformation is counted on: 2R of each particle of the stack.
  double diameter() const { return 2.0 * radius * stack; }
};

struct PlateRow {
  double time = 0.0;          // s
  double deformation = 0.0;   // Δ/(2R), R of the sphere the particle stands for
  double approach = 0.0;      // Δ, m: decrease of the plate gap from the first touch
  double top_force = 0.0;     // N, compressive
  double bottom_force = 0.0;  // N
  double hertz_force = 0.0;  // N, (√2/3) E* √R Δ^{3/2}, E* of the sphere–plate pair (a stack:
                             // hertz_stack_force)
  std::int64_t contacts = 0;  // sphere–sphere plus sphere–wall contacts
  std::int64_t intact_bonds = 0;
  double kinetic_energy = 0.0;  // J
  double work = 0.0;            // J, done by the plates since the start
  double cpu_seconds = 0.0;     // process CPU time since the run started (all threads)
  double wall_seconds = 0.0;    // elapsed time since the run started
  WorkCount work_count;         // counted over the steps since the run started
  // An ensemble of fills ([bms] fills): the forces above are the fills' means, these the top
  // force's sample standard deviation, least and largest over the fills (0 for one fill).
  double top_force_sd = 0.0, top_force_min = 0.0, top_force_max = 0.0;
};

// What is pressed: sub-spheres (one for classical DEM) and their bonds (BMS) or the rigid clump
// they form (CMS), in any frame; run_plate puts the plates on its lowest and highest points.
struct PlateParticle {
  SphereState spheres;
  BondSet bonds;
  ClumpSet clumps;
};

// `stack` copies of one particle's sub-spheres (bodies 0 … stack − 1), each the one below moved
// straight up to where it first touches it (dropped onto it), every sub-sphere with the body
// radius `body_radius` when there are several copies (a contact between two copies is one
// between two particles, `contact_radius = "body"`).
SphereState stacked(const SphereState& one, int stack, double body_radius);

// Hertz between a sphere and two identical plates: each contact carries Δ/2 (models.md).
double hertz_plate_force(double effective_modulus, double radius, double approach);

// Hertz for `stack` equal spheres one on another between two plates: each plate contact and each
// of the stack − 1 sphere–sphere contacts (R* = R/2) carries the same force F, so the approach is
// the sum of their overlaps, each δ = (9 F² / (16 E*² R*))^{1/3}, and F follows in closed form.
double hertz_stack_force(double plate_modulus, double pair_modulus, double radius, int stack,
                         double approach);

// The particle's smallest sub-sphere radius: the rig's Verlet skin is 0.1 of it unless a config
// gives one.
double smallest_radius(const SphereState& spheres);

// The particle's lowest and highest points (z), where the plates first touch it. At least one
// sphere.
struct VerticalExtent {
  double low = 0.0, high = 0.0;
};
VerticalExtent vertical_extent(const SphereState& spheres);

// A single sphere of setup.radius and setup.sphere_material. `engine` is the engine's settings
// as they are (time step, skin, overlap check, local damping), but for its divergence check every
// 1000 steps (the rig's loading is slow).
std::vector<PlateRow> run_plate(const MaterialTable& materials, const PlateSetup& setup,
                                const EngineSettings& engine);
// How far a run has come: its rows so far, the CPU and wall seconds it spent and the work it
// counted (a resumed run's cpu_s and wall_s columns and its count go on from those of the
// attempts before).
struct PlateProgress {
  std::vector<PlateRow> rows;
  double cpu_seconds = 0.0, wall_seconds = 0.0;
  WorkCount work_count;
};

// A run continued from a checkpoint: the engine as it was saved and its progress. The particle
// given to run_plate is still made, from the same config, for where the plates first touched.
struct PlateResumePoint {
  LoadedSnapshot snapshot;
  PlateProgress progress;
};

// `after_step` (optional) is called after every step with the engine and a function giving the
// progress (for a checkpoint); false stops the run there (a signal): run_plate then returns
// fewer than setup.total_records() rows.
struct PlateHooks {
  std::optional<PlateResumePoint> resume;
  std::function<bool(const Engine&, const std::function<PlateProgress()>&)> after_step;
};

// What an unloaded run (setup.unload) left, by the top plate's force
// (analysis::unloading_residual); rows after the first `records` are the unloading's.
using PlateUnloading = analysis::UnloadingResidual;
PlateUnloading plate_unloading(const std::vector<PlateRow>& rows, int records);

// Any particle. `row` (optional) sees every row as it is recorded, with the engine.
std::vector<PlateRow> run_plate(const MaterialTable& materials, const PlateSetup& setup,
                                const EngineSettings& engine, PlateParticle particle,
                                const std::function<void(const PlateRow&, const Engine&)>& row = {},
                                PlateHooks hooks = {});

}  // namespace shapepress::scenarios
