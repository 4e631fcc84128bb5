#include "scenarios/calibrate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <variant>

#include <fmt/format.h>

#include "analysis/curves.hpp"
#include "analysis/optimize.hpp"
#include "common/error.hpp"
#include "scenarios/bms_particle.hpp"

namespace shapepress::scenarios {

std::vector<std::string> calibration_parameter_names() {
  return {"normal_stiffness", "shear_stiffness",    "modulus",
          "shear_ratio",      "contact_modulus",    "radius_multiplier",
          "yield_stress",     "shear_yield_stress", "hardening_ratio"};
}

namespace {

BondParameters& particle_bond(PlateConfig& c) {
  if (!c.bms) throw InputError("calibrate: the config has no [bms] particle to calibrate");
  return c.bms->bond;
}

// The sub-spheres' own contact material: [bms] material when it is not the sphere's, else a copy
// of it named "<name>-contact" with the same interactions, so fitting its E leaves the sphere's
// (the Hertz reference's) alone. A calibrated config refitted keeps its one contact material.
Material& contact_material(PlateConfig& c) {
  auto& materials = c.materials.materials;
  const std::string base = c.bms->material;
  if (base != materials.at(static_cast<std::size_t>(c.setup.sphere_material)).name)
    for (Material& m : materials)
      if (m.name == base) return m;
  const std::string name = base + "-contact";
  for (const Material& m : materials)
    if (m.name == name)
      throw InputError(fmt::format(
          "calibrate: contact_modulus: [bms] material is the sphere's '{}' and a material '{}' "
          "exists; set [bms] material = \"{}\" to fit it",
          base, name, name));
  Material copy;
  for (const Material& m : materials)
    if (m.name == base) copy = m;
  if (copy.name.empty()) throw InputError("calibrate: unknown [bms] material '" + base + "'");
  copy.name = name;
  std::vector<Interaction> added;
  for (const Interaction& in : c.materials.interactions) {
    if (in.first != base && in.second != base) continue;
    Interaction twin = in;
    if (twin.first == base) twin.first = name;
    if (twin.second == base) twin.second = name;
    added.push_back(twin);
    if (in.first == base && in.second == base) {  // also the bulk–contact pair
      Interaction mixed = in;
      mixed.second = name;
      added.push_back(mixed);
    }
  }
  c.materials.interactions.insert(c.materials.interactions.end(), added.begin(), added.end());
  materials.push_back(copy);
  c.bms->material = name;
  return materials.back();
}

// Fitting the bond modulus of a config given in Table 1's per-area form: start from the
// equivalent Ē = k̄n (ri + rj) of this fill's sub-spheres and k̄s/k̄n, so that the fitted
// parameters hold for any N (P&C 2004 §2.2.2) while the start is the config's.
PlateConfig modulus_form_if_asked(const PlateConfig& config,
                                  const std::vector<std::string>& parameters) {
  const bool asked =
      std::find(parameters.begin(), parameters.end(), "modulus") != parameters.end() ||
      std::find(parameters.begin(), parameters.end(), "shear_ratio") != parameters.end();
  if (!asked || !config.bms || config.bms->bond.modulus > 0.0) return config;
  PlateConfig c = config;
  BmsParticleInfo info;
  bms_particle(c.materials.table(), c.setup.radius, *c.bms, "BMS sphere", &info);
  BondParameters& b = c.bms->bond;
  b.modulus = b.normal_stiffness * 2.0 * info.sub_sphere_radius;
  b.shear_ratio = b.shear_stiffness / b.normal_stiffness;
  return c;
}

}  // namespace

bool is_bond_parameter(const std::string& name) {
  return name == "normal_stiffness" || name == "shear_stiffness" || name == "modulus" ||
         name == "shear_ratio" || name == "radius_multiplier" || name == "yield_stress" ||
         name == "shear_yield_stress" || name == "hardening_ratio";
}

namespace {

bool is_plastic_parameter(const std::string& name) {
  return name == "yield_stress" || name == "shear_yield_stress" || name == "hardening_ratio";
}

// The yielding bond's parameters (const or not, as `b` is): the [bond] model must be
// elastic_plastic.
template <class Bond>
auto& plastic_bond_of(Bond& b, const std::string& name) {
  auto* plastic = std::get_if<ElasticPlasticBond>(&b.model);
  if (plastic == nullptr)
    throw InputError(
        fmt::format("calibrate: '{}' needs [bond] model = \"elastic_plastic\" (the "
                    "config's bonds are {})",
                    name, bond_model_name(b.model)));
  return *plastic;
}

// The stiffness's form the name needs: Ē (modulus, shear_ratio) or k̄n, k̄s.
void check_bond_form(const BondParameters& b, const std::string& name) {
  const bool modulus_form = b.modulus > 0.0;
  if ((name == "modulus" || name == "shear_ratio") && !modulus_form)
    throw InputError("calibrate: '" + name +
                     "' needs [bond] modulus (the config gives normal_stiffness/shear_stiffness)");
  if ((name == "normal_stiffness" || name == "shear_stiffness") && modulus_form)
    throw InputError("calibrate: '" + name +
                     "' needs [bond] normal_stiffness/shear_stiffness "
                     "(the config gives modulus)");
}

}  // namespace

double get_bond_parameter(const BondParameters& b, const std::string& name) {
  if (is_plastic_parameter(name)) {
    const ElasticPlasticBond& p = plastic_bond_of(b, name);
    return name == "yield_stress"         ? p.yield_stress
           : name == "shear_yield_stress" ? p.shear_yield_stress
                                          : p.hardening_ratio;
  }
  check_bond_form(b, name);
  if (name == "normal_stiffness") return b.normal_stiffness;
  if (name == "shear_stiffness") return b.shear_stiffness;
  if (name == "modulus") return b.modulus;
  if (name == "shear_ratio") return b.shear_ratio;
  if (name == "radius_multiplier") return b.radius_multiplier;
  throw InputError(fmt::format("calibrate: '{}' is not a bond parameter", name));
}

void set_bond_parameter(BondParameters& b, const std::string& name, double value) {
  if (is_plastic_parameter(name)) {
    ElasticPlasticBond& p = plastic_bond_of(b, name);
    (name == "yield_stress"         ? p.yield_stress
     : name == "shear_yield_stress" ? p.shear_yield_stress
                                    : p.hardening_ratio) = value;
    return;
  }
  check_bond_form(b, name);
  if (name == "normal_stiffness")
    b.normal_stiffness = value;
  else if (name == "shear_stiffness")
    b.shear_stiffness = value;
  else if (name == "modulus") {
    // Bonds stated as a fraction of the solid's modulus stay in that form: the fraction moves.
    if (b.modulus_fraction > 0.0) b.modulus_fraction *= value / b.modulus;
    b.modulus = value;
  } else if (name == "shear_ratio")
    b.shear_ratio = value;
  else if (name == "radius_multiplier")
    b.radius_multiplier = value;
  else
    throw InputError(fmt::format("calibrate: '{}' is not a bond parameter", name));
}

double get_parameter(const PlateConfig& config, const std::string& name) {
  PlateConfig c = config;
  if (name == "contact_modulus") {
    if (!c.bms) throw InputError("calibrate: the config has no [bms] particle to calibrate");
    return contact_material(c).youngs_modulus;
  }
  if (is_bond_parameter(name)) return get_bond_parameter(particle_bond(c), name);
  throw InputError(fmt::format("calibrate: unknown parameter '{}' (known: {})", name,
                               fmt::join(calibration_parameter_names(), ", ")));
}

void set_parameter(PlateConfig& config, const std::string& name, double value) {
  if (name == "contact_modulus") {
    if (!config.bms) throw InputError("calibrate: the config has no [bms] particle to calibrate");
    contact_material(config).youngs_modulus = value;
    return;
  }
  if (is_bond_parameter(name)) return set_bond_parameter(particle_bond(config), name, value);
  throw InputError(fmt::format("calibrate: unknown parameter '{}' (known: {})", name,
                               fmt::join(calibration_parameter_names(), ", ")));
}

CurveError plate_curve_error(const std::vector<PlateRow>& rows,
                             const std::vector<double>& reference_deformation,
                             const std::vector<double>& reference_force, double from, double to) {
  analysis::Curve run{{0.0}, {0.0}, "run"};
  for (const PlateRow& r : rows)
    if (r.deformation > run.x.back()) {
      run.x.push_back(r.deformation);
      run.y.push_back(r.top_force);
    }
  const analysis::Curve reference{reference_deformation, reference_force, "reference"};
  reference.check();
  run.check();
  const double upper = std::min({to, run.x.back(), reference.x.back()});
  if (!(upper > from))
    throw InputError(fmt::format(
        "calibrate: the window [{}, {}] is not covered by the run (to {:.3g}) and the reference "
        "(to {:.3g})",
        from, to, run.x.back(), reference.x.back()));
  const analysis::CurveDifference d = analysis::compare_curves(run, reference, from, upper);
  return {d.rms_relative, d.max_relative};
}

double plate_unloading_error(const std::vector<PlateRow>& rows, int records,
                             const std::vector<double>& reference_deformation,
                             const std::vector<double>& reference_force) {
  if (rows.size() <= static_cast<std::size_t>(records) || records < 1)
    throw InputError("calibrate: the run has no unloading rows to compare ([plate] unload)");
  // Both curves ascending in deformation, from their turn (the largest deformation) down.
  analysis::Curve run{{}, {}, "run unloading"}, reference{{}, {}, "reference unloading"};
  for (std::size_t i = rows.size(); i-- > static_cast<std::size_t>(records) - 1;)
    if (run.x.empty() || rows[i].deformation > run.x.back()) {
      run.x.push_back(rows[i].deformation);
      run.y.push_back(rows[i].top_force);
    }
  double peak = 0.0;
  for (std::size_t i = reference_deformation.size(); i-- > 0;) {
    peak = std::max(peak, reference_force[i]);
    if (reference.x.empty() || reference_deformation[i] > reference.x.back()) {
      reference.x.push_back(reference_deformation[i]);
      reference.y.push_back(reference_force[i]);
    }
  }
  run.check();
  reference.check();
  if (!(peak > 0.0)) throw InputError("calibrate: the reference's unloading carries no force");
  const double upper = std::min(run.x.back(), reference.x.back());
  constexpr int samples = 200;
  double sum = 0.0;
  for (int k = 0; k <= samples; ++k) {
    const double x = upper * k / samples;
    const double d = analysis::interpolate(run, x) - analysis::interpolate(reference, x);
    sum += d * d;
  }
  return std::sqrt(sum / (samples + 1)) / peak;
}

const CalibrationEvaluation* known_evaluation(const std::vector<CalibrationEvaluation>& known,
                                              const std::vector<double>& values) {
  // Exact equality: evaluations.csv keeps 17 significant digits, which read back to the same
  // doubles, and the search computes the same points again.
  for (const CalibrationEvaluation& e : known)
    if (e.values == values) return &e;
  return nullptr;
}

CalibrationResult calibrate_plate(
    const PlateConfig& config, const CalibrationOptions& options,
    const std::function<void(const CalibrationEvaluation&)>& progress) {
  if (options.parameters.empty()) throw InputError("calibrate: no parameter to fit");
  if (!(options.from >= 0.0 && options.to > options.from))
    throw InputError(fmt::format("calibrate: window [{}, {}] must have 0 <= from < to",
                                 options.from, options.to));
  if (options.max_evaluations < 2) throw InputError("calibrate: --max-evaluations must be >= 2");
  CalibrationResult result;
  PlateConfig base = modulus_form_if_asked(config, options.parameters);
  const bool unloading = !options.reference_unloading_deformation.empty();
  if (unloading) base.setup.unload = true;
  // The objective of a run: the loading's RMS relative error, and with an unloading reference
  // the unloading's over the peak force, the two branches weighed alike.
  struct RunError {
    double objective = 0.0, loading = 0.0, loading_max = 0.0, unloading = 0.0;
  };
  const auto run_error = [&](const PlateRunOutcome& run) {
    const CurveError load = plate_curve_error(run.rows, options.reference_deformation,
                                              options.reference_force, options.from, options.to);
    RunError e{load.rms_relative, load.rms_relative, load.max_relative, 0.0};
    if (unloading) {
      e.unloading = plate_unloading_error(run.rows, run.rows.empty() ? 0 : base.setup.records,
                                          options.reference_unloading_deformation,
                                          options.reference_unloading_force);
      e.objective = std::sqrt(0.5 * (e.loading * e.loading + e.unloading * e.unloading));
    }
    return e;
  };
  for (const auto& [name, value] : options.start) {
    if (!(value > 0.0))
      throw InputError(fmt::format("calibrate: start value of {} = {} must be > 0", name, value));
    set_parameter(base, name, value);
  }
  for (const std::string& name : options.parameters) {
    const double v = get_parameter(base, name);
    // The search runs on logarithms: a yield stress left at its default (inf: never yields) or
    // a hardening ratio of 0 has no start there.
    if (!(v > 0.0 && std::isfinite(v)))
      throw InputError(fmt::format(
          "calibrate: start value of {} = {} must be > 0 and finite (set it in the config or "
          "with --start {}=…)",
          name, v, name));
    result.start.push_back(v);
  }
  const auto configured = [&](const std::vector<double>& values) {
    PlateConfig c = base;
    for (std::size_t k = 0; k < values.size(); ++k)
      set_parameter(c, options.parameters[k], values[k]);
    return c;
  };
  // All parameters are positive scales spanning decades: search their logarithms, within six
  // decades of the start.
  std::vector<double> start_log;
  analysis::SearchOptions search;
  for (double v : result.start) {
    start_log.push_back(std::log(v));
    search.lower.push_back(std::log(v) - std::log(1e6));
    search.upper.push_back(std::log(v) + std::log(1e6));
    search.initial_step.push_back(std::log(options.initial_factor));
  }
  search.max_evaluations = options.max_evaluations;
  search.value_tolerance = 1e-4;      // 0.01 % RMS: below the run-to-run resolution of the curve
  search.parameter_tolerance = 1e-3;  // 0.1 % in each parameter
  // Every evaluation presses the same fills; only the bonds (and contacts) change.
  BmsFillCache fills;
  const auto objective = [&](const std::vector<double>& x) {
    CalibrationEvaluation e;
    for (double v : x)
      e.values.push_back(std::exp(v));
    if (const CalibrationEvaluation* known = known_evaluation(options.known, e.values)) {
      e = *known;
      e.reused = true;
      result.evaluations.push_back(e);
      if (progress) progress(e);
      return std::isfinite(e.rms_relative) ? e.rms_relative : 1e6;
    }
    const auto t0 = std::chrono::steady_clock::now();
    try {
      const PlateRunOutcome run =
          run_plate_config(configured(e.values), PlateParticleKind::bms, {}, &fills);
      e.rms_relative = run_error(run).objective;
    } catch (const ComputationError&) {
      // A diverged trial is a bad point, not the end of the search.
      e.rms_relative = std::numeric_limits<double>::infinity();
    }
    e.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    result.evaluations.push_back(e);
    if (progress) progress(e);
    return std::isfinite(e.rms_relative) ? e.rms_relative : 1e6;
  };
  const analysis::MinimumResult best =
      options.method == analysis::SearchMethod::bobyqa
          ? analysis::minimize_bobyqa(objective, start_log, search)
          : analysis::minimize_nelder_mead(objective, start_log, search);
  for (double v : best.parameters)
    result.values.push_back(std::exp(v));
  result.converged = best.converged;
  result.config = configured(result.values);
  result.best = run_plate_config(result.config, PlateParticleKind::bms, {}, &fills);
  const RunError error = run_error(result.best);
  result.rms_relative = error.objective;
  result.max_relative = error.loading_max;
  result.loading_rms_relative = error.loading;
  result.unloading_rms = error.unloading;
  return result;
}

}  // namespace shapepress::scenarios
