#pragma once
// The compaction scenario: a box of spheres between the fixed bottom plate and the punch, the
// punch driven by a PunchProgram, a PunchRecord every N steps. Output goes through hooks, so
// this file holds the physics loop and no I/O (the CLI writes punch.csv and snapshots).
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>
#include "packing/solid_volume.hpp"
#include "scenarios/namespaces.hpp"

#include "scenarios/punch.hpp"
#include "simulate/engine.hpp"
#include "simulate/snapshot.hpp"
#include "simulate/timestep.hpp"
#include "simulate/work_count.hpp"

namespace shapepress::scenarios {

// What the inertial number reads of the bed: its particles' mean size and mass-scaled density.
struct InertialScale {
  double diameter = 0.0;  // m, the mean volume-equivalent diameter of the bodies
  double density = 0.0;   // kg/m³, the particles' density × run.density_scale
};

struct CompactionSetup {
  PunchProgram program;
  double die_area = 0.0;  // m², the periodic cross-section
  // H0 of the strain is PunchState::reference_gap (saved with the punch for a restart): the gap
  // when loading starts, the loose fill height, or the gap at which the bed's solid fraction
  // would be reference_solid_fraction, H0 = V / (A φ0), so that beds of every kind count their
  // strain from one density (punch.strain_reference).
  enum class StrainReference { start, fill, solid_fraction };
  StrainReference strain_reference = StrainReference::start;
  double reference_solid_fraction = 0.59;
  // Which volume the bed's solid fraction is stated by (punch.solid_fraction_volume): the
  // bodies' in the bed or their shapes' (meshes'). One and the same for spheres and clumps; for
  // BMS bodies the two differ by the fill's surface offset (docs/models.md, "A body's volume").
  packing::SolidVolume solid_fraction_volume = packing::SolidVolume::body;
  // m³: Σ of the volumes solid_fraction_volume names: the solid fraction of punch.csv, of its
  // target, Heckel's and the ceiling's.
  double solid_volume = 0.0;
  // m³: Σ of the bodies' volumes in the bed (a packing from `pack`: BodyTemplate::body_volume),
  // else Σ sphere volumes (clumps: their unions').
  double body_volume = 0.0;
  // m³: Σ of the bodies' shape (mesh) volumes; body_volume for spheres and clumps.
  // punch.csv's solid_fraction_shape.
  double shape_volume = 0.0;
  // m³: Σ sub-sphere volumes (clumps: unions); below solid_volume for BMS bodies by their
  // sub-spheres' packing fraction. punch.csv's solid_fraction_spheres.
  double sphere_volume = 0.0;
  double max_solid_fraction = 0.95;  // the ceiling behind program.min_gap
  // The target gap would pass the ceiling: loading stops at program.min_gap instead.
  bool ceiling_limits_load = false;
  std::int64_t max_steps = 0;  // total step index to stop at; 0: when the program is done
  std::int64_t record_every = 100;
  std::int64_t snapshot_every = 0;  // 0: none
  InertialScale inertial;           // of the bed, for the quasi-static check
  // The step the run takes and the bounds it was chosen from, kept in its checkpoints: a bonded
  // bed's bound reads the bonds' current lengths, so a resumed run recomputing it would step
  // differently from the uninterrupted one.
  TimeStepChoice time_step;
  std::size_t bottom_wall = 0;
  std::size_t punch_wall = 1;
};

// "start", "fill", "solid_fraction": punch.strain_reference's values, run.json's.
std::string strain_reference_name(CompactionSetup::StrainReference reference);
// What H0 is, for punch.csv's comment lines.
std::string strain_reference_comment(const CompactionSetup& setup);

// One row of punch.csv (columns: docs/stages.md, "compact").
struct PunchRecord {
  std::int64_t step = 0;
  double time = 0.0;                    // s
  double gap = 0.0;                     // m, punch - bottom
  double strain = 0.0;                  // (H0 - H)/H0
  double top_force = 0.0;               // N, compressive load on the punch
  double bottom_force = 0.0;            // N, on the bottom plate
  double stress = 0.0;                  // Pa, top force / die area
  double solid_fraction = 0.0;          // solid_volume / (die area × gap)
  double solid_fraction_spheres = 0.0;  // sphere_volume / (die area × gap)
  double solid_fraction_shape = 0.0;    // shape_volume / (die area × gap)
  PunchPhase phase = PunchPhase::load;
  double kinetic_energy = 0.0;  // J, translational + rotational
  double punch_work = 0.0;      // J, ∫ F dz done by the punch on the bed since the run began
  std::int64_t sphere_contacts = 0;
  std::int64_t wall_contacts = 0;
  double contacts_per_particle = 0.0;  // 2 × sphere–sphere contacts / N (LIGGGHTS contact/atom)
  std::int64_t intact_bonds = 0;       // BMS bonds not broken
};

// The columns of punch.csv, each with its unit, and one record as its row.
std::vector<std::string> punch_csv_columns();
std::vector<double> punch_csv_row(const PunchRecord& r);

// What a run has produced so far beyond the engine and the punch: every record (the rows of
// punch.csv at full precision, which the summary is judged over) and the steps taken. A
// checkpoint keeps it, so a resumed run ends with the summary of the uninterrupted one.
struct CompactionHistory {
  std::vector<PunchRecord> records;
  std::int64_t steps = 0;
  WorkCount work_count;  // of the steps taken (simulate/work_count.hpp)
  // Wall seconds of the stepping loop before this process's loop began (a resumed checkpoint's;
  // NaN when a checkpoint older than this count does not say), and when it began: a checkpoint
  // states their sum, so a resumed run states the whole run's wall time.
  double loop_seconds = 0.0;
  std::chrono::steady_clock::time_point loop_started{};
};

struct CompactionHooks {
  std::function<void(const PunchRecord&)> record;
  std::function<void(const Engine&, const PunchState&)> snapshot;
  std::function<void(std::int64_t step)> progress;
  // After every step, once its record and snapshot are out: a checkpoint may be taken here.
  // Returning false stops the run there (a signal asked for it); the summary says so.
  std::function<bool(const Engine&, const PunchState&, const CompactionHistory&)> after_step;
};

// Whether one phase of a compaction (loading, or unloading) was quasi-static: the bed's kinetic
// energy small against the work of the punch, the top and bottom forces equal (no stress wave or
// inertia between them), and the inertial number I = ε̇ d √(ρ/σ) small (GDR MiDi 2004: the
// time a particle takes to move by its size under the stress, against the time the punch takes
// to strain the bed by one), judged over the phase's records whose stress is at least a tenth of
// the peak, where the forces carry the curve. Unloading's work is the punch's at its start (what
// the bed can give back); ρ is the mass-scaled density, so mass scaling raises I as √s.
struct PhaseQuasiStatic {
  double max_kinetic_to_work = 0.0;   // largest kinetic energy / punch work
  double mean_force_imbalance = 0.0;  // mean |top - bottom| / top
  double max_force_imbalance = 0.0;   // largest |top - bottom| / top
  double max_inertial_number = 0.0;   // largest ε̇ d √(ρ/σ)
  std::int64_t records = 0;           // records judged
  bool quasi_static() const {
    return max_kinetic_to_work <= max_kinetic_energy_ratio &&
           mean_force_imbalance <= max_mean_force_imbalance &&
           max_inertial_number <= max_inertial_number_limit;
  }
  // 1 % of the work held as motion, 5 % between the plates on average, I ≤ 1e-3 (the usual
  // quasi-static limit of dense granular flow): beyond them the curve carries the bed's inertia,
  // not its stiffness (docs/models.md, "Quasi-static").
  static constexpr double max_kinetic_energy_ratio = 0.01;
  static constexpr double max_mean_force_imbalance = 0.05;
  static constexpr double max_inertial_number_limit = 1e-3;
};

struct QuasiStaticCheck : PhaseQuasiStatic {  // the loading's
  PhaseQuasiStatic unload;                    // records 0: not unloaded
  bool quasi_static() const {
    return PhaseQuasiStatic::quasi_static() && (unload.records == 0 || unload.quasi_static());
  }
};

struct CompactionSummary {
  PunchRecord first;  // where loading starts (after the relaxation)
  PunchRecord last;
  double max_stress = 0.0;
  QuasiStaticCheck quasi_static;
  std::int64_t steps = 0;           // steps taken, those before a resumed checkpoint included
  WorkCount work_count;             // counted over those steps: the run's deterministic cost
  double loop_seconds = 0.0;        // wall time of the stepping loop (after the checkpoint)
  double total_loop_seconds = 0.0;  // the run's, before the checkpoint included (NaN: unknown)
  std::int64_t loop_steps = 0;      // steps taken in it (after the checkpoint when resumed)
  bool interrupted = false;         // CompactionHooks::after_step stopped the run
};

// What a compaction snapshot keeps beyond the engine: the punch controller's state and the bed's
// body, shape and sub-sphere volumes (a bed of bodies cannot recompute them from its spheres).
ScenarioState compaction_scenario_state(const PunchState& punch, const CompactionSetup& setup);

PunchRecord punch_record(const Engine& engine, const CompactionSetup& setup,
                         const PunchState& punch);

// The check over a run's records, loading and unloading each on their own; the strain rate of a
// record is the gap's rate of change since the one before it over the gap.
QuasiStaticCheck quasi_static_check(const std::vector<PunchRecord>& records,
                                    const InertialScale& scale = {});

// Steps until the program is done or max_steps is reached. Throws ComputationError on
// divergence (from Engine::step). `resumed`: the history a checkpoint kept, the engine and punch
// restored from the same checkpoint; its records are not emitted again.
CompactionSummary run_compaction(Engine& engine, const CompactionSetup& setup, PunchState& punch,
                                 const CompactionHooks& hooks, CompactionHistory resumed = {});

}  // namespace shapepress::scenarios
