#pragma once
// Where every bed is made. The `pack` stage's algorithm: a bed of bodies (spheres, BMS, CMS
// templates of `fill`) drawn from a size distribution, turned uniformly on SO(3), inserted
// without overlap into a periodic x/y box above the die floor, settled under gravity, optionally
// pre-compressed by the punch to a solid fraction and released, and measured (body_packing.hpp
// PackMeasures), each phase a function run by one phase loop. `compact`'s pour of a config's
// [generate] and [clumps] is settled by the same loop for a fixed time (settle_for_time).
//
// During pack every body moves as one rigid body (the engine's ClumpSet; a plain sphere as a
// sphere) with the mass and inertia of its template's sub-spheres scaled (volume × s³, inertia
// × s⁵): sub-spheres of one body never interact, contacts between bodies are Hertz–Mindlin of
// the [material] section. The bonds of BMS bodies carry no force in pack; they are written at
// rest in the packed geometry (rest length = the distance then), so `compact` starts from
// force-free bonds. This is the LIGGGHTS multisphere way of filling a die with BMS particles and
// costs a rigid-body step per body instead of a bonded network's stiff step.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "packing/body_packing.hpp"
#include "packing/clump_packing.hpp"
#include "packing/packing.hpp"
#include "packing/solid_volume.hpp"
#include "simulate/engine.hpp"
#include "simulate/snapshot.hpp"

namespace shapepress::packing {

// How a body's template is chosen: by number (each body independently, P(t) ∝ weight) or by
// volume (each body takes the template whose share of the drawn volume lags furthest behind its
// weight, so the volume shares match the weights, not only on average).
enum class TemplateWeighting { number, volume };

// How the settle starts: the pour (insert_bodies: bounding spheres apart in a region several
// times the bed's height) falls under gravity to rest; a deposit lays the poured bodies down
// geometrically first (deposition.hpp: dropped to contact and shaken lower, without overlap), so
// the settle starts near the settled bed and has little to fall.
enum class Insertion { pour, deposit };

struct TemplateChoice {
  std::string name;  // "sphere", "bms/<name>", "cms/<name>"
  double weight = 1.0;
};

// How far the sub-spheres of a BMS template may overlap: a bonded template's sub-spheres touch
// (fill's random packings jam them to contact), and an overlap counted twice in mass and in the
// contact law is no BMS particle. Relative to the smaller radius of the pair.
inline constexpr double bms_overlap_tolerance = 0.02;

struct PackRequest {
  std::vector<TemplateChoice> templates;
  TemplateWeighting weighting = TemplateWeighting::number;
  std::int64_t count = 0;                         // bodies; 0: draw until target_mass
  std::optional<double> target_mass;              // kg of body volume × density
  SizeQuantiles sizes;                            // of the volume-equivalent diameter
  double diameter_min = 0.0, diameter_max = 0.0;  // m, truncation
  double box_x = 1e-3, box_y = 1e-3;              // m, periodic cross-section
  double floor = 0.0;                             // m, the die floor's z
  std::uint64_t seed = 1;

  // Material of the bodies during pack (Hertz–Mindlin) and of the die walls.
  double density = 1500.0;      // kg/m³
  double youngs_modulus = 5e6;  // Pa, reduced from the solid's for a larger time step
  double poisson_ratio = 0.3;
  double restitution = 0.1;    // low: a clump's contacts damp with M/n (clumps.hpp)
  double friction = 0.3;       // body–body sliding
  double wall_friction = 0.3;  // body–wall sliding
  double rolling_friction = 0.0;

  // Insertion and settle.
  Insertion insertion = Insertion::pour;
  double insertion_fraction = 0.2;  // of the bounding spheres in the insertion region
  int attempts_per_body = 2000;
  double gravity = 9.81;               // m/s², down
  double kinetic_energy_ratio = 1e-5;  // at rest: KE below this × Σ m g d of the bodies
  // Viscous drag on every body's velocity and spin, v → v e^(-dt/τ): a clump's contacts damp
  // with M/n (clumps.hpp), too little to bring a bed to rest; the drag is what LIGGGHTS users add
  // to fill a die. It slows the fall to ≈ g τ, so it is kept long against the contacts' periods.
  double damping_time = 0.01;    // s, τ; 0: none
  double max_settle_time = 0.5;  // s, per phase (settle, press, relax)
  // Mass scaling of pack's dynamics: the bodies settle, are pressed (at punch_speed / √s, the
  // unscaled press's dynamics) and relax at s × density, whose time step is √s longer (both
  // bounds, the clump period and the Rayleigh time, go as √m) and whose overlaps under the
  // bed's own weight are s^(2/3) deeper; a release at the true density then lets those overlaps
  // spring back, so the packing's are the true weight's. The fall and the drag's decay are
  // s-free (gravity, g τ and τ are), so those phases take √s fewer steps.
  double settle_density_scale = 1.0;
  std::optional<double> time_step;  // s, fixed; else time_step_fraction × the engine's bound
  double time_step_fraction = 0.2;

  // Pre-compression: the punch moves down at punch_speed until the solid fraction by the
  // volume solid_fraction_volume names reaches this, then back up and the bed relaxes. The
  // settled and pre-compression fractions of the result are by the same volume.
  SolidVolume solid_fraction_volume = SolidVolume::body;
  std::optional<double> target_solid_fraction;
  double press_friction = 0.0;           // sliding friction of every contact while pressing
  double punch_speed = 0.05;             // m/s
  double solid_fraction_ceiling = 0.74;  // a target above it is refused

  void check() const;  // InputError naming the bad value
};

// The named templates from the templates files: "sphere" (a unit sphere), "bms/<name>",
// "cms/<name>", searched in the files in order. InputError naming the files and the name when
// missing, and for a BMS template whose sub-spheres overlap by more than bms_overlap_tolerance.
std::vector<BodyTemplate> load_body_templates(const std::vector<std::filesystem::path>& files,
                                              const std::vector<TemplateChoice>& choices);
// Every template of `kind` (bms or cms) in a templates file, in the file's order, named as
// load_body_templates names them (compact's [clumps] without a template name). InputError naming
// the file when it holds none.
std::vector<BodyTemplate> load_body_templates(const std::filesystem::path& file, BodyKind kind);
// InputError naming the template and the pair when two sub-spheres overlap beyond the tolerance.
void check_bms_template(const BodyTemplate& shape);

// The x at Q = level of the table's distribution, number-weighted (Q0) or volume-weighted (Q3).
double size_quantile(const SizeTable& table, double level, bool volume_weighted);
// The same of a sample of diameters.
double sample_quantile(std::vector<double> diameters, double level, bool volume_weighted);

// Bodies drawn from the request: template, scale (to a volume-equivalent diameter from the
// size distribution), a uniform orientation, volumes; centres at the origin. Deterministic in
// request.seed. InputError when the truncation leaves no size.
std::vector<PackedBody> draw_bodies(const PackRequest& request,
                                    const std::vector<BodyTemplate>& templates);

// A body's sub-spheres' reach from its centre of mass at scale 1.
double bounding_radius(const BodyTemplate& shape);
// Centres by random sequential insertion of bounding spheres (largest first) in the periodic
// box, the insertion region's height set by request.insertion_fraction; returns the region's
// top. InputError when a body is wider than the box or finds no place.
double insert_bodies(const PackRequest& request, const std::vector<BodyTemplate>& templates,
                     std::vector<PackedBody>& bodies);

// Where a pack run stands between two steps: what a checkpoint keeps beside the engine's
// snapshot, so that a resumed run takes the steps the uninterrupted one takes.
// With settle_density_scale s > 1 the settle, press and relaxation run at s × density and a
// release at the true density ends the run.
enum class PackPhase { settle = 0, press = 1, relax = 2, release = 3 };
struct PackPhaseState {
  PackPhase phase = PackPhase::settle;
  double phase_start = 0.0;     // s, the engine's time when the phase began
  std::int64_t phase_step = 0;  // steps into the phase (the rest test runs every 200th)
  bool settled = true;          // the phases before this one came to rest
  double settled_solid_fraction = 0.0;
  double precompression_solid_fraction = 0.0;
};

struct PackProgress {
  std::function<void(const std::string& phase, double time, double max_time)> update;
  // After every step: a checkpoint may be taken here. Returning false stops the run there (a
  // signal asked for it): PackRun::interrupted.
  std::function<bool(const Engine&, const PackPhaseState&)> after_step;
};

// A checkpoint to continue from: the engine's snapshot and the phase it was taken in.
struct PackResume {
  LoadedSnapshot snapshot;
  PackPhaseState phase;
};

struct PackRun {
  BodyPacking packing;
  double time_step = 0.0;         // s, at the true density (all phases, or the release)
  double settle_time_step = 0.0;  // s, at settle_density_scale × density (settle, press, relax)
  std::int64_t steps = 0;
  bool settled = true;                  // every phase ended below the kinetic-energy threshold
  double settled_solid_fraction = 0.0;  // by body volume after the gravity settle
  double precompression_solid_fraction = 0.0;  // reached by the punch (0: no press)
  double loop_seconds = 0.0;
  std::int64_t loop_steps = 0;  // steps taken in this process (after the checkpoint if resumed)
  bool interrupted = false;     // PackProgress::after_step stopped the run; no packing
};

// Draws, inserts, settles (and presses), and measures. ComputationError on divergence.
// `resume`: continue from a checkpoint of the same request (the bodies are drawn and inserted
// again, deterministically, for their set-up; the engine is the checkpoint's).
PackRun pack(const PackRequest& request, const std::vector<BodyTemplate>& templates,
             const PackProgress& progress = {}, std::optional<PackResume> resume = {});

// compact's pour: its [generate] spheres inserted at random (insert_random_spheres, numbered in
// cell order) or the spheres it was given, and its [clumps] inserted around them (insert_clumps),
// all of one material; settle_for_time then settles it.
struct Pour {
  Box box;
  std::optional<InsertionRequest> spheres;  // absent: the given spheres
  std::optional<ClumpInsertion> clumps;
  double density = 0.0;  // kg/m³
  int material = 0;
};
SphereState pour(const Pour& request, const SphereList& given, ClumpSet& clumps);

// compact's pour settled by pack's settle phase for a fixed time with the compaction's
// materials: no rest test and no drag, as the config's settle_time is part of the bed's recipe
// (its solid fraction and so the compaction's curve follow it), where pack's own settle runs to
// rest.
struct TimedSettle {
  Box box;
  std::vector<PlaneWall> walls;  // the die floor and the parked punch
  EngineSettings settings;       // gravity zero: 9.81 m/s² down
  double settle_time = 0.2;      // s
  // Sliding and rolling friction of every interaction while settling (a denser fill, as DEM
  // fills are usually made to reach a target density); absent: the interactions' own.
  std::optional<double> friction;
};

// Checkpoints of a timed settle (docs/stages.md, "Checkpoints and --resume"): `after_step` after
// every step; returning false stops the settle there (a signal asked for it). `resume`: a
// snapshot of the same settle's engine to continue from.
struct SettleCheckpoints {
  std::function<bool(const Engine&)> after_step;
  std::optional<LoadedSnapshot> resume;
};

// The spheres and clumps after ceil(settle_time / time step) steps, with no velocity and no
// angular momentum; none when checkpoints.after_step stopped the settle.
std::optional<SphereState> settle_for_time(SphereState state, ClumpSet& clumps,
                                           std::vector<Material> materials,
                                           std::vector<Interaction> interactions,
                                           const TimedSettle& request,
                                           SettleCheckpoints checkpoints = {});

// The highest point of any sphere, at least `floor`.
double bed_top(const SphereState& state, double floor);

// The measures of a placed packing (place_bodies done): solid fractions, bed height,
// body–body contacts, sizes of the weighting against `target`, ⟨P2⟩ of the long axes, overlaps.
PackMeasures measure_packing(const BodyPacking& packing, const SizeTable& target,
                             bool volume_weighted);

}  // namespace shapepress::packing
