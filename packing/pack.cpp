#include "packing/pack.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <numeric>
#include <optional>

#include "common/error.hpp"
#include "geometry/templates_file.hpp"
#include "packing/bed_state.hpp"
#include "packing/clump_packing.hpp"
#include "packing/deposition.hpp"
#include "simulate/engine.hpp"
#include "simulate/timestep.hpp"

namespace shapepress::packing {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError("pack: " + what);
}

BodyTemplate unit_sphere() {
  BodyTemplate t;
  t.name = "sphere";
  t.kind = BodyKind::sphere;
  t.centres = {{0.0, 0.0, 0.0}};
  t.radii = {0.5};
  t.shape_volume = t.sphere_volume = t.body_volume = std::numbers::pi / 6.0;
  const double moment = 0.4 * t.shape_volume * 0.25;  // (2/5) m r², per unit density
  t.principal_inertia = t.body_inertia = {moment, moment, moment};
  return t;
}

BodyTemplate body_template(const geometry::TemplateRecord& r, const std::filesystem::path& file) {
  BodyTemplate t;
  const bool bonded = r.body.kind == geometry::TemplateKind::bonded;
  t.name = (bonded ? "bms/" : "cms/") + r.name;
  t.source = file.string();
  t.kind = bonded ? BodyKind::bms : BodyKind::cms;
  for (const geometry::Vec3& c : r.body.centres)
    t.centres.push_back({c.x(), c.y(), c.z()});
  t.radii = r.body.radii;
  t.bonds = r.body.bonds;
  t.shape_volume = r.shape_mass.volume;
  t.sphere_volume = r.mass.volume;
  // The body frame is the template's principal frame: its inertia there is diagonal.
  t.body_volume = r.body_mass.volume;
  for (int k = 0; k < 3; ++k) {
    t.principal_inertia[k] = r.mass.inertia(k, k);
    t.body_inertia[k] = r.body_mass.inertia(k, k);
  }
  if (!(t.shape_volume > 0.0) || !(t.sphere_volume > 0.0) || !(t.body_volume > 0.0) ||
      t.radii.empty())
    throw InputError(
        fmt::format("{}: template {} has no volume or no sub-spheres", file.string(), t.name));
  return t;
}

}  // namespace

void PackRequest::check() const {
  require(!templates.empty(), "no template to pack");
  for (const TemplateChoice& t : templates)
    require(std::isfinite(t.weight) && t.weight > 0.0,
            fmt::format("template {}: weight {} must be > 0", t.name, t.weight));
  require(count > 0 || (target_mass && *target_mass > 0.0),
          "give pack.count > 0 or pack.target_mass > 0");
  require(std::isfinite(box_x) && std::isfinite(box_y) && box_x > 0.0 && box_y > 0.0,
          "box_x and box_y must be > 0");
  require(std::isfinite(diameter_min) && std::isfinite(diameter_max) && diameter_min > 0.0 &&
              diameter_max > diameter_min,
          fmt::format("need 0 < diameter_min < diameter_max (got {} and {} m)", diameter_min,
                      diameter_max));
  require(std::isfinite(damping_time) && damping_time >= 0.0, "settle.damping_time must be >= 0");
  for (double v : {density, youngs_modulus, restitution, insertion_fraction, max_settle_time,
                   time_step_fraction, punch_speed, kinetic_energy_ratio})
    require(std::isfinite(v) && v > 0.0, "material, settle and press values must be > 0");
  require(std::isfinite(settle_density_scale) && settle_density_scale >= 1.0,
          "settle.density_scale must be >= 1");
  require(poisson_ratio >= 0.0 && poisson_ratio < 0.5, "poisson_ratio must be in [0, 0.5)");
  require(restitution <= 1.0, "restitution must be in (0, 1]");
  require(friction >= 0.0 && wall_friction >= 0.0 && rolling_friction >= 0.0,
          "friction must be >= 0");
  require(insertion_fraction < 0.5, "insertion_fraction must be < 0.5 (random insertion jams)");
  if (target_solid_fraction)
    require(std::isfinite(*target_solid_fraction) && *target_solid_fraction > 0.0 &&
                *target_solid_fraction <= solid_fraction_ceiling,
            fmt::format("press.solid_fraction = {} is above the ceiling "
                        "press.solid_fraction_ceiling = {} the punch may press rigid bodies to",
                        *target_solid_fraction, solid_fraction_ceiling));
}

void check_bms_template(const BodyTemplate& shape) {
  const std::size_t n = shape.radii.size();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const Vector3& a = shape.centres[i];
      const Vector3& b = shape.centres[j];
      const double gap = std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
      const double overlap = shape.radii[i] + shape.radii[j] - gap;
      const double smaller = std::min(shape.radii[i], shape.radii[j]);
      if (overlap > bms_overlap_tolerance * smaller)
        throw InputError(fmt::format(
            "{}: template {}: sub-spheres {} and {} overlap by {:.3g} of the smaller radius; a "
            "BMS template's sub-spheres only touch (tolerance {}): fill it again, or use it as "
            "a CMS template",
            shape.source, shape.name, i, j, overlap / smaller, bms_overlap_tolerance));
    }
}

std::vector<BodyTemplate> load_body_templates(const std::vector<std::filesystem::path>& files,
                                              const std::vector<TemplateChoice>& choices) {
  std::vector<std::vector<geometry::TemplateRecord>> records;
  for (const std::filesystem::path& file : files)
    records.push_back(geometry::read_templates(file));
  std::vector<BodyTemplate> out;
  for (const TemplateChoice& choice : choices) {
    if (choice.name == "sphere") {
      out.push_back(unit_sphere());
      continue;
    }
    const bool bms = choice.name.starts_with("bms/"), cms = choice.name.starts_with("cms/");
    if (!bms && !cms)
      throw InputError(
          fmt::format("pack: template '{}' must be \"sphere\", \"bms/<name>\" or "
                      "\"cms/<name>\"",
                      choice.name));
    const std::string name = choice.name.substr(4);
    const geometry::TemplateKind kind =
        bms ? geometry::TemplateKind::bonded : geometry::TemplateKind::rigid;
    bool found = false;
    for (std::size_t f = 0; f < files.size() && !found; ++f)
      for (const geometry::TemplateRecord& r : records[f])
        if (r.name == name && r.body.kind == kind) {
          out.push_back(body_template(r, files[f]));
          found = true;
          break;
        }
    if (!found) {
      std::string where;
      for (const std::filesystem::path& f : files)
        where += (where.empty() ? "'" : ", '") + f.string() + "'";
      throw InputError(fmt::format("no template /{} in {}", choice.name,
                                   where.empty() ? "(no templates file given)" : where));
    }
    if (out.back().kind == BodyKind::bms) check_bms_template(out.back());
  }
  return out;
}

std::vector<BodyTemplate> load_body_templates(const std::filesystem::path& file, BodyKind kind) {
  const geometry::TemplateKind wanted =
      kind == BodyKind::bms ? geometry::TemplateKind::bonded : geometry::TemplateKind::rigid;
  std::vector<BodyTemplate> out;
  for (const geometry::TemplateRecord& r : geometry::read_templates(file))
    if (r.body.kind == wanted) {
      out.push_back(body_template(r, file));
      if (kind == BodyKind::bms) check_bms_template(out.back());
    }
  if (out.empty())
    throw InputError(
        fmt::format("'{}' holds no template of kind {} (no /{} group): fill with "
                    "--kind {}",
                    file.string(), geometry::kind_name(wanted), geometry::kind_name(wanted),
                    geometry::kind_name(wanted)));
  return out;
}

double size_quantile(const SizeTable& table, double level, bool volume_weighted) {
  const std::size_t n = table.diameter.size();
  std::vector<double> q(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) {
    const double mid = std::sqrt(table.diameter[k] * table.diameter[k - 1]);
    const double w = volume_weighted ? mid * mid * mid : 1.0;
    q[k] = q[k - 1] + w * (table.cumulative[k] - table.cumulative[k - 1]);
  }
  const auto it = std::lower_bound(q.begin(), q.end(), level * q.back());
  if (it == q.begin()) return table.diameter.front();
  if (it == q.end()) return table.diameter.back();
  const auto k = static_cast<std::size_t>(it - q.begin());
  const double span = q[k] - q[k - 1];
  const double t = span > 0.0 ? (level * q.back() - q[k - 1]) / span : 0.0;
  return table.diameter[k - 1] * std::pow(table.diameter[k] / table.diameter[k - 1], t);
}

double sample_quantile(std::vector<double> diameters, double level, bool volume_weighted) {
  if (diameters.empty()) return 0.0;
  std::sort(diameters.begin(), diameters.end());
  double total = 0.0;
  for (double d : diameters)
    total += volume_weighted ? d * d * d : 1.0;
  // The weighted empirical distribution, each sample's weight centred on it (Hazen).
  double below = 0.0;
  double previous_d = diameters.front(), previous_q = 0.0;
  for (double d : diameters) {
    const double w = (volume_weighted ? d * d * d : 1.0) / total;
    const double q = below + 0.5 * w;
    if (q >= level) {
      if (q == previous_q) return d;
      return previous_d + (d - previous_d) * (level - previous_q) / (q - previous_q);
    }
    below += w, previous_d = d, previous_q = q;
  }
  return diameters.back();
}

std::vector<PackedBody> draw_bodies(const PackRequest& request,
                                    const std::vector<BodyTemplate>& templates) {
  request.check();
  if (templates.size() != request.templates.size())
    throw InputError("pack: one template per choice expected");
  const double kept = retained_fraction(request.sizes, request.diameter_min, request.diameter_max);
  if (!(kept > 1e-6))
    throw InputError(fmt::format(
        "pack: the size cutoff [{:.4g}, {:.4g}] m keeps {:.3g} of the size distribution (x10..x90 "
        "of the distribution: {:.4g}..{:.4g} m): nothing to pack",
        request.diameter_min, request.diameter_max, kept, request.sizes.diameters.front(),
        request.sizes.diameters.back()));
  const SizeTable table = size_table(request.sizes, request.diameter_min, request.diameter_max);
  // Independent streams: the sizes do not change when the templates or weights do.
  std::mt19937_64 size_random(request.seed), turn_random(request.seed ^ 0x9e3779b97f4a7c15ULL),
      pick_random(request.seed ^ 0xbf58476d1ce4e5b9ULL);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double weight_sum = 0.0;
  for (const TemplateChoice& t : request.templates)
    weight_sum += t.weight;
  std::vector<double> template_volume(templates.size(), 0.0);
  double drawn_volume = 0.0, drawn_mass = 0.0;
  std::vector<PackedBody> bodies;
  constexpr std::int64_t max_bodies = 1'000'000;
  while (request.count > 0 ? static_cast<std::int64_t>(bodies.size()) < request.count
                           : drawn_mass < *request.target_mass) {
    if (static_cast<std::int64_t>(bodies.size()) >= max_bodies)
      throw InputError(fmt::format("pack: target_mass {} kg needs more than {} bodies",
                                   *request.target_mass, max_bodies));
    const double d = table.sample(unit(size_random));
    const double volume = std::numbers::pi / 6.0 * d * d * d;
    std::size_t pick = 0;
    if (request.weighting == TemplateWeighting::number) {
      double u = unit(pick_random) * weight_sum;
      while (pick + 1 < templates.size() && u >= request.templates[pick].weight)
        u -= request.templates[pick++].weight;
    } else {  // the template whose volume share lags furthest behind its weight
      double worst = -std::numeric_limits<double>::infinity();
      for (std::size_t t = 0; t < templates.size(); ++t) {
        const double lag =
            request.templates[t].weight / weight_sum * (drawn_volume + volume) - template_volume[t];
        if (lag > worst) worst = lag, pick = t;
      }
    }
    const BodyTemplate& shape = templates[pick];
    PackedBody body;
    body.template_index = static_cast<std::int32_t>(pick);
    body.scale = d / shape.volume_equivalent_diameter();
    body.orientation = random_rotation(turn_random);
    const double s3 = body.scale * body.scale * body.scale;
    body.shape_volume = shape.shape_volume * s3;
    body.sphere_volume = shape.sphere_volume * s3;
    body.body_volume = shape.body_volume * s3;
    template_volume[pick] += volume;
    drawn_volume += volume;
    drawn_mass += request.density * body.body_volume;
    bodies.push_back(body);
  }
  return bodies;
}

double bounding_radius(const BodyTemplate& shape) {
  double reach = 0.0;
  for (std::size_t i = 0; i < shape.radii.size(); ++i)
    reach =
        std::max(reach, std::hypot(shape.centres[i][0], shape.centres[i][1], shape.centres[i][2]) +
                            shape.radii[i]);
  return reach;
}

double insert_bodies(const PackRequest& request, const std::vector<BodyTemplate>& templates,
                     std::vector<PackedBody>& bodies) {
  const std::size_t n = bodies.size();
  std::vector<double> reach(n);
  double bound_volume = 0.0, largest = 0.0;
  for (std::size_t b = 0; b < n; ++b) {
    const BodyTemplate& t = templates[static_cast<std::size_t>(bodies[b].template_index)];
    reach[b] = bodies[b].scale * bounding_radius(t);
    bound_volume += 4.0 / 3.0 * std::numbers::pi * std::pow(reach[b], 3);
    if (2.0 * reach[b] >= std::min(request.box_x, request.box_y))
      throw InputError(fmt::format(
          "pack: body {} ({}, volume-equivalent diameter {:.4g} m) reaches {:.4g} m across, not "
          "less than the box ({:.4g} × {:.4g} m): a body must not touch its own periodic image; "
          "a larger box or a smaller diameter_max",
          b, t.name, std::cbrt(6.0 * bodies[b].shape_volume / std::numbers::pi), 2.0 * reach[b],
          request.box_x, request.box_y));
    largest = std::max(largest, reach[b]);
  }
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return reach[a] > reach[b]; });
  const double area = request.box_x * request.box_y;
  double height = std::max(2.0 * largest, bound_volume / (request.insertion_fraction * area));
  std::mt19937_64 random(request.seed ^ 0x94d049bb133111ebULL);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // A region that jams is made taller (by a quarter, a few times) before giving up.
  for (int round = 0; round < 8; ++round, height *= 1.25) {
    std::vector<std::size_t> placed;
    bool jammed = false;
    for (std::size_t b : order) {
      bool ok = false;
      for (int attempt = 0; attempt < request.attempts_per_body && !ok; ++attempt) {
        const double x = request.box_x * unit(random), y = request.box_y * unit(random);
        const double z = request.floor + reach[b] + (height - 2.0 * reach[b]) * unit(random);
        ok = std::none_of(placed.begin(), placed.end(), [&](std::size_t o) {
          double dx = bodies[o].centre[0] - x, dy = bodies[o].centre[1] - y;
          dx -= request.box_x * std::nearbyint(dx / request.box_x);
          dy -= request.box_y * std::nearbyint(dy / request.box_y);
          const double dz = bodies[o].centre[2] - z, gap = reach[o] + reach[b];
          return dx * dx + dy * dy + dz * dz < gap * gap;
        });
        if (ok) bodies[b].centre = {x, y, z};
      }
      if (!ok) {
        jammed = true;
        break;
      }
      placed.push_back(b);
    }
    if (!jammed) return request.floor + height;
  }
  throw InputError(fmt::format(
      "pack: {} bodies found no place by random insertion up to a region {:.4g} m tall: a lower "
      "settle.insertion_fraction or more settle.attempts_per_body",
      n, height));
}

namespace {

MaterialTable pack_materials(const PackRequest& r, double friction, double wall_friction) {
  std::vector<Material> materials = {{"particle", r.youngs_modulus, r.poisson_ratio, r.density},
                                     {"wall", r.youngs_modulus, r.poisson_ratio, r.density}};
  Interaction bodies{"particle", "particle", r.restitution, friction, r.rolling_friction};
  Interaction walls{"particle", "wall", r.restitution, wall_friction, r.rolling_friction};
  return MaterialTable(materials, {bodies, walls});
}

// The rigid-clump period bound (simulate/timestep.hpp clump_contact_period) for a body in a
// packed bed: at most contacts_per_body of its sub-spheres touch at once, taken as its outermost
// ones (the longest lever arms) at 0.1 of their radius. The engine's generic bound lets every
// sub-sphere touch; a body of 350 sub-spheres in a bed touches a dozen neighbours and the walls,
// and that bound would cost its square root in time step (√(350 / 12) ≈ 5). The divergence check
// stays the guard.
constexpr std::size_t contacts_per_body = 12;

double packed_clump_period(const SphereState& state, const ClumpSet& clumps,
                           const MaterialTable& table) {
  std::vector<double> overlap(state.size(), 0.0);
  std::vector<int> partners = {0, 1};
  for (std::size_t c = 0; c < clumps.size(); ++c) {
    std::vector<std::pair<double, std::int32_t>> reach;
    for (std::int32_t i = clumps.first[c]; i < clumps.last[c]; ++i)
      reach.emplace_back(-(std::hypot(state.position.x[i] - clumps.centre.x[c],
                                      state.position.y[i] - clumps.centre.y[c],
                                      state.position.z[i] - clumps.centre.z[c]) +
                           state.radius[i]),
                         i);
    const std::size_t touching = std::min(contacts_per_body, reach.size());
    std::partial_sort(reach.begin(), reach.begin() + static_cast<std::ptrdiff_t>(touching),
                      reach.end());
    for (std::size_t k = 0; k < touching; ++k) {
      const auto i = static_cast<std::size_t>(reach[k].second);
      overlap[i] = assumed_clump_overlap * state.radius[i];
    }
  }
  return clump_contact_period(clumps, state, table, partners, overlap);
}

double kinetic_energy(const Engine& engine) {
  return engine.energy().kinetic;
}

void apply_drag(Engine& engine, double factor) {
  SphereState& s = engine.mutable_state();
  ClumpSet& clumps = engine.mutable_clumps();
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!clumps.clump_of.empty() && clumps.clump_of[i] >= 0) continue;  // the body's
    s.velocity.x[i] *= factor, s.velocity.y[i] *= factor, s.velocity.z[i] *= factor;
    s.angular_velocity.x[i] *= factor, s.angular_velocity.y[i] *= factor,
        s.angular_velocity.z[i] *= factor;
  }
  for (std::size_t c = 0; c < clumps.size(); ++c) {
    clumps.velocity.x[c] *= factor, clumps.velocity.y[c] *= factor, clumps.velocity.z[c] *= factor;
    for (double& l : clumps.rotation[c].body_angular_momentum)
      l *= factor;
  }
}

const char* phase_name(PackPhase phase) {
  switch (phase) {
    case PackPhase::settle:
      return "settle";
    case PackPhase::press:
      return "press";
    case PackPhase::relax:
      return "relax";
    case PackPhase::release:
      return "release";
  }
  return "?";
}

enum class PhaseEnd { rest, time_out, elapsed, interrupted };

// When a phase ends: at rest, its kinetic energy below `rest` (tested every 200th step from
// min_time on), or at max_time; or, given `steps`, after exactly that many steps with no rest
// test (compact's pour, whose settle time is part of the bed's recipe). drag_time: the drag
// v → v e^(-dt/τ) of τ = drag_time after every step (0: none).
struct PhaseEnding {
  double min_time = 0.0;                                      // s
  double max_time = std::numeric_limits<double>::infinity();  // s
  double rest = 0.0;                                          // J
  double drag_time = 0.0;                                     // s
  std::optional<std::int64_t> steps;
};

PhaseEnding until_rest(double min_time, double max_time, double rest, double drag_time) {
  PhaseEnding ending;
  ending.min_time = min_time, ending.max_time = max_time;
  ending.rest = rest, ending.drag_time = drag_time;
  return ending;
}

PhaseEnding after_steps(std::int64_t steps) {
  PhaseEnding ending;
  ending.min_time = std::numeric_limits<double>::infinity();  // no kinetic energy computed
  ending.steps = steps;
  return ending;
}

// Runs the phase state.phase from state.phase_step on until `ending` (a poured bed starts at
// rest, hence min_time). `each_step` runs before every step (the punch's motion) and returns
// false to end the phase.
template <class EachStep>
PhaseEnd run_phase(Engine& engine, const PhaseEnding& ending, const PackProgress& progress,
                   PackPhaseState& state, EachStep&& each_step) {
  constexpr int check_every = 200;
  const char* name = phase_name(state.phase);
  for (;;) {
    if (ending.steps && state.phase_step >= *ending.steps) return PhaseEnd::elapsed;
    const double t = engine.time() - state.phase_start;
    if (state.phase_step % check_every == 0) {
      if (progress.update) progress.update(name, t, ending.max_time);
      if (t >= ending.min_time && kinetic_energy(engine) < ending.rest) {
        spdlog::info("pack: {} at rest after {} steps, {:.3g} s", name, state.phase_step, t);
        return PhaseEnd::rest;
      }
    }
    if (t >= ending.max_time) {
      spdlog::warn(
          "pack: {} did not come to rest in {} s (settle.max_time): kinetic energy "
          "{:.3g} J against the threshold {:.3g} J",
          name, ending.max_time, kinetic_energy(engine), ending.rest);
      return PhaseEnd::time_out;
    }
    if (!each_step()) return PhaseEnd::rest;
    engine.step();
    if (ending.drag_time > 0.0)
      apply_drag(engine, std::exp(-engine.settings().time_step / ending.drag_time));
    ++state.phase_step;
    if (progress.after_step && !progress.after_step(engine, state)) return PhaseEnd::interrupted;
  }
}

// Every mass and moment of inertia times `factor` (the settle's mass scaling undone): the
// velocities stay, and the spins with them (a clump's angular momentum scales with its inertia).
void scale_masses(SphereState& s, ClumpSet& clumps, double factor) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    s.mass[i] *= factor;
    s.inverse_mass[i] /= factor;
    s.inverse_inertia[i] /= factor;
  }
  for (std::size_t c = 0; c < clumps.size(); ++c) {
    clumps.mass[c] *= factor;
    for (int k = 0; k < 3; ++k) {
      clumps.rotation[c].principal_inertia[k] *= factor;
      clumps.rotation[c].body_angular_momentum[k] *= factor;
    }
  }
}

// Σ of the volumes the bed's solid fraction is by (press.solid_fraction_volume): the bodies' in
// the bed (BodyTemplate::body_volume) or their shapes'.
double stated_solid_volume(const std::vector<PackedBody>& bodies, const PackRequest& request) {
  const bool shape = request.solid_fraction_volume == SolidVolume::shape;
  double v = 0.0;
  for (const PackedBody& b : bodies)
    v += shape ? b.shape_volume : b.body_volume;
  return v;
}

// The bodies drawn and inserted in a region above the floor, and placed as the engine's
// particles: every body rigid while it is packed, a sphere body a sphere, the others clumps of
// their scaled template's mass properties. Sub-sphere i of the engine is particle i of `placed`.
struct InsertedBodies {
  std::vector<PackedBody> bodies;
  BodyPacking placed;
  double region_top = 0.0;  // m, the top of the insertion region
};

InsertedBodies insert_bed(const PackRequest& request, const std::vector<BodyTemplate>& templates) {
  InsertedBodies inserted;
  inserted.bodies = draw_bodies(request, templates);
  inserted.region_top = insert_bodies(request, templates, inserted.bodies);
  spdlog::info("pack: {} bodies inserted below {:.4g} m", inserted.bodies.size(),
               inserted.region_top);
  if (request.insertion == Insertion::deposit) {
    DepositionMoves moves;
    moves.seed = request.seed;
    inserted.region_top = deposit_bodies(templates, inserted.bodies,
                                         Box{request.box_x, request.box_y}, request.floor, moves);
    spdlog::info("pack: {} bodies laid down below {:.4g} m", inserted.bodies.size(),
                 inserted.region_top);
  }
  inserted.placed.templates = templates;
  inserted.placed.bodies = inserted.bodies;
  place_bodies(inserted.placed);
  return inserted;
}

// The step of `bed` at `density`, for bodies as fast as `speed`.
TimeStepChoice packed_time_step(const PackRequest& request, const Bed& bed, double density,
                                double speed, const MaterialTable& table) {
  PackRequest at = request;
  at.density = density;
  TimeStepChoice step =
      select_time_step(bed.state, pack_materials(at, request.friction, request.wall_friction), {1},
                       request.time_step, request.time_step_fraction, speed, BondSet{}, bed.clumps);
  if (!request.time_step && !bed.clumps.empty()) {
    step.clump_period = packed_clump_period(bed.state, bed.clumps, table);
    // A sub-sphere of a rigid body has no motion of its own, so its Rayleigh time (a wave
    // across it) bounds nothing: the body's contact oscillation does. Free spheres keep theirs.
    const bool all_rigid = std::all_of(bed.clumps.clump_of.begin(), bed.clumps.clump_of.end(),
                                       [](std::int32_t c) { return c >= 0; });
    step.time_step =
        request.time_step_fraction *
        (all_rigid ? step.clump_period : std::min(step.rayleigh_time, step.clump_period));
  }
  return step;
}

// The bed at the true density and at the settle's scaled one (settle.density_scale), each with
// its step; the scaled bed is made only when the settle is scaled.
struct DensityBeds {
  Bed bed, settle_bed;
  TimeStepChoice step, settle_step;
};

DensityBeds density_beds(const PackRequest& request, const BodyPacking& placed, double speed,
                         const MaterialTable& table) {
  const double mass_scale = request.settle_density_scale;
  DensityBeds beds;
  beds.bed = bed_from_packing(placed, {request.density, 0, std::nullopt, true});
  beds.step = packed_time_step(request, beds.bed, request.density, speed, table);
  if (mass_scale != 1.0)
    beds.settle_bed =
        bed_from_packing(placed, {request.density * mass_scale, 0, std::nullopt, true});
  beds.settle_step =
      mass_scale == 1.0
          ? beds.step
          : packed_time_step(request, beds.settle_bed, request.density * mass_scale, speed, table);
  return beds;
}

// Gravity, and a neighbour-list skin of a fifth of the smallest sub-sphere's radius.
EngineSettings pack_settings(const PackRequest& request, const SphereState& state) {
  double smallest = std::numeric_limits<double>::infinity();
  for (double radius : state.radius)
    smallest = std::min(smallest, radius);
  EngineSettings settings;
  settings.gravity = {0.0, 0.0, -request.gravity};
  settings.skin = 0.2 * smallest;
  return settings;
}

// What the phases run to: the kinetic energy of rest, the phases' shortest times and drags, the
// punch's speed, the gap it presses to and where it is parked, and the steps and materials.
struct PhasePlan {
  double mass_scale = 1.0;
  MaterialTable table;
  double time_step = 0.0;         // s, at the true density
  double settle_time_step = 0.0;  // s, at the scaled one
  double rest = 0.0;              // J, at the true density
  double free_fall = 0.0;         // s, the settle's shortest time
  double release_min_time = 0.0, release_drag_time = 0.0;
  double press_speed = 0.0;   // m/s
  double area = 0.0;          // m², the box's
  double gap = 0.0;           // m, the punch's target above the floor (0: no press)
  double parked_punch = 0.0;  // m, the punch's position outside the press
};

PhasePlan phase_plan(const PackRequest& request, const std::vector<PackedBody>& bodies,
                     const DensityBeds& beds, MaterialTable table, double fall,
                     double parked_punch) {
  const double mass_scale = request.settle_density_scale;
  double rest = 0.0;  // Σ m g d: KE below ratio × this is rest, m the body's mass in the engine
  for (const PackedBody& b : bodies)
    rest += request.density * b.body_volume * request.gravity *
            std::cbrt(6.0 * b.shape_volume / std::numbers::pi);
  rest *= request.kinetic_energy_ratio;
  // The bed released from the scaled weight's deeper overlaps springs back by a few per cent of
  // a sub-sphere's radius, a small motion of the whole bed: its kinetic energy is judged after
  // some contact periods at the true density, and a drag of about a hundred contact periods
  // (damping the bed's slowest modes, not the contacts') brings it to rest where settle's
  // τ, long against the fall, would take a few τ.
  const double contact_period = beds.step.time_step / request.time_step_fraction;
  const double release_min_time = 20.0 * contact_period;
  const double release_drag_time =
      request.damping_time > 0.0 ? std::min(request.damping_time, 100.0 * contact_period) : 0.0;
  const double press_speed = request.punch_speed / std::sqrt(mass_scale);
  const double free_fall = std::sqrt(2.0 * fall / request.gravity);
  const double area = request.box_x * request.box_y;
  const double gap = request.target_solid_fraction ? stated_solid_volume(bodies, request) /
                                                         (area * *request.target_solid_fraction)
                                                   : 0.0;
  return PhasePlan{mass_scale,
                   std::move(table),
                   beds.step.time_step,
                   beds.settle_step.time_step,
                   rest,
                   free_fall,
                   release_min_time,
                   release_drag_time,
                   press_speed,
                   area,
                   gap,
                   parked_punch};
}

// The phase's materials: frictionless by default while pressing, so the bodies slide into a
// denser bed, as DEM fills are made.
MaterialTable phase_materials(const PackRequest& request, const PhasePlan& plan, PackPhase phase) {
  return phase == PackPhase::press
             ? pack_materials(request, request.press_friction, request.press_friction)
             : plan.table;
}

// The engine of the phase running now, and where the run is in its phases.
struct PhaseEngine {
  std::unique_ptr<Engine> engine;
  PackPhaseState state;
};

// The next phase on the same bed, walls and contact history; the release at the true density
// and its step (velocities kept, spins kept by scaling the angular momenta with the inertias).
void next_phase(PhaseEngine& run, const PackRequest& request, const PhasePlan& plan,
                PackPhase phase) {
  SphereState s = run.engine->state();
  EngineCheckpoint checkpoint = run.engine->checkpoint();
  EngineSettings next = run.engine->settings();
  if (phase == PackPhase::release) {
    scale_masses(s, checkpoint.clumps, 1.0 / plan.mass_scale);
    next.time_step = plan.time_step;
  }
  run.engine =
      std::make_unique<Engine>(std::move(s), run.engine->box(),
                               phase_materials(request, plan, phase), next, std::move(checkpoint));
  run.state.phase = phase;
  run.state.phase_start = run.engine->time();
  run.state.phase_step = 0;
}

constexpr auto keep_going = [] { return true; };

// Each phase runs the engine until it ends and starts the next; each returns whether the run is
// done (finished or interrupted: PackRun::interrupted).

// The pour settles under gravity (at the scaled weight), then is pressed, released or done.
bool settle_phase(PhaseEngine& run, const PackRequest& request, const PhasePlan& plan,
                  const std::vector<PackedBody>& bodies, const PackProgress& progress,
                  PackRun& result) {
  const PhaseEnd end = run_phase(*run.engine,
                                 until_rest(plan.free_fall, request.max_settle_time,
                                            plan.rest * plan.mass_scale, request.damping_time),
                                 progress, run.state, keep_going);
  if (end == PhaseEnd::interrupted) {
    result.interrupted = true;
    return true;
  }
  PackPhaseState& state = run.state;
  state.settled = end == PhaseEnd::rest;
  state.settled_solid_fraction =
      stated_solid_volume(bodies, request) /
      (plan.area * (bed_top(run.engine->state(), request.floor) - request.floor));
  spdlog::info("pack: settled at solid fraction {:.4f} by {} volume", state.settled_solid_fraction,
               solid_volume_name(request.solid_fraction_volume));
  if (!request.target_solid_fraction) {
    if (plan.mass_scale == 1.0) return true;
    next_phase(run, request, plan, PackPhase::release);
    return false;
  }
  if (state.settled_solid_fraction >= *request.target_solid_fraction)
    spdlog::warn(
        "pack: the bed settled denser ({:.4f} by {} volume) than press.solid_fraction = "
        "{}: the punch does not touch it, and the bed is stated as settled, not "
        "pre-compressed",
        state.settled_solid_fraction, solid_volume_name(request.solid_fraction_volume),
        *request.target_solid_fraction);
  next_phase(run, request, plan, PackPhase::press);
  PlaneWall& punch = run.engine->walls()[1];
  punch.position = std::max(bed_top(run.engine->state(), request.floor), request.floor + plan.gap);
  run.engine->rebase_energy();
  return false;
}

// The punch presses the bed to the target gap, then goes back to where it was parked.
bool press_phase(PhaseEngine& run, const PackRequest& request, const PhasePlan& plan,
                 const std::vector<PackedBody>& bodies, const PackProgress& progress,
                 PackRun& result) {
  Engine& engine = *run.engine;
  const double dt = plan.settle_time_step;
  PhaseEnd end = PhaseEnd::rest;
  try {
    end = run_phase(engine,
                    until_rest(std::numeric_limits<double>::infinity(), request.max_settle_time,
                               0.0, request.damping_time),
                    progress, run.state, [&] {
                      PlaneWall& p = engine.walls()[1];
                      if (p.position - request.floor <= plan.gap) {
                        p.velocity = 0.0;
                        return false;
                      }
                      p.velocity = -plan.press_speed;
                      p.position =
                          std::max(request.floor + plan.gap, p.position - plan.press_speed * dt);
                      return true;
                    });
  } catch (const ComputationError& e) {
    // Rigid bodies that cannot rearrange (a single layer, a jammed bed) stop the punch
    // short of the target: it then drives a sub-sphere into its neighbour until the
    // overlap check trips. The target is what cannot be had.
    const double reached = stated_solid_volume(bodies, request) /
                           (plan.area * (engine.walls()[1].position - request.floor));
    throw InputError(fmt::format(
        "pack: the press jammed at a solid fraction of {:.4f} by {} volume, short of "
        "press.solid_fraction = {}: the rigid bodies cannot be pressed further without "
        "overlapping ({}); lower press.solid_fraction, or pack more bodies so that they "
        "can rearrange",
        reached, solid_volume_name(request.solid_fraction_volume), *request.target_solid_fraction,
        e.what()));
  }
  if (end == PhaseEnd::interrupted) {
    result.interrupted = true;
    return true;
  }
  // Where the punch stopped is the bed's solid fraction only if it reached the bed.
  if (run.state.settled_solid_fraction < *request.target_solid_fraction)
    run.state.precompression_solid_fraction =
        stated_solid_volume(bodies, request) /
        (plan.area * (engine.walls()[1].position - request.floor));
  // Release: the punch back to where it was parked; the bed relaxes under gravity.
  engine.walls()[1].velocity = 0.0;
  engine.walls()[1].position = plan.parked_punch;
  next_phase(run, request, plan, PackPhase::relax);
  return false;
}

// The pressed bed relaxes under gravity (at the scaled weight), then is released or done.
bool relax_phase(PhaseEngine& run, const PackRequest& request, const PhasePlan& plan,
                 const PackProgress& progress, PackRun& result) {
  const PhaseEnd end = run_phase(
      *run.engine,
      until_rest(0.0, request.max_settle_time, plan.rest * plan.mass_scale, request.damping_time),
      progress, run.state, keep_going);
  result.interrupted = end == PhaseEnd::interrupted;
  run.state.settled = run.state.settled && end == PhaseEnd::rest;
  if (plan.mass_scale == 1.0 || result.interrupted) return true;
  next_phase(run, request, plan, PackPhase::release);
  return false;
}

// The bed at its true weight comes to rest under the release's drag.
bool release_phase(PhaseEngine& run, const PackRequest& request, const PhasePlan& plan,
                   const PackProgress& progress, PackRun& result) {
  const PhaseEnd end = run_phase(
      *run.engine,
      until_rest(plan.release_min_time, request.max_settle_time, plan.rest, plan.release_drag_time),
      progress, run.state, keep_going);
  result.interrupted = end == PhaseEnd::interrupted;
  run.state.settled = run.state.settled && end == PhaseEnd::rest;
  return true;
}

// The bodies where the engine left them, as a packing measured against the size distribution.
BodyPacking packed_bed(const PackRequest& request, const std::vector<BodyTemplate>& templates,
                       std::vector<PackedBody> bodies, const BodyPacking& placed,
                       const Engine& engine) {
  const SphereState& s = engine.state();
  const ClumpSet& clumps = engine.clumps();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const auto i = static_cast<std::size_t>(placed.first_particle[b]);
    if (clumps.empty() || clumps.clump_of[i] < 0) {
      bodies[b].centre = {s.position.x[i], s.position.y[i], s.position.z[i]};
      continue;
    }
    const auto c = static_cast<std::size_t>(clumps.clump_of[i]);
    bodies[b].centre = {clumps.centre.x[c], clumps.centre.y[c], clumps.centre.z[c]};
    bodies[b].orientation = clumps.rotation[c].orientation;
  }
  BodyPacking packing;
  packing.templates = templates;
  packing.bodies = std::move(bodies);
  packing.box = Box{request.box_x, request.box_y};
  packing.floor = request.floor;
  place_bodies(packing);
  packing.top = bed_top(engine.state(), request.floor);
  const SizeTable target = size_table(request.sizes, request.diameter_min, request.diameter_max);
  packing.measures = measure_packing(packing, target, request.sizes.volume_weighted);
  return packing;
}

}  // namespace

double bed_top(const SphereState& state, double floor) {
  double top = floor;
  for (std::size_t i = 0; i < state.size(); ++i)
    top = std::max(top, state.position.z[i] + state.radius[i]);
  return top;
}

SphereState pour(const Pour& request, const SphereList& given, ClumpSet& clumps) {
  SphereState state = make_state(
      request.spheres ? in_cell_order(insert_random_spheres(request.box, *request.spheres),
                                      request.spheres->diameter_max)
                      : given,
      request.density, request.material);
  if (request.clumps)
    insert_clumps(state, clumps, request.box, *request.clumps, request.density, request.material);
  return state;
}

std::optional<SphereState> settle_for_time(SphereState state, ClumpSet& clumps,
                                           std::vector<Material> materials,
                                           std::vector<Interaction> interactions,
                                           const TimedSettle& request,
                                           SettleCheckpoints checkpoints) {
  if (request.friction)  // a denser fill: settle with other friction, press with the real one
    for (Interaction& in : interactions)
      in.sliding_friction = in.rolling_friction = *request.friction;
  EngineSettings settings = request.settings;
  if (settings.gravity == std::array<double, 3>{0.0, 0.0, 0.0}) settings.gravity = {0, 0, -9.81};
  const MaterialTable table(materials, interactions);
  Engine engine = checkpoints.resume
                      ? Engine(std::move(checkpoints.resume->state), checkpoints.resume->box, table,
                               settings, std::move(checkpoints.resume->checkpoint))
                      : Engine(std::move(state), request.box, table, request.walls, settings, {},
                               std::move(clumps));
  const auto steps = static_cast<std::int64_t>(std::ceil(request.settle_time / settings.time_step));
  spdlog::info("settling {} spheres ({} in {} rigid clumps) under gravity for {} steps",
               engine.state().size(),
               engine.clumps().empty() ? 0 : engine.clumps().member_start.back(),
               engine.clumps().size(), steps);
  // pack's settle phase from the start of the engine's steps (a resumed settle at its step).
  PackPhaseState phase;
  phase.phase_step = engine.step_index();
  PackProgress progress;
  if (checkpoints.after_step)
    progress.after_step = [&](const Engine& e, const PackPhaseState&) {
      return checkpoints.after_step(e);
    };
  if (run_phase(engine, after_steps(steps), progress, phase, keep_going) == PhaseEnd::interrupted)
    return std::nullopt;
  SphereState settled = engine.state();
  settled.velocity.resize(settled.size());
  settled.angular_velocity.resize(settled.size());
  clumps = engine.clumps();  // at rest too: no velocity, no angular momentum
  clumps.velocity.resize(clumps.size());
  for (RigidRotation& r : clumps.rotation)
    r.body_angular_momentum = {0.0, 0.0, 0.0};
  return settled;
}

PackRun pack(const PackRequest& request, const std::vector<BodyTemplate>& templates,
             const PackProgress& progress, std::optional<PackResume> resume) {
  PackRun run;
  InsertedBodies inserted = insert_bed(request, templates);
  const double region_top = inserted.region_top;
  const double mass_scale = request.settle_density_scale;
  const MaterialTable table = pack_materials(request, request.friction, request.wall_friction);
  std::vector<PlaneWall> walls = {
      PlaneWall{request.floor, 1, 0.0, 1},
      PlaneWall{region_top + 0.01 * (region_top - request.floor), -1, 0.0, 1}};
  const double fall = region_top - request.floor;
  const double speed = std::sqrt(2.0 * request.gravity * fall) + request.punch_speed;
  DensityBeds beds = density_beds(request, inserted.placed, speed, table);
  const TimeStepChoice& step = beds.step;
  run.time_step = step.time_step;
  run.settle_time_step = beds.settle_step.time_step;
  EngineSettings settings = pack_settings(request, beds.bed.state);
  spdlog::info(
      "pack: {} sub-spheres in {} bodies, time step {:.3g} s (Rayleigh {:.3g} s, clump "
      "bound {:.3g} s)",
      beds.bed.state.size(), inserted.bodies.size(), step.time_step, step.rayleigh_time,
      step.clump_period);
  if (mass_scale != 1.0)
    spdlog::info("pack: the settle at {} × density, time step {:.3g} s", mass_scale,
                 beds.settle_step.time_step);
  const PhasePlan plan = phase_plan(request, inserted.bodies, beds, table, fall, walls[1].position);
  PhaseEngine phases;
  phases.state = resume ? resume->phase : PackPhaseState{};
  const bool scaled_now = mass_scale != 1.0 && phases.state.phase != PackPhase::release;
  settings.time_step = scaled_now ? beds.settle_step.time_step : step.time_step;
  Bed& start = scaled_now ? beds.settle_bed : beds.bed;
  phases.engine =
      resume ? std::make_unique<Engine>(std::move(resume->snapshot.state), resume->snapshot.box,
                                        phase_materials(request, plan, phases.state.phase),
                                        settings, std::move(resume->snapshot.checkpoint))
             : std::make_unique<Engine>(std::move(start.state), Box{request.box_x, request.box_y},
                                        table, walls, settings, BondSet{}, std::move(start.clumps));

  const auto started = std::chrono::steady_clock::now();
  const std::int64_t first_step = phases.engine->step_index();
  const std::vector<PackedBody>& bodies = inserted.bodies;
  for (bool done = false; !done;) {
    switch (phases.state.phase) {
      case PackPhase::settle:
        done = settle_phase(phases, request, plan, bodies, progress, run);
        break;
      case PackPhase::press:
        done = press_phase(phases, request, plan, bodies, progress, run);
        break;
      case PackPhase::relax:
        done = relax_phase(phases, request, plan, progress, run);
        break;
      case PackPhase::release:
        done = release_phase(phases, request, plan, progress, run);
        break;
    }
  }
  const Engine& engine = *phases.engine;
  run.settled = phases.state.settled;
  run.settled_solid_fraction = phases.state.settled_solid_fraction;
  run.precompression_solid_fraction = phases.state.precompression_solid_fraction;
  run.loop_steps = engine.step_index() - first_step;
  run.loop_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  run.steps = engine.step_index();
  if (run.interrupted) return run;
  run.packing = packed_bed(request, templates, std::move(inserted.bodies), inserted.placed, engine);
  return run;
}

namespace {

// Pairs of sub-spheres of different bodies that overlap, by a cell grid periodic in x and y.
template <class Visit>
void overlapping_pairs(const BodyPacking& p, Visit&& visit) {
  const SphereList& s = p.particles;
  const std::size_t n = s.size();
  if (n == 0) return;
  const double r_max = *std::max_element(s.radius.begin(), s.radius.end());
  const double cell = 2.0 * r_max;
  const int nx = std::max(1, static_cast<int>(p.box.length_x / cell));
  const int ny = std::max(1, static_cast<int>(p.box.length_y / cell));
  double z_low = s.z[0], z_high = s.z[0];
  for (std::size_t i = 0; i < n; ++i)
    z_low = std::min(z_low, s.z[i]), z_high = std::max(z_high, s.z[i]);
  const int nz = std::max(1, static_cast<int>((z_high - z_low) / cell) + 1);
  const auto wrap = [](double x, double length) { return x - length * std::floor(x / length); };
  std::map<std::int64_t, std::vector<std::size_t>> cells;
  const auto key = [&](int ix, int iy, int iz) {
    return (static_cast<std::int64_t>(iz) * ny + iy) * nx + ix;
  };
  std::vector<std::array<int, 3>> at(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int ix =
        std::min(nx - 1, static_cast<int>(wrap(s.x[i], p.box.length_x) / p.box.length_x * nx));
    const int iy =
        std::min(ny - 1, static_cast<int>(wrap(s.y[i], p.box.length_y) / p.box.length_y * ny));
    const int iz = std::min(nz - 1, static_cast<int>((s.z[i] - z_low) / cell));
    at[i] = {ix, iy, iz};
    cells[key(ix, iy, iz)].push_back(i);
  }
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<std::int64_t> seen;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int iz = at[i][2] + dz;
          if (iz < 0 || iz >= nz) continue;
          const int ix = (at[i][0] + dx + nx) % nx, iy = (at[i][1] + dy + ny) % ny;
          const std::int64_t k = key(ix, iy, iz);
          if (std::find(seen.begin(), seen.end(), k) != seen.end()) continue;
          seen.push_back(k);
          const auto it = cells.find(k);
          if (it == cells.end()) continue;
          for (std::size_t j : it->second) {
            if (j <= i || p.particle_body[i] == p.particle_body[j]) continue;
            double ddx = s.x[j] - s.x[i], ddy = s.y[j] - s.y[i];
            ddx -= p.box.length_x * std::nearbyint(ddx / p.box.length_x);
            ddy -= p.box.length_y * std::nearbyint(ddy / p.box.length_y);
            const double d =
                std::sqrt(ddx * ddx + ddy * ddy + (s.z[j] - s.z[i]) * (s.z[j] - s.z[i]));
            const double overlap = s.radius[i] + s.radius[j] - d;
            if (overlap > 0.0) visit(i, j, overlap);
          }
        }
  }
}

}  // namespace

PackMeasures measure_packing(const BodyPacking& p, const SizeTable& target, bool volume_weighted) {
  PackMeasures m;
  const SphereList& s = p.particles;
  double top = p.floor;
  for (std::size_t i = 0; i < s.size(); ++i) {
    top = std::max(top, s.z[i] + s.radius[i]);
    const double wall_overlap = p.floor - (s.z[i] - s.radius[i]);
    if (wall_overlap > m.largest_overlap) m.largest_overlap = wall_overlap;
    m.largest_overlap_relative = std::max(m.largest_overlap_relative, wall_overlap / s.radius[i]);
  }
  m.bed_height = top - p.floor;
  double body = 0.0, shape = 0.0, spheres = 0.0;
  std::vector<double> diameters;
  double order = 0.0;
  std::size_t oriented = 0;
  for (const PackedBody& b : p.bodies) {
    body += b.body_volume, shape += b.shape_volume, spheres += b.sphere_volume;
    diameters.push_back(std::cbrt(6.0 * b.shape_volume / std::numbers::pi));
    const BodyTemplate& t = p.templates[static_cast<std::size_t>(b.template_index)];
    if (t.kind == BodyKind::sphere) continue;
    // The long axis: the principal axis of the smallest moment.
    const auto k = static_cast<std::size_t>(
        std::min_element(t.principal_inertia.begin(), t.principal_inertia.end()) -
        t.principal_inertia.begin());
    Vector3 axis = {0.0, 0.0, 0.0};
    axis[k] = 1.0;
    const double c = rotate_to_world(b.orientation, axis)[2];
    order += 0.5 * (3.0 * c * c - 1.0);
    ++oriented;
  }
  const double bed_volume = p.box.length_x * p.box.length_y * m.bed_height;
  m.solid_fraction = bed_volume > 0.0 ? body / bed_volume : 0.0;
  m.solid_fraction_shape = bed_volume > 0.0 ? shape / bed_volume : 0.0;
  m.solid_fraction_spheres = bed_volume > 0.0 ? spheres / bed_volume : 0.0;
  m.orientation_order = oriented > 0 ? order / static_cast<double>(oriented) : 0.0;
  m.x10 = sample_quantile(diameters, 0.1, volume_weighted);
  m.x50 = sample_quantile(diameters, 0.5, volume_weighted);
  m.x90 = sample_quantile(diameters, 0.9, volume_weighted);
  m.target_x10 = size_quantile(target, 0.1, volume_weighted);
  m.target_x50 = size_quantile(target, 0.5, volume_weighted);
  m.target_x90 = size_quantile(target, 0.9, volume_weighted);
  std::vector<std::pair<std::int32_t, std::int32_t>> touching;
  overlapping_pairs(p, [&](std::size_t i, std::size_t j, double overlap) {
    m.largest_overlap = std::max(m.largest_overlap, overlap);
    m.largest_overlap_relative =
        std::max(m.largest_overlap_relative, overlap / std::min(s.radius[i], s.radius[j]));
    touching.emplace_back(std::min(p.particle_body[i], p.particle_body[j]),
                          std::max(p.particle_body[i], p.particle_body[j]));
  });
  std::sort(touching.begin(), touching.end());
  touching.erase(std::unique(touching.begin(), touching.end()), touching.end());
  m.coordination = p.bodies.empty() ? 0.0
                                    : 2.0 * static_cast<double>(touching.size()) /
                                          static_cast<double>(p.bodies.size());
  return m;
}

}  // namespace shapepress::packing
