#include "geometry/templates_file.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "common/error.hpp"
#include "common/hdf5_file.hpp"

namespace shapepress::geometry {
namespace {

std::vector<double> flatten(const std::vector<Vec3>& points) {
  std::vector<double> flat;
  flat.reserve(3 * points.size());
  for (const Vec3& p : points)
    flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  return flat;
}

// fmt rather than operator+: GCC 12 warns (-Wrestrict, falsely) on chained string additions.
std::string child(const std::string& group, std::string_view leaf) {
  return fmt::format("{}/{}", group, leaf);
}

std::vector<double> as_vector(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

struct Metric {
  const char* name;
  double value;
  const char* unit;
};

std::vector<Metric> metrics(const FillQuality& q) {
  return {{"volume_fraction", q.volume_fraction, "1"},
          {"volume_error", q.volume_error, "1"},
          {"surface_rms_m", q.surface_rms_m, "m"},
          {"hausdorff_m", q.hausdorff_m, "m"},
          {"surface_rms_relative", q.surface_rms_relative, "1"},
          {"hausdorff_relative", q.hausdorff_relative, "1"},
          {"inertia_error", q.inertia_error, "1"},
          {"extent_error", q.extent_error, "1"},
          {"min_radius_m", q.min_radius_m, "m"},
          {"max_radius_m", q.max_radius_m, "m"},
          {"bond_count", static_cast<double>(q.bond_count), "1"},
          {"mean_coordination", q.mean_coordination, "1"},
          {"connected", q.connected ? 1.0 : 0.0, "1"},
          {"sphere_count", static_cast<double>(q.sphere_count), "1"}};
}

}  // namespace

MassProperties body_mass_properties(const SphereTemplate& spheres, double* probe_radius,
                                    int cells) {
  std::vector<double> sorted = spheres.radii;
  if (sorted.empty()) return {};
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                   sorted.end());
  const double probe = sorted[sorted.size() / 2];
  if (probe_radius) *probe_radius = probe;
  MassProperties m =
      spheres.centres.size() == 1
          ? ellipsoid_mass_properties(Vec3::Constant(spheres.radii[0]), spheres.centres[0])
          : closed_union_mass_properties(spheres.centres, spheres.radii, probe, cells);
  // About the body origin (parallel axes), the body frame's diagonal kept: the body is turned and
  // integrated about its sub-spheres' principal axes.
  const Vec3 d = m.centre;
  const Mat3 about_origin =
      m.inertia + m.volume * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
  m.inertia = about_origin.diagonal().asDiagonal();
  m.centre = Vec3::Zero();
  diagonalise(m);
  return m;
}

TemplateRecord make_template_record(std::string name, std::string source,
                                    const SphereTemplate& filled,
                                    const MassProperties& template_mass,
                                    const MassProperties& shape_mass, const FillQuality& quality) {
  TemplateRecord r;
  r.name = std::move(name);
  r.source = std::move(source);
  r.body = filled;
  r.body_origin = template_mass.centre;
  r.body_axes = template_mass.principal_axes;
  for (Vec3& c : r.body.centres)
    c = r.body_axes.transpose() * (c - r.body_origin);
  r.mass = template_mass;
  r.mass.centre = Vec3::Zero();
  r.mass.inertia = template_mass.principal_moments.asDiagonal();
  r.mass.principal_axes = Mat3::Identity();
  r.shape_mass = shape_mass;
  r.quality = quality;
  r.body_mass = body_mass_properties(r.body, &r.body_probe_radius);
  return r;
}

void write_templates(const std::filesystem::path& path, const std::vector<TemplateRecord>& records,
                     const Provenance& provenance) {
  H5Writer file(path, provenance);
  file.attribute("/", "format", "shapepress templates 1");
  file.attribute("/", "template_count", static_cast<std::int64_t>(records.size()));
  for (const TemplateRecord& r : records) {
    const std::string g = fmt::format("/{}/{}", kind_name(r.body.kind), r.name);
    file.group(g);
    file.attribute(g, "source", r.source);
    file.attribute(g, "kind", kind_name(r.body.kind));
    file.attribute(g, "seed", static_cast<std::int64_t>(r.seed));
    file.attribute(g, "sphere_count", static_cast<std::int64_t>(r.body.centres.size()));
    file.write(child(g, "centres"), flatten(r.body.centres), {r.body.centres.size(), 3});
    file.unit(child(g, "centres"), "m");
    file.write(child(g, "radii"), r.body.radii);
    file.unit(child(g, "radii"), "m");
    if (r.body.kind == TemplateKind::bonded) {
      file.attribute(g, "bond_multiplier", r.bond_multiplier);
      std::vector<std::int32_t> bonds;
      for (const Bond& b : r.body.bonds)
        bonds.insert(bonds.end(), {b[0], b[1]});
      file.write(child(g, "bonds"), bonds, {r.body.bonds.size(), 2});
    }
    const std::vector<double> volume = {r.mass.volume}, shape_volume = {r.shape_mass.volume};
    file.write(child(g, "volume"), volume);
    file.unit(child(g, "volume"), "m^3");
    file.write(child(g, "principal_inertia"), as_vector(r.mass.principal_moments));
    file.unit(child(g, "principal_inertia"), "m^5");
    file.write(child(g, "shape_volume"), shape_volume);
    file.unit(child(g, "shape_volume"), "m^3");
    file.write(child(g, "shape_principal_inertia"), as_vector(r.shape_mass.principal_moments));
    file.unit(child(g, "shape_principal_inertia"), "m^5");
    const std::vector<double> body_volume = {r.body_mass.volume}, probe = {r.body_probe_radius};
    file.write(child(g, "body_volume"), body_volume);
    file.unit(child(g, "body_volume"), "m^3");
    file.write(child(g, "body_inertia"), as_vector(r.body_mass.inertia.diagonal()));
    file.unit(child(g, "body_inertia"), "m^5");
    file.write(child(g, "body_probe_radius"), probe);
    file.unit(child(g, "body_probe_radius"), "m");
    file.write(child(g, "body_origin"), as_vector(r.body_origin));
    file.unit(child(g, "body_origin"), "m");
    std::vector<double> axes(9);  // row-major: axes[3 i + j] = R(i, j)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        axes[static_cast<std::size_t>(3 * i + j)] = r.body_axes(i, j);
    file.write(child(g, "body_axes"), axes, {3, 3});
    for (const Metric& m : metrics(r.quality)) {
      const std::vector<double> value = {m.value};
      file.write(child(g, "quality/") + m.name, value);
      file.unit(child(g, "quality/") + m.name, m.unit);
    }
    file.write(child(g, "quality/shape_extents_m"), as_vector(r.quality.shape_extents));
    file.write(child(g, "quality/union_extents_m"), as_vector(r.quality.union_extents));
  }
  file.commit();
}

std::vector<TemplateRecord> read_templates(const std::filesystem::path& path) {
  H5Reader file(path);
  std::vector<TemplateRecord> records;
  for (TemplateKind kind : {TemplateKind::bonded, TemplateKind::rigid}) {
    const std::string group = fmt::format("/{}", kind_name(kind));
    if (!file.has(group)) continue;
    for (const std::string& name : file.members(group)) {
      const std::string g = child(group, name);
      TemplateRecord r;
      r.name = name;
      r.source = file.attribute_string(g, "source");
      r.seed = static_cast<std::uint64_t>(file.attribute_int64(g, "seed"));
      r.body.kind = kind;
      const std::vector<double> c = file.doubles(child(g, "centres"));
      for (std::size_t i = 0; i + 2 < c.size(); i += 3)
        r.body.centres.emplace_back(c[i], c[i + 1], c[i + 2]);
      r.body.radii = file.doubles(child(g, "radii"));
      if (kind == TemplateKind::bonded) {
        r.bond_multiplier = file.attribute_double(g, "bond_multiplier");
        const std::vector<std::int32_t> b = file.int32s(child(g, "bonds"));
        for (std::size_t i = 0; i + 1 < b.size(); i += 2)
          r.body.bonds.push_back({b[i], b[i + 1]});
      }
      r.mass.volume = file.doubles(child(g, "volume")).at(0);
      const std::vector<double> moments = file.doubles(child(g, "principal_inertia"));
      r.mass.principal_moments = Vec3(moments.at(0), moments.at(1), moments.at(2));
      r.mass.inertia = r.mass.principal_moments.asDiagonal();
      r.shape_mass.volume = file.doubles(child(g, "shape_volume")).at(0);
      const std::vector<double> origin = file.doubles(child(g, "body_origin"));
      r.body_origin = Vec3(origin.at(0), origin.at(1), origin.at(2));
      const std::vector<double> axes = file.doubles(child(g, "body_axes"));
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          r.body_axes(i, j) = axes.at(static_cast<std::size_t>(3 * i + j));
      if (file.has(child(g, "body_volume"))) {
        r.body_mass.volume = file.doubles(child(g, "body_volume")).at(0);
        const std::vector<double> body = file.doubles(child(g, "body_inertia"));
        r.body_mass.inertia = Vec3(body.at(0), body.at(1), body.at(2)).asDiagonal();
        diagonalise(r.body_mass);
        r.body_probe_radius = file.doubles(child(g, "body_probe_radius")).at(0);
      } else {
        r.body_mass = body_mass_properties(r.body, &r.body_probe_radius);
      }
      r.quality.volume_error = file.doubles(child(g, "quality/volume_error")).at(0);
      r.quality.volume_fraction = file.doubles(child(g, "quality/volume_fraction")).at(0);
      r.quality.connected = file.doubles(child(g, "quality/connected")).at(0) != 0.0;
      r.quality.sphere_count = static_cast<int>(r.body.centres.size());
      records.push_back(std::move(r));
    }
  }
  return records;
}

}  // namespace shapepress::geometry
