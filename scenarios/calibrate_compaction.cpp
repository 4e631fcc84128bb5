#include "scenarios/calibrate_compaction.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "analysis/compaction.hpp"
#include "analysis/optimize.hpp"
#include "common/error.hpp"
#include "common/job_pool.hpp"

namespace shapepress::scenarios {

std::vector<std::string> compaction_parameter_names() {
  return {"loading_stiffness",      "loading_modulus",    "youngs_modulus",  "plasticity_ratio",
          "multicontact_prefactor", "normal_stiffness",   "shear_stiffness", "modulus",
          "yield_stress",           "shear_yield_stress", "hardening_ratio"};
}

namespace {

bool is_law_parameter(const std::string& name) {
  return name == "loading_stiffness" || name == "plasticity_ratio" ||
         name == "multicontact_prefactor";
}

// The multi-contact laws of the particles' interactions (with each other first, then with the
// walls): the paper states one k1, λp and β for the powder, so a fit moves them together.
std::vector<MulticontactLaw*> particle_laws(CompactConfig& c, const std::string& name) {
  std::vector<MulticontactLaw*> laws;
  for (Interaction& in : c.materials.interactions) {
    if (in.first != c.particle_material && in.second != c.particle_material) continue;
    if (auto* law = std::get_if<MulticontactLaw>(&in.normal_law)) {
      if (in.first == in.second)
        laws.insert(laws.begin(), law);
      else
        laws.push_back(law);
    }
  }
  if (laws.empty())
    throw InputError(
        fmt::format("calibrate: '{}' needs an [[interaction]] of material '{}' with normal_law = "
                    "\"multicontact\"",
                    name, c.particle_material));
  return laws;
}

Material& particle_material(CompactConfig& c) {
  for (Material& m : c.materials.materials)
    if (m.name == c.particle_material) return m;
  throw InputError("calibrate: unknown particle material '" + c.particle_material + "'");
}

BondParameters& bond_of(CompactConfig& c, const std::string& name) {
  if (!c.bond)
    throw InputError("calibrate: '" + name + "' needs a [bond] table (a packing of BMS bodies)");
  return *c.bond;
}

// The bodies' bond parameters a compaction fits: their stiffness and, for elastic_plastic bonds,
// their yield (calibrate.hpp's names; radius_multiplier and shear_ratio stay the FEM fit's).
bool is_compaction_bond_parameter(const std::string& name) {
  return is_bond_parameter(name) && name != "radius_multiplier" && name != "shear_ratio";
}

// Hertz's k1 = 4/3 E* √R* for two particles of the mean of the bed's diameter bounds (R* = d/4),
// the start of a k1 fit whose config takes k1 from E.
double hertz_loading_stiffness(CompactConfig& c) {
  if (!c.generate)
    throw InputError(
        "calibrate: the config's multi-contact law takes k1 from E (no loading_stiffness) and "
        "has no [generate] to take a particle size from: give a start with --start "
        "loading_stiffness=VALUE (N/m^1.5)");
  const Material& m = particle_material(c);
  const double d = 0.5 * (c.generate->diameter_min + c.generate->diameter_max);
  return implied_loading_stiffness(m.youngs_modulus, d, m.poisson_ratio);
}

// Log-space bounds: six decades either side of the start, and λp ≤ 1 (Eq. 6: k2 ≥ k1).
std::pair<double, double> log_bounds(const std::string& name, double start) {
  const double decades = std::log(1e6);
  double upper = std::log(start) + decades;
  if (name == "plasticity_ratio") upper = std::min(upper, 0.0);
  return {std::log(start) - decades, upper};
}

analysis::PunchCurve punch_curve(const CompactionTrial& trial) {
  analysis::PunchCurve c;
  for (const PunchRecord& r : trial.records) {
    c.time.push_back(r.time);
    c.gap.push_back(r.gap);
    c.top_force.push_back(r.top_force);
    c.stress.push_back(r.stress);
    c.solid_fraction.push_back(r.solid_fraction);
    c.phase.push_back(static_cast<int>(r.phase));
  }
  c.reference_gap = trial.prepared.punch.reference_gap;
  c.die_area = trial.prepared.setup.die_area;
  return c;
}

}  // namespace

double implied_loading_modulus(double loading_stiffness, double diameter, double poisson_ratio) {
  return loading_stiffness / (4.0 / 3.0 * std::sqrt(0.25 * diameter)) * 2.0 *
         (1.0 - poisson_ratio * poisson_ratio);
}

double implied_loading_stiffness(double loading_modulus, double diameter, double poisson_ratio) {
  return 4.0 / 3.0 * loading_modulus / (2.0 * (1.0 - poisson_ratio * poisson_ratio)) *
         std::sqrt(0.25 * diameter);
}

double get_parameter(const CompactConfig& config, const std::string& name) {
  CompactConfig c = config;
  if (name == "youngs_modulus") return particle_material(c).youngs_modulus;
  if (name == "loading_modulus") {
    const Material& m = particle_material(c);
    return m.loading_modulus.value_or(m.youngs_modulus);
  }
  if (is_law_parameter(name)) {
    const MulticontactParameters& p = particle_laws(c, name).front()->parameters;
    if (name == "plasticity_ratio") return p.plasticity_ratio;
    if (name == "multicontact_prefactor") return p.prefactor;
    return p.loading_stiffness ? *p.loading_stiffness : hertz_loading_stiffness(c);
  }
  if (is_compaction_bond_parameter(name)) return get_bond_parameter(bond_of(c, name), name);
  throw InputError(fmt::format("calibrate: unknown compaction parameter '{}' (known: {})", name,
                               fmt::join(compaction_parameter_names(), ", ")));
}

void set_parameter(CompactConfig& config, const std::string& name, double value) {
  if (name == "youngs_modulus" || name == "loading_modulus") {
    Material& m = particle_material(config);
    if (name == "youngs_modulus")
      m.youngs_modulus = value;
    else
      m.loading_modulus = value;
    // Bonds stated as a fraction of the bodies' solid modulus are the same solid: they follow it.
    if (config.bond && config.bond->modulus_fraction > 0.0)
      config.bond->modulus =
          config.bond->modulus_fraction * m.loading_modulus.value_or(m.youngs_modulus);
  } else if (is_law_parameter(name)) {
    for (MulticontactLaw* law : particle_laws(config, name)) {
      MulticontactParameters& p = law->parameters;
      if (name == "plasticity_ratio")
        p.plasticity_ratio = value;
      else if (name == "multicontact_prefactor")
        p.prefactor = value;
      else
        p.loading_stiffness = value;
    }
  } else if (is_compaction_bond_parameter(name)) {
    set_bond_parameter(bond_of(config, name), name, value);
  } else {
    throw InputError(fmt::format("calibrate: unknown compaction parameter '{}' (known: {})", name,
                                 fmt::join(compaction_parameter_names(), ", ")));
  }
}

CompactionBed compaction_bed(const CompactConfig& config, const std::filesystem::path& packing) {
  if (config.clumps)
    throw InputError(
        "calibrate: [clumps] are inserted at random for every run; calibrate on a packing made "
        "by `pack` (--packing) instead");
  CompactionBed bed;
  bed.punch = std::numeric_limits<double>::quiet_NaN();
  if (!packing.empty()) {
    if (is_body_packing(packing))
      bed.bodies = read_packing(packing);
    else
      bed.spheres = read_spheres(packing);
    return bed;
  }
  // Poured and settled once; the punch then starts where compact would start it, on its top.
  const PreparedCompaction settled = prepare_compaction(config, std::nullopt);
  const SphereState& s = settled.engine->state();
  bed.spheres = SphereList{};
  for (std::size_t i = 0; i < s.size(); ++i) {
    bed.spheres->x.push_back(s.position.x[i]);
    bed.spheres->y.push_back(s.position.y[i]);
    bed.spheres->z.push_back(s.position.z[i]);
    bed.spheres->radius.push_back(s.radius[i]);
  }
  bed.punch = settled.engine->walls()[settled.setup.punch_wall].position;
  return bed;
}

CompactionTrial run_compaction_trial(const CompactConfig& config, const CompactionBed& bed) {
  const auto t0 = std::chrono::steady_clock::now();
  CompactionTrial trial;
  CompactConfig c = config;
  if (!std::isnan(bed.punch)) c.punch = bed.punch;
  trial.prepared =
      bed.bodies ? prepare_compaction(c, *bed.bodies) : prepare_compaction(c, bed.spheres);
  CompactionHooks hooks;
  hooks.record = [&](const PunchRecord& r) { trial.records.push_back(r); };
  PreparedCompaction& p = trial.prepared;
  trial.summary = run_compaction(*p.engine, p.setup, p.punch, hooks);
  trial.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return trial;
}

analysis::MeasuredMismatch trial_mismatch(const CompactionTrial& trial,
                                          const analysis::MeasuredCurve& reference, double from,
                                          double to) {
  return analysis::compare_with_measured(
      analysis::simulated_loading(punch_curve(trial), reference.axes), reference.loading(), from,
      to);
}

double trial_recovery(const CompactionTrial& trial) {
  const analysis::CompactionMetrics m = analysis::analyse_compaction(punch_curve(trial));
  return m.unloaded ? m.elastic_recovery : std::numeric_limits<double>::quiet_NaN();
}

namespace {

void check_calibration_options(const CompactionCalibrationOptions& options) {
  if (options.target_recovery &&
      !(*options.target_recovery > 0.0 && *options.target_recovery < 1.0))
    throw InputError(fmt::format("calibrate: --target-recovery {} must be a percentage in (0, 100)",
                                 100.0 * *options.target_recovery));
  if (options.parameters.empty()) throw InputError("calibrate: no parameter to fit");
  if (!(options.to > options.from))
    throw InputError(
        fmt::format("calibrate: window [{}, {}] must have from < to", options.from, options.to));
  if (options.max_evaluations < 2) throw InputError("calibrate: --max-evaluations must be >= 2");
}

// The config the evaluations run: the evaluations' mass scaling and the stated start values.
CompactConfig evaluation_base(const CompactConfig& config,
                              const CompactionCalibrationOptions& options) {
  CompactConfig base = config;
  if (options.density_scale) base.density_scale = *options.density_scale;
  for (const auto& [name, value] : options.start) {
    if (!(value > 0.0))
      throw InputError(fmt::format("calibrate: start value of {} = {} must be > 0", name, value));
    set_parameter(base, name, value);
  }
  return base;
}

// The search runs in the logarithms of the parameters (all positive, over decades).
struct LogSearch {
  analysis::SearchOptions options;
  std::vector<double> start;  // the parameters' start values themselves
  std::vector<double> start_log;
};

// Each fitted parameter's start (a k1 taken from E becomes the stated start in `base`), its
// bounds and first step.
LogSearch log_search(CompactConfig& base, const CompactionCalibrationOptions& options) {
  LogSearch search;
  for (const std::string& name : options.parameters) {
    const double v = get_parameter(base, name);
    if (!(v > 0.0))
      throw InputError(fmt::format("calibrate: start value of {} = {} must be > 0", name, v));
    search.start.push_back(v);
    set_parameter(base, name, v);
    search.start_log.push_back(std::log(v));
    const auto [lower, upper] = log_bounds(name, v);
    search.options.lower.push_back(lower);
    search.options.upper.push_back(upper);
    search.options.initial_step.push_back(std::log(options.initial_factor));
  }
  search.options.max_evaluations = options.max_evaluations;
  search.options.value_tolerance = 1e-4;      // 0.01 % RMS, below the curve's resolution
  search.options.parameter_tolerance = 1e-3;  // 0.1 % in each parameter
  return search;
}

CompactConfig with_values(const CompactConfig& from, const std::vector<std::string>& parameters,
                          const std::vector<double>& values) {
  CompactConfig c = from;
  for (std::size_t k = 0; k < values.size(); ++k)
    set_parameter(c, parameters[k], values[k]);
  return c;
}

// The trial's mismatch in the options' window; a window with no point on the run's loading
// curve is an input error.
analysis::MeasuredMismatch window_error(const CompactionTrial& trial,
                                        const CompactionCalibrationOptions& options) {
  const analysis::MeasuredMismatch m =
      trial_mismatch(trial, options.reference, options.from, options.to);
  if (m.points == 0)
    throw InputError(fmt::format(
        "calibrate: no point of {} in the window [{}, {}] lies on the run's loading curve",
        options.reference.source.string(), options.from, options.to));
  return m;
}

}  // namespace

double compaction_objective(const CompactionTrial& trial,
                            const CompactionCalibrationOptions& options) {
  const double curve = window_error(trial, options).rms_relative;
  if (!options.target_recovery) return curve;
  const double recovery = trial_recovery(trial);
  if (!std::isfinite(recovery))
    throw InputError(
        "calibrate: --target-recovery needs runs that unload: give the config's [punch] an "
        "unload_speed");
  const double e_recovery = (recovery - *options.target_recovery) / *options.target_recovery;
  return std::sqrt(0.5 * (curve * curve + e_recovery * e_recovery));
}

namespace {

// A batch's evaluations at the search's points (in log space). A point of a resumed
// calibration's file, or one this search has run before (a contraction can land on an earlier
// vertex), takes that value: the same run would give the same value. Returns the indices of
// the points still to run.
std::vector<std::size_t> reuse_known(const std::vector<std::vector<double>>& points,
                                     const std::vector<CalibrationEvaluation>& from_file,
                                     const std::vector<CalibrationEvaluation>& made,
                                     std::vector<CalibrationEvaluation>& evaluations) {
  std::vector<std::size_t> to_run;
  evaluations.assign(points.size(), CalibrationEvaluation{});
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (double v : points[i])
      evaluations[i].values.push_back(std::exp(v));
    const CalibrationEvaluation* known = known_evaluation(from_file, evaluations[i].values);
    if (!known) known = known_evaluation(made, evaluations[i].values);
    if (known) {
      evaluations[i] = *known;
      evaluations[i].reused = true;
    } else {
      to_run.push_back(i);
    }
  }
  return to_run;
}

// One trial: its run and its RMS in the window. The search's start must meet the reference
// (`first`); a later point whose curve misses it (a bed too soft to reach the reference's
// stress) is a bad point, as a diverged one is.
void run_evaluation(const CompactConfig& scene, const CompactionBed& bed,
                    const CompactionCalibrationOptions& options, bool first,
                    CalibrationEvaluation& evaluation, std::optional<CompactionTrial>& trial) {
  try {
    trial = run_compaction_trial(scene, bed);
    evaluation.wall_seconds = trial->wall_seconds;
    if (!first && trial_mismatch(*trial, options.reference, options.from, options.to).points == 0) {
      evaluation.rms_relative = std::numeric_limits<double>::infinity();
      return;
    }
    evaluation.rms_relative = compaction_objective(*trial, options);
  } catch (const ComputationError&) {
    // A diverged trial is a bad point, not the end of the search.
    evaluation.rms_relative = std::numeric_limits<double>::infinity();
  }
}

}  // namespace

CompactionCalibrationResult calibrate_compaction(
    const CompactConfig& config, const std::filesystem::path& packing,
    const CompactionCalibrationOptions& options, int threads,
    const std::function<void(const CalibrationEvaluation&)>& progress) {
  check_calibration_options(options);
  CompactionCalibrationResult result;
  result.config = config;
  CompactConfig base = evaluation_base(config, options);
  const LogSearch search = log_search(base, options);
  result.start = search.start;
  // The bed is the config's: poured and settled with its own values (the start values are the
  // search's, not the powder's), so a `compact` run of the config presses the same bed.
  CompactConfig pour = config;
  pour.density_scale = base.density_scale;
  const CompactionBed bed = compaction_bed(pour, packing);
  std::optional<CompactionTrial> best;
  std::vector<double> best_values;
  double best_value = HUGE_VAL;
  const analysis::BatchObjective objective = [&](const std::vector<std::vector<double>>& points) {
    const std::size_t n = points.size();
    std::vector<CalibrationEvaluation> evaluations;
    const std::vector<std::size_t> to_run =
        reuse_known(points, options.known, result.evaluations, evaluations);
    std::vector<std::optional<CompactionTrial>> trials(n);
    const bool first_batch = result.evaluations.empty();
    // Trials side by side each run their engine on one thread (the same bits as alone); a
    // single trial runs on this thread and its engine takes the threads. Another error ends
    // the search (run_jobs rethrows it).
    const int side_by_side = std::min(threads, static_cast<int>(to_run.size()));
    run_jobs(to_run.size(), side_by_side, [&](std::size_t k) {
      if (side_by_side > 1) omp_set_num_threads(1);  // on the pool's own thread
      const std::size_t i = to_run[k];
      run_evaluation(with_values(base, options.parameters, evaluations[i].values), bed, options,
                     first_batch && i == 0, evaluations[i], trials[i]);
    });
    std::vector<double> values;
    for (std::size_t i = 0; i < n; ++i) {
      const CalibrationEvaluation& e = evaluations[i];
      result.evaluations.push_back(e);
      if (progress) progress(e);
      const double value = std::isfinite(e.rms_relative) ? e.rms_relative : 1e6;
      // The best run so far is kept, so the fit's curve needs no extra run (ties: the first,
      // as the search takes it).
      if (trials[i] && value < best_value) {
        best_value = value;
        best_values = e.values;
        best = std::move(trials[i]);
      }
      values.push_back(value);
    }
    return values;
  };
  const analysis::MinimumResult found =
      analysis::minimize(options.method, objective, search.start_log, search.options);
  for (double v : found.parameters)
    result.values.push_back(std::exp(v));
  result.converged = found.converged;
  result.config = with_values(config, options.parameters, result.values);
  // The best point's run, unless a resumed calibration took its value from the file.
  const CompactConfig scene = with_values(base, options.parameters, result.values);
  if (!best || best_values != result.values) best = run_compaction_trial(scene, bed);
  result.error = window_error(*best, options);
  result.recovery = trial_recovery(*best);
  result.objective = compaction_objective(*best, options);
  result.best = std::move(*best);
  return result;
}

}  // namespace shapepress::scenarios
