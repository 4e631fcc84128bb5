#include "simulate/snapshot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>

#include "common/atomic_file.hpp"
#include "common/config.hpp"
#include "common/error.hpp"
#include "common/hdf5_file.hpp"

namespace shapepress::simulate {
namespace {

std::vector<double> interleave(const Vec3Array& v) {
  std::vector<double> out(3 * v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    out[3 * i] = v.x[i];
    out[3 * i + 1] = v.y[i];
    out[3 * i + 2] = v.z[i];
  }
  return out;
}

Vec3Array split(const std::vector<double>& values) {
  Vec3Array v;
  const std::size_t n = values.size() / 3;
  v.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    v.x[i] = values[3 * i];
    v.y[i] = values[3 * i + 1];
    v.z[i] = values[3 * i + 2];
  }
  return v;
}

std::vector<double> history_values(const std::vector<ContactHistory>& history) {
  std::vector<double> out;
  out.reserve(3 * history.size());
  for (const ContactHistory& h : history)
    out.insert(out.end(), h.tangential, h.tangential + 3);
  return out;
}

std::vector<ContactHistory> history_from(const std::vector<double>& values) {
  std::vector<ContactHistory> out(values.size() / 3);
  for (std::size_t k = 0; k < out.size(); ++k)
    for (int c = 0; c < 3; ++c)
      out[k].tangential[c] = values[3 * k + c];
  return out;
}

// One normal-law history field (normal_laws.hpp) of every contact: `slot` in
// ContactHistory::normal, 0 for contacts whose law does not keep it.
std::vector<double> normal_history_values(const std::vector<ContactHistory>& history,
                                          std::size_t slot) {
  std::vector<double> out;
  out.reserve(history.size());
  for (const ContactHistory& h : history)
    out.push_back(h.normal[slot]);
  return out;
}

// Calls f(slot, field) for every history field of every registered normal law.
template <class F>
void for_each_history_field(F&& f) {
  for_each_normal_law([&]<class Law>() {
    for (std::size_t k = 0; k < Law::history_fields.size(); ++k)
      f(normal_history_offset<Law> + k, Law::history_fields[k]);
  });
}

// A snapshot written before a law existed has none of its history: it is zero.
void read_normal_history(const H5Reader& file, const std::string& prefix,
                         std::vector<ContactHistory>& history, const std::filesystem::path& path) {
  for_each_history_field([&](std::size_t slot, const HistoryField& field) {
    const std::string name = prefix + field.name;
    if (!file.has(name)) return;
    const std::vector<double> values = file.doubles(name);
    if (values.size() != history.size())
      throw InputError("'" + path.string() + "': " + name + " does not match the contacts");
    for (std::size_t k = 0; k < values.size(); ++k)
      history[k].normal[slot] = values[k];
  });
}

void write_vec3(H5Writer& file, const std::string& name, const Vec3Array& v,
                std::string_view unit) {
  file.write(name, interleave(v), {v.size(), 3});
  file.unit(name, unit);
}

void write_with_unit(H5Writer& file, const std::string& name, std::span<const double> values,
                     std::string_view si_unit) {
  file.write(name, values);
  file.unit(name, si_unit);
}

void write_normal_history(H5Writer& file, const std::string& prefix,
                          const std::vector<ContactHistory>& history) {
  for_each_history_field([&](std::size_t slot, const HistoryField& field) {
    write_with_unit(file, prefix + field.name, normal_history_values(history, slot), field.unit);
  });
}

// The bonds and their history (/bonds): everything BondSet holds but the per-step results and
// the gather index, which are rebuilt. Pairs as (B, 2) so the XDMF sidecar draws them as lines.
void write_bonds(H5Writer& file, const BondSet& b) {
  if (b.empty()) return;
  std::vector<std::int32_t> pairs;
  pairs.reserve(2 * b.size());
  for (std::size_t k = 0; k < b.size(); ++k)
    pairs.insert(pairs.end(), {b.first[k], b.second[k]});
  file.write("/bonds/pairs", pairs, {b.size(), 2});
  write_with_unit(file, "/bonds/radius", b.radius, "m");
  write_with_unit(file, "/bonds/normal_spring", b.normal_spring, "N/m");
  write_with_unit(file, "/bonds/shear_spring", b.shear_spring, "N/m");
  write_with_unit(file, "/bonds/twist_spring", b.twist_spring, "N m");
  write_with_unit(file, "/bonds/bend_spring", b.bend_spring, "N m");
  write_with_unit(file, "/bonds/tensile_strength", b.tensile_strength, "Pa");
  write_with_unit(file, "/bonds/shear_strength", b.shear_strength, "Pa");
  file.write("/bonds/damping_ratio", b.damping_ratio);
  const BondSet::History& h = b.history;
  write_with_unit(file, "/bonds/length", h.length, "m");
  write_with_unit(file, "/bonds/normal_force", h.normal_force, "N");
  write_vec3(file, "/bonds/shear_force", h.shear_force, "N");
  write_with_unit(file, "/bonds/twist_moment", h.twist_moment, "N m");
  write_vec3(file, "/bonds/bend_moment", h.bend_moment, "N m");
  file.write("/bonds/intact", b.intact);
  file.attribute("/bonds", "contact_when_bonded", std::int64_t{b.contact_when_bonded ? 1 : 0});
  // The bond model (bond_models.hpp) as its [bond] lines, and its history one dataset per field:
  // none for the default elastic model, whose snapshots stay as they were.
  const std::string model = bond_model_toml(b.model);
  if (!model.empty()) file.attribute("/bonds", "model", model);
  const std::vector<HistoryField> fields = bond_model_history_fields(b.model);
  for (std::size_t k = 0; k < fields.size(); ++k)
    write_with_unit(file, std::string("/bonds/") + fields[k].name, h.model_fields[k],
                    fields[k].unit);
}

BondSet read_bonds(const H5Reader& file) {
  BondSet b;
  if (!file.has("/bonds/pairs")) return b;
  const std::vector<std::int32_t> pairs = file.int32s("/bonds/pairs");
  for (std::size_t k = 0; k + 1 < pairs.size(); k += 2) {
    b.first.push_back(pairs[k]);
    b.second.push_back(pairs[k + 1]);
  }
  b.radius = file.doubles("/bonds/radius");
  b.normal_spring = file.doubles("/bonds/normal_spring");
  b.shear_spring = file.doubles("/bonds/shear_spring");
  b.twist_spring = file.doubles("/bonds/twist_spring");
  b.bend_spring = file.doubles("/bonds/bend_spring");
  b.tensile_strength = file.doubles("/bonds/tensile_strength");
  b.shear_strength = file.doubles("/bonds/shear_strength");
  b.damping_ratio = file.doubles("/bonds/damping_ratio");
  BondSet::History& h = b.history;
  h.length = to_sphere_array(file.doubles("/bonds/length"));
  h.normal_force = to_sphere_array(file.doubles("/bonds/normal_force"));
  h.shear_force = split(file.doubles("/bonds/shear_force"));
  h.twist_moment = to_sphere_array(file.doubles("/bonds/twist_moment"));
  h.bend_moment = split(file.doubles("/bonds/bend_moment"));
  b.intact = file.uint8s("/bonds/intact");
  b.contact_when_bonded = file.attribute_int64("/bonds", "contact_when_bonded") != 0;
  const std::size_t n = b.size();
  // A snapshot without a model attribute holds elastic bonds (written before models existed, or
  // by the default); one without a history field's dataset has none of that history: zeros.
  if (file.has_attribute("/bonds", "model"))
    b.model = read_bond_model(
        ConfigTable::parse(file.attribute_string("/bonds", "model"), file.path().string()),
        "'" + file.path().string() + "': /bonds model");
  const std::vector<HistoryField> fields = bond_model_history_fields(b.model);
  for (std::size_t k = 0; k < bond_model_history_size; ++k) {
    const std::string name =
        k < fields.size() ? std::string("/bonds/") + fields[k].name : std::string();
    h.model_fields[k] = k < fields.size() && file.has(name) ? to_sphere_array(file.doubles(name))
                                                            : SphereArray<double>(n, 0.0);
    if (h.model_fields[k].size() != n)
      throw InputError("'" + file.path().string() + "': " + name + " does not match the bonds");
  }
  for (std::size_t size :
       {b.radius.size(), b.normal_spring.size(), b.shear_spring.size(), b.twist_spring.size(),
        b.bend_spring.size(), b.tensile_strength.size(), b.shear_strength.size(),
        b.damping_ratio.size(), h.length.size(), h.normal_force.size(), h.twist_moment.size(),
        h.shear_force.size(), h.bend_moment.size(), b.intact.size()})
    if (size != n)
      throw InputError("'" + file.path().string() + "': /bonds datasets differ in length");
  return b;
}

// The clumps (/clumps): bodies with their motion and last force and torque, and the sub-sphere
// offsets; the derived arrays (clump_of, arms) are rebuilt. For ParaView, each body frame as
// three line cells from the centre along the principal axes (axis 0 the smallest moment), as
// long as the clump's reach.
void write_clumps(H5Writer& file, const ClumpSet& k) {
  if (k.empty()) return;
  const std::size_t n = k.size();
  std::vector<std::int32_t> range;
  std::vector<double> orientation, momentum, inertia, omega, axis_points;
  std::vector<std::int32_t> axis_lines, axis_id;
  for (std::size_t c = 0; c < n; ++c) {
    range.insert(range.end(), {k.first[c], k.last[c]});
    const RigidRotation& r = k.rotation[c];
    orientation.insert(orientation.end(),
                       {r.orientation.w, r.orientation.x, r.orientation.y, r.orientation.z});
    momentum.insert(momentum.end(), r.body_angular_momentum.begin(), r.body_angular_momentum.end());
    inertia.insert(inertia.end(), r.principal_inertia.begin(), r.principal_inertia.end());
    const Vector3 w = k.angular_velocity(c);
    omega.insert(omega.end(), w.begin(), w.end());
    double reach = 0.0;
    for (std::int32_t m = k.member_start[c]; m < k.member_start[c + 1]; ++m)
      reach = std::max(reach, std::hypot(k.offset.x[m], k.offset.y[m], k.offset.z[m]));
    const Vector3 centre = {k.centre.x[c], k.centre.y[c], k.centre.z[c]};
    const auto base = static_cast<std::int32_t>(4 * c);
    axis_points.insert(axis_points.end(), centre.begin(), centre.end());
    for (int a = 0; a < 3; ++a) {
      Vector3 unit = {0.0, 0.0, 0.0};
      unit[static_cast<std::size_t>(a)] = reach;
      const Vector3 tip = rotate_to_world(r.orientation, unit);
      axis_points.insert(axis_points.end(),
                         {centre[0] + tip[0], centre[1] + tip[1], centre[2] + tip[2]});
      axis_lines.insert(axis_lines.end(), {base, base + 1 + a});
      axis_id.push_back(a);
    }
  }
  file.write("/clumps/range", range, {n, 2});
  write_with_unit(file, "/clumps/mass", k.mass, "kg");
  write_with_unit(file, "/clumps/volume", k.volume, "m^3");
  write_vec3(file, "/clumps/centre", k.centre, "m");
  write_vec3(file, "/clumps/velocity", k.velocity, "m/s");
  write_vec3(file, "/clumps/force", k.force, "N");
  write_vec3(file, "/clumps/torque", k.torque, "N m");
  file.write("/clumps/orientation", orientation, {n, 4});
  file.write("/clumps/body_angular_momentum", momentum, {n, 3});
  file.unit("/clumps/body_angular_momentum", "kg m^2/s");
  file.write("/clumps/principal_inertia", inertia, {n, 3});
  file.unit("/clumps/principal_inertia", "kg m^2");
  file.write("/clumps/angular_velocity", omega, {n, 3});
  file.unit("/clumps/angular_velocity", "rad/s");
  write_vec3(file, "/clumps/offset", k.offset, "m");
  file.write("/clumps/axis_points", axis_points, {4 * n, 3});
  file.write("/clumps/axis_lines", axis_lines, {3 * n, 2});
  file.write("/clumps/axis_id", axis_id);
}

ClumpSet read_clumps(const H5Reader& file) {
  ClumpSet k;
  if (!file.has("/clumps/range")) return k;
  const std::vector<std::int32_t> range = file.int32s("/clumps/range");
  for (std::size_t c = 0; c + 1 < range.size(); c += 2) {
    k.first.push_back(range[c]);
    k.last.push_back(range[c + 1]);
  }
  const std::size_t n = k.first.size();
  k.mass = file.doubles("/clumps/mass");
  k.volume = file.doubles("/clumps/volume");
  k.centre = split(file.doubles("/clumps/centre"));
  k.velocity = split(file.doubles("/clumps/velocity"));
  k.force = split(file.doubles("/clumps/force"));
  k.torque = split(file.doubles("/clumps/torque"));
  k.offset = split(file.doubles("/clumps/offset"));
  const std::vector<double> orientation = file.doubles("/clumps/orientation");
  const std::vector<double> momentum = file.doubles("/clumps/body_angular_momentum");
  const std::vector<double> inertia = file.doubles("/clumps/principal_inertia");
  for (std::size_t size :
       {k.mass.size(), k.volume.size(), k.centre.size(), k.velocity.size(), k.force.size(),
        k.torque.size(), orientation.size() / 4, momentum.size() / 3, inertia.size() / 3})
    if (size != n)
      throw InputError("'" + file.path().string() + "': /clumps datasets differ in length");
  for (std::size_t c = 0; c < n; ++c) {
    RigidRotation r;
    r.orientation = {orientation[4 * c], orientation[4 * c + 1], orientation[4 * c + 2],
                     orientation[4 * c + 3]};
    for (std::size_t a = 0; a < 3; ++a) {
      r.body_angular_momentum[a] = momentum[3 * c + a];
      r.principal_inertia[a] = inertia[3 * c + a];
    }
    k.rotation.push_back(r);
  }
  return k;
}

}  // namespace

void write_snapshot(const std::filesystem::path& path, const Engine& engine,
                    const ScenarioState& scenario, const Provenance& provenance) {
  const SphereState& s = engine.state();
  const std::size_t n = s.size();
  H5Writer file(path, provenance);
  write_vec3(file, "/particles/position", s.position, "m");
  write_vec3(file, "/particles/velocity", s.velocity, "m/s");
  write_vec3(file, "/particles/angular_velocity", s.angular_velocity, "rad/s");
  write_vec3(file, "/particles/force", s.force, "N");
  write_vec3(file, "/particles/torque", s.torque, "N m");
  write_with_unit(file, "/particles/radius", s.radius, "m");
  write_with_unit(file, "/particles/mass", s.mass, "kg");
  file.write("/particles/inverse_mass", s.inverse_mass);
  file.write("/particles/inverse_inertia", s.inverse_inertia);
  file.write("/particles/material", s.material);
  file.write("/particles/body", s.body);
  write_with_unit(file, "/particles/body_radius", s.body_radius, "m");
  const std::vector<std::int32_t> contacts = engine.contacts_per_sphere();
  file.write("/particles/contacts", contacts);
  if (engine.computes_particle_stress()) {
    // Love–Weber stress (xx, yy, zz, xy, xz, yz) and p = -tr σ/3 of the last force evaluation.
    const std::vector<double>& stress = engine.particle_stress();
    file.write("/particles/stress", stress, {n, stress_components});
    file.unit("/particles/stress", "Pa");
    std::vector<double> pressure(n);
    for (std::size_t i = 0; i < n; ++i)
      pressure[i] = engine.particle_pressure(i);
    write_with_unit(file, "/particles/pressure", pressure, "Pa");
  }

  const EngineCheckpoint c = engine.checkpoint();
  file.group("/engine");
  file.attribute("/engine", "step", static_cast<std::int64_t>(c.step));
  file.attribute("/engine", "time", c.time);
  file.attribute("/engine", "energy_reference", c.energy_reference);
  file.attribute("/engine", "work_in", c.work_in);
  file.attribute("/engine", "box_x", engine.box().length_x);
  file.attribute("/engine", "box_y", engine.box().length_y);
  write_vec3(file, "/engine/build_reference", c.build_reference, "m");
  write_with_unit(file, "/engine/build_wall_position", c.build_wall_position, "m");
  file.write("/engine/contact_first", c.first);
  file.write("/engine/contact_second", c.second);
  file.write("/engine/contact_tangential", history_values(c.history), {c.history.size(), 3});
  std::vector<ContactHistory> wall_history;
  for (const auto& w : c.wall_history)
    wall_history.insert(wall_history.end(), w.begin(), w.end());
  file.write("/engine/wall_tangential", history_values(wall_history), {wall_history.size(), 3});
  write_normal_history(file, "/engine/contact_", c.history);
  write_normal_history(file, "/engine/wall_", wall_history);
  write_bonds(file, c.bonds);
  write_clumps(file, c.clumps);
  if (!c.bond_force.empty()) {  // bond sub-steps: the two shares of /particles/force and torque
    file.write("/engine/bond_force", c.bond_force, {6, n});
    file.write("/engine/slow_force", c.slow_force, {6, n});
  }

  // Walls: the state, and each wall as a quad over the box for ParaView.
  const auto& walls = c.walls;
  std::vector<double> position, velocity, force, points;
  std::vector<std::int32_t> facing, material, quads;
  const double lx = engine.box().length_x, ly = engine.box().length_y;
  for (std::size_t k = 0; k < walls.size(); ++k) {
    position.push_back(walls[k].position);
    velocity.push_back(walls[k].velocity);
    force.push_back(c.wall_force[k]);
    facing.push_back(walls[k].facing);
    material.push_back(walls[k].material);
    const double z = walls[k].position;
    const double corners[4][2] = {{0, 0}, {lx, 0}, {lx, ly}, {0, ly}};
    for (int q = 0; q < 4; ++q) {
      points.insert(points.end(), {corners[q][0], corners[q][1], z});
      quads.push_back(static_cast<std::int32_t>(4 * k + q));
    }
  }
  write_with_unit(file, "/walls/position", position, "m");
  file.write("/walls/velocity", velocity);
  file.write("/walls/force", force);
  file.write("/walls/facing", facing);
  file.write("/walls/material", material);
  file.write("/walls/points", points, {4 * walls.size(), 3});
  file.write("/walls/quads", quads, {walls.size(), 4});
  std::vector<std::string> scenario_names;
  std::vector<double> scenario_values;
  for (const auto& [name, value] : scenario) {
    scenario_names.push_back(name);
    scenario_values.push_back(value);
  }
  file.write_strings("/scenario/names", scenario_names);
  file.write("/scenario/values", scenario_values);
  file.attribute("/", "spheres", static_cast<std::int64_t>(n));
  file.attribute("/", "bonds", static_cast<std::int64_t>(c.bonds.size()));
  file.attribute("/", "clumps", static_cast<std::int64_t>(c.clumps.size()));
  file.commit();
}

LoadedSnapshot read_snapshot(const std::filesystem::path& path) {
  H5Reader file(path);
  if (!file.has("/engine") || !file.has("/particles/position"))
    throw InputError("'" + path.string() + "' is not a shapepress snapshot (no /engine group)");
  LoadedSnapshot out;
  SphereState& s = out.state;
  s.position = split(file.doubles("/particles/position"));
  s.velocity = split(file.doubles("/particles/velocity"));
  s.angular_velocity = split(file.doubles("/particles/angular_velocity"));
  s.force = split(file.doubles("/particles/force"));
  s.torque = split(file.doubles("/particles/torque"));
  s.radius = to_sphere_array(file.doubles("/particles/radius"));
  s.mass = to_sphere_array(file.doubles("/particles/mass"));
  s.inverse_mass = to_sphere_array(file.doubles("/particles/inverse_mass"));
  s.inverse_inertia = to_sphere_array(file.doubles("/particles/inverse_inertia"));
  s.material = to_sphere_array(file.int32s("/particles/material"));
  s.body = to_sphere_array(file.int32s("/particles/body"));
  // Absent in a snapshot written before body radii: every sphere its own.
  s.body_radius = file.has("/particles/body_radius")
                      ? to_sphere_array(file.doubles("/particles/body_radius"))
                      : s.radius;
  const std::size_t n = s.radius.size();

  EngineCheckpoint& c = out.checkpoint;
  c.step = file.attribute_int64("/engine", "step");
  c.time = file.attribute_double("/engine", "time");
  c.energy_reference = file.attribute_double("/engine", "energy_reference");
  c.work_in = file.attribute_double("/engine", "work_in");
  out.box =
      Box{file.attribute_double("/engine", "box_x"), file.attribute_double("/engine", "box_y")};
  c.build_reference = split(file.doubles("/engine/build_reference"));
  c.first = file.int32s("/engine/contact_first");
  c.second = file.int32s("/engine/contact_second");
  c.history = history_from(file.doubles("/engine/contact_tangential"));
  read_normal_history(file, "/engine/contact_", c.history, path);
  if (file.has("/particles/pressure")) {  // the p the multi-contact law reads next step
    c.particle_pressure = file.doubles("/particles/pressure");
    if (c.particle_pressure.size() != n)
      throw InputError("'" + path.string() + "': /particles/pressure must have N values");
  }
  const auto position = file.doubles("/walls/position");
  const auto velocity = file.doubles("/walls/velocity");
  const auto facing = file.int32s("/walls/facing");
  const auto material = file.int32s("/walls/material");
  c.wall_force = file.doubles("/walls/force");
  if (file.has("/engine/bond_force")) {
    c.bond_force = file.doubles("/engine/bond_force");
    c.slow_force = file.doubles("/engine/slow_force");
    if (c.bond_force.size() != 6 * n || c.slow_force.size() != 6 * n)
      throw InputError("'" + path.string() +
                       "': /engine/bond_force and slow_force must have 6 N values");
  }
  auto wall_history = history_from(file.doubles("/engine/wall_tangential"));
  read_normal_history(file, "/engine/wall_", wall_history, path);
  if (wall_history.size() != position.size() * n || c.history.size() != c.first.size())
    throw InputError("'" + path.string() + "': contact history does not match the spheres");
  for (std::size_t k = 0; k < position.size(); ++k) {
    c.walls.push_back(PlaneWall{position[k], facing[k], velocity[k], material[k]});
    c.wall_history.emplace_back(wall_history.begin() + static_cast<std::ptrdiff_t>(k * n),
                                wall_history.begin() + static_cast<std::ptrdiff_t>((k + 1) * n));
  }
  // The rebuild test measures against the walls' motion since the last build (Engine::step);
  // snapshots written before it was stored fall back to "no wall motion", the plain test.
  if (file.has("/engine/build_wall_position")) {
    c.build_wall_position = file.doubles("/engine/build_wall_position");
    if (c.build_wall_position.size() != c.walls.size())
      throw InputError("'" + path.string() +
                       "': /engine/build_wall_position must have one value per wall");
  }
  c.bonds = read_bonds(file);
  for (std::size_t k = 0; k < c.bonds.size(); ++k)
    if (c.bonds.first[k] < 0 || c.bonds.second[k] < 0 ||
        static_cast<std::size_t>(c.bonds.second[k]) >= n)
      throw InputError("'" + path.string() + "': bond " + std::to_string(k) +
                       " joins a sphere that is not in the snapshot");
  c.clumps = read_clumps(file);
  c.clumps.index(n);  // InputError when a range leaves the snapshot's spheres
  const std::vector<std::string> scenario_names = file.strings("/scenario/names");
  const std::vector<double> scenario_values = file.doubles("/scenario/values");
  if (scenario_names.size() != scenario_values.size())
    throw InputError("'" + path.string() +
                     "': /scenario/names and /scenario/values differ in length");
  for (std::size_t k = 0; k < scenario_names.size(); ++k)
    out.scenario.emplace_back(scenario_names[k], scenario_values[k]);
  return out;
}

void write_xdmf(const std::filesystem::path& path, const std::vector<SnapshotIndexEntry>& entries) {
  std::string xml =
      "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"
      "  <Grid Name=\"run\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const SnapshotIndexEntry& e : entries) {
    const std::string f = e.file.generic_string();
    const auto item = [&](std::string_view dataset, std::size_t rows, int columns) {
      const std::string dims =
          columns > 1 ? fmt::format("{} {}", rows, columns) : fmt::format("{}", rows);
      return fmt::format(
          "<DataItem Dimensions=\"{}\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">{}:{}"
          "</DataItem>",
          dims, f, dataset);
    };
    xml += fmt::format(
        "   <Grid Name=\"t{}\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
        "    <Time Value=\"{:.17g}\"/>\n",
        e.time, e.time);
    xml += fmt::format(
        "    <Grid Name=\"spheres\"><Topology TopologyType=\"Polyvertex\" "
        "NumberOfElements=\"{}\"/>\n     <Geometry GeometryType=\"XYZ\">{}</Geometry>\n",
        e.spheres, item("/particles/position", e.spheres, 3));
    const auto attribute = [&](std::string_view name, std::string_view type,
                               std::string_view dataset, int columns, bool integer) {
      std::string data = item(dataset, e.spheres, columns);
      if (integer) {
        data.replace(data.find("Float\" Precision=\"8\""), 20, "Int\" Precision=\"4\"");
      }
      return fmt::format(
          "     <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">{}"
          "</Attribute>\n",
          name, type, data);
    };
    xml += attribute("radius", "Scalar", "/particles/radius", 1, false);
    xml += attribute("velocity", "Vector", "/particles/velocity", 3, false);
    xml += attribute("force", "Vector", "/particles/force", 3, false);
    xml += attribute("contacts", "Scalar", "/particles/contacts", 1, true);
    xml += attribute("body", "Scalar", "/particles/body", 1, true);
    if (e.stress) {
      xml += attribute("pressure", "Scalar", "/particles/pressure", 1, false);
      xml += attribute("stress", "Tensor6", "/particles/stress", 6, false);
    }
    xml += "    </Grid>\n";
    if (e.bonds > 0) {
      // Bonds as two-node line cells on the sphere centres; threshold on "intact" to hide the
      // broken ones.
      xml += fmt::format(
          "    <Grid Name=\"bonds\"><Topology TopologyType=\"Polyline\" NodesPerElement=\"2\" "
          "NumberOfElements=\"{}\"><DataItem Dimensions=\"{} 2\" NumberType=\"Int\" "
          "Precision=\"4\" Format=\"HDF\">{}:/bonds/pairs</DataItem></Topology>\n"
          "     <Geometry GeometryType=\"XYZ\">{}</Geometry>\n",
          e.bonds, e.bonds, f, item("/particles/position", e.spheres, 3));
      xml += fmt::format(
          "     <Attribute Name=\"intact\" AttributeType=\"Scalar\" Center=\"Cell\"><DataItem "
          "Dimensions=\"{}\" NumberType=\"UChar\" Precision=\"1\" Format=\"HDF\">{}:"
          "/bonds/intact</DataItem></Attribute>\n",
          e.bonds, f);
      xml += fmt::format(
          "     <Attribute Name=\"bond_normal_force\" AttributeType=\"Scalar\" "
          "Center=\"Cell\">{}</Attribute>\n    </Grid>\n",
          item("/bonds/normal_force", e.bonds, 1));
    }
    if (e.clumps > 0) {
      // Each clump's body frame as three line cells from its centre along its principal axes,
      // colourable by "axis" (0: the smallest principal moment).
      xml += fmt::format(
          "    <Grid Name=\"clump_axes\"><Topology TopologyType=\"Polyline\" "
          "NodesPerElement=\"2\" NumberOfElements=\"{}\"><DataItem Dimensions=\"{} 2\" "
          "NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">{}:/clumps/axis_lines</DataItem>"
          "</Topology>\n     <Geometry GeometryType=\"XYZ\">{}</Geometry>\n",
          3 * e.clumps, 3 * e.clumps, f, item("/clumps/axis_points", 4 * e.clumps, 3));
      xml += fmt::format(
          "     <Attribute Name=\"axis\" AttributeType=\"Scalar\" Center=\"Cell\"><DataItem "
          "Dimensions=\"{}\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">{}:"
          "/clumps/axis_id</DataItem></Attribute>\n    </Grid>\n",
          3 * e.clumps, f);
    }
    xml += fmt::format(
        "    <Grid Name=\"walls\"><Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"{}\">"
        "<DataItem Dimensions=\"{} 4\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">{}:"
        "/walls/quads</DataItem></Topology>\n     <Geometry GeometryType=\"XYZ\">{}</Geometry>"
        "</Grid>\n   </Grid>\n",
        e.walls, e.walls, f, item("/walls/points", 4 * e.walls, 3));
  }
  xml += "  </Grid>\n </Domain>\n</Xdmf>\n";
  write_file_atomically(path, xml);
}

}  // namespace shapepress::simulate
