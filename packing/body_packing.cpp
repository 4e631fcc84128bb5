#include "packing/body_packing.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/hdf5_file.hpp"
#include "geometry/templates_file.hpp"

namespace shapepress::packing {

double BodyTemplate::volume_equivalent_diameter() const {
  return std::cbrt(6.0 * shape_volume / std::numbers::pi);
}

void set_body_volume(BodyTemplate& shape) {
  if (shape.radii.size() == 1) {  // a plain sphere is its own body, to the bit
    shape.body_volume = shape.sphere_volume;
    shape.body_inertia = shape.principal_inertia;
    return;
  }
  geometry::SphereTemplate spheres;
  for (const Vector3& c : shape.centres)
    spheres.centres.emplace_back(c[0], c[1], c[2]);
  spheres.radii = shape.radii;
  const geometry::MassProperties body = geometry::body_mass_properties(spheres);
  shape.body_volume = body.volume;
  for (int k = 0; k < 3; ++k)
    shape.body_inertia[static_cast<std::size_t>(k)] = body.inertia(k, k);
}

void place_body(const BodyTemplate& shape, const PackedBody& body, std::vector<Vector3>& centres,
                std::vector<double>& radii) {
  centres.clear(), radii.clear();
  for (std::size_t i = 0; i < shape.radii.size(); ++i) {
    const Vector3& c = shape.centres[i];
    const Vector3 arm = rotate_to_world(body.orientation,
                                        {body.scale * c[0], body.scale * c[1], body.scale * c[2]});
    centres.push_back({body.centre[0] + arm[0], body.centre[1] + arm[1], body.centre[2] + arm[2]});
    radii.push_back(body.scale * shape.radii[i]);
  }
}

namespace {

// A template or body without its body volume (made by hand, or read from a packing written before
// body volumes were kept) gets it from its sub-spheres.
void complete_body_volumes(BodyPacking& packing) {
  for (BodyTemplate& shape : packing.templates)
    if (!(shape.body_volume > 0.0)) set_body_volume(shape);
  for (PackedBody& body : packing.bodies)
    if (!(body.body_volume > 0.0)) {
      const double s = body.scale;
      body.body_volume =
          packing.templates.at(static_cast<std::size_t>(body.template_index)).body_volume * s * s *
          s;
    }
}

}  // namespace

void place_bodies(BodyPacking& packing) {
  complete_body_volumes(packing);
  packing.particles = SphereList{};
  packing.particle_body.clear();
  packing.first_particle.assign(1, 0);
  packing.bonds.clear();
  packing.bond_rest_length.clear();
  std::vector<Vector3> centres;
  std::vector<double> radii;
  for (std::size_t b = 0; b < packing.bodies.size(); ++b) {
    const PackedBody& body = packing.bodies[b];
    const BodyTemplate& shape = packing.templates.at(static_cast<std::size_t>(body.template_index));
    place_body(shape, body, centres, radii);
    const auto first = static_cast<std::int32_t>(packing.particles.size());
    for (std::size_t i = 0; i < radii.size(); ++i) {
      packing.particles.x.push_back(centres[i][0]);
      packing.particles.y.push_back(centres[i][1]);
      packing.particles.z.push_back(centres[i][2]);
      packing.particles.radius.push_back(radii[i]);
      packing.particle_body.push_back(static_cast<std::int32_t>(b));
    }
    for (const auto& [i, j] : shape.bonds) {
      packing.bonds.push_back({first + i, first + j});
      const auto a = static_cast<std::size_t>(i), c = static_cast<std::size_t>(j);
      packing.bond_rest_length.push_back(std::hypot(centres[a][0] - centres[c][0],
                                                    centres[a][1] - centres[c][1],
                                                    centres[a][2] - centres[c][2]));
    }
    packing.first_particle.push_back(static_cast<std::int32_t>(packing.particles.size()));
  }
}

namespace {

constexpr const char* format_name = "shapepress packing 1";

// Rows of N numbers as one run of numbers, for an (M, N) dataset.
template <class T, std::size_t N>
std::vector<T> flatten(const std::vector<std::array<T, N>>& rows) {
  std::vector<T> out;
  out.reserve(N * rows.size());
  for (const std::array<T, N>& row : rows)
    out.insert(out.end(), row.begin(), row.end());
  return out;
}

std::string xdmf_for(const std::filesystem::path& h5, const BodyPacking& p) {
  const std::string f = h5.filename().generic_string();
  const std::size_t n = p.particles.size();
  std::string xml = fmt::format(
      "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"
      "  <Grid Name=\"packing\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
      "   <Grid Name=\"spheres\"><Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{0}\"/>\n"
      "    <Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"{0} 3\" NumberType=\"Float\" "
      "Precision=\"8\" Format=\"HDF\">{1}:/particles/position</DataItem></Geometry>\n"
      "    <Attribute Name=\"radius\" AttributeType=\"Scalar\" Center=\"Node\"><DataItem "
      "Dimensions=\"{0}\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">{1}:/particles/radius"
      "</DataItem></Attribute>\n"
      "    <Attribute Name=\"body\" AttributeType=\"Scalar\" Center=\"Node\"><DataItem "
      "Dimensions=\"{0}\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">{1}:/particles/body"
      "</DataItem></Attribute>\n   </Grid>\n",
      n, f);
  if (!p.bonds.empty())
    xml += fmt::format(
        "   <Grid Name=\"bonds\"><Topology TopologyType=\"Polyline\" NodesPerElement=\"2\" "
        "NumberOfElements=\"{0}\"><DataItem Dimensions=\"{0} 2\" NumberType=\"Int\" "
        "Precision=\"4\" Format=\"HDF\">{1}:/bonds/pairs</DataItem></Topology>\n"
        "    <Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"{2} 3\" NumberType=\"Float\" "
        "Precision=\"8\" Format=\"HDF\">{1}:/particles/position</DataItem></Geometry>\n   "
        "</Grid>\n",
        p.bonds.size(), f, n);
  xml += "  </Grid>\n </Domain>\n</Xdmf>\n";
  return xml;
}

}  // namespace

void write_packing(const std::filesystem::path& path, const BodyPacking& p,
                   const Provenance& provenance) {
  H5Writer file(path, provenance);
  file.attribute("/", "format", std::string_view{format_name});
  file.attribute("/", "box_x", p.box.length_x);
  file.attribute("/", "box_y", p.box.length_y);
  file.attribute("/", "floor", p.floor);
  file.attribute("/", "top", p.top);
  std::vector<std::string> names, sources;
  std::vector<std::int32_t> kinds;
  for (std::size_t t = 0; t < p.templates.size(); ++t) {
    const BodyTemplate& shape = p.templates[t];
    names.push_back(shape.name), sources.push_back(shape.source);
    kinds.push_back(static_cast<std::int32_t>(shape.kind));
    const std::string group = fmt::format("/templates/{}", t);
    file.write(group + "/centres", flatten(shape.centres), {shape.centres.size(), 3});
    file.unit(group + "/centres", "m");
    file.write(group + "/radii", shape.radii);
    file.unit(group + "/radii", "m");
    file.write(group + "/bonds", flatten(shape.bonds), {shape.bonds.size(), 2});
    file.attribute(group, "shape_volume", shape.shape_volume);
    file.attribute(group, "sphere_volume", shape.sphere_volume);
    file.attribute(group, "body_volume", shape.body_volume);
    file.write(group + "/principal_inertia",
               std::vector<double>(shape.principal_inertia.begin(), shape.principal_inertia.end()));
    file.unit(group + "/principal_inertia", "m^5");
    file.write(group + "/body_inertia",
               std::vector<double>(shape.body_inertia.begin(), shape.body_inertia.end()));
    file.unit(group + "/body_inertia", "m^5");
  }
  file.write_strings("/templates/name", names);
  file.write_strings("/templates/source", sources);
  file.write("/templates/kind", kinds);

  std::vector<std::int32_t> body_template, body_kind;
  std::vector<double> scale, orientation, centre, shape_volume, sphere_volume, body_volume;
  for (const PackedBody& b : p.bodies) {
    body_template.push_back(b.template_index);
    body_kind.push_back(
        static_cast<std::int32_t>(p.templates[static_cast<std::size_t>(b.template_index)].kind));
    scale.push_back(b.scale);
    orientation.insert(orientation.end(),
                       {b.orientation.w, b.orientation.x, b.orientation.y, b.orientation.z});
    centre.insert(centre.end(), b.centre.begin(), b.centre.end());
    shape_volume.push_back(b.shape_volume);
    sphere_volume.push_back(b.sphere_volume);
    body_volume.push_back(b.body_volume);
  }
  const std::size_t m = p.bodies.size();
  file.write("/bodies/template", body_template);
  file.write("/bodies/kind", body_kind);
  file.write("/bodies/scale", scale);
  file.write("/bodies/orientation", orientation, {m, 4});
  file.write("/bodies/centre", centre, {m, 3});
  file.unit("/bodies/centre", "m");
  file.write("/bodies/shape_volume", shape_volume);
  file.unit("/bodies/shape_volume", "m^3");
  file.write("/bodies/sphere_volume", sphere_volume);
  file.unit("/bodies/sphere_volume", "m^3");
  file.write("/bodies/body_volume", body_volume);
  file.unit("/bodies/body_volume", "m^3");
  file.write("/bodies/first_particle", p.first_particle);

  const std::size_t n = p.particles.size();
  std::vector<double> position;
  position.reserve(3 * n);
  for (std::size_t i = 0; i < n; ++i)
    position.insert(position.end(), {p.particles.x[i], p.particles.y[i], p.particles.z[i]});
  file.write("/particles/position", position, {n, 3});
  file.unit("/particles/position", "m");
  file.write("/particles/radius", p.particles.radius);
  file.unit("/particles/radius", "m");
  file.write("/particles/body", p.particle_body);
  file.write("/bonds/pairs", flatten(p.bonds), {p.bonds.size(), 2});
  file.write("/bonds/rest_length", p.bond_rest_length);
  file.unit("/bonds/rest_length", "m");
  for_each_measure(p.measures, [&](const char* name, const char* unit, double value) {
    const std::string dataset = fmt::format("/measures/{}", name);
    file.write(dataset, std::vector<double>{value});
    file.unit(dataset, unit);
  });
  // The sidecar first: a packed.h5 under its final name always has its packed.xmf.
  std::filesystem::path sidecar = path;
  sidecar.replace_extension(".xmf");
  write_file_atomically(sidecar, xdmf_for(path, p));
  try {
    file.commit();
  } catch (...) {  // no sidecar without its packed.h5
    std::error_code ignored;
    std::filesystem::remove(sidecar, ignored);
    throw;
  }
}

namespace {

struct Reader {
  const H5Reader& file;
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(fmt::format("{}: {}", file.path().string(), what));
  }
  std::vector<double> rows(const std::string& dataset, std::size_t columns,
                           std::size_t expected_rows) const {
    std::vector<std::size_t> shape;
    std::vector<double> v = file.doubles(dataset, &shape);
    const bool empty = v.empty() && expected_rows == 0;
    if (!empty && (shape.size() != 2 || shape[1] != columns || shape[0] != expected_rows))
      fail(fmt::format("{} must be {}×{}", dataset, expected_rows, columns));
    return v;
  }
  std::vector<std::array<std::int32_t, 2>> pairs(const std::string& dataset) const {
    std::vector<std::size_t> shape;
    const std::vector<std::int32_t> v = file.int32s(dataset, &shape);
    if (!v.empty() && (shape.size() != 2 || shape[1] != 2)) fail(dataset + " must be B×2");
    std::vector<std::array<std::int32_t, 2>> out;
    for (std::size_t k = 0; k + 1 < v.size(); k += 2)
      out.push_back({v[k], v[k + 1]});
    return out;
  }
  std::vector<double> sized(const std::string& dataset, std::size_t size) const {
    std::vector<double> v = file.doubles(dataset);
    if (v.size() != size)
      fail(fmt::format("{} must hold {} values, not {}", dataset, size, v.size()));
    for (std::size_t k = 0; k < v.size(); ++k)
      if (!std::isfinite(v[k])) fail(fmt::format("{}[{}] is not finite", dataset, k));
    return v;
  }
};

// One template of /templates/<t>: its sub-spheres, bonds, volumes and inertia.
BodyTemplate read_template(const Reader& read, std::size_t t, const std::string& name,
                           const std::string& source, std::int32_t kind) {
  const H5Reader& file = read.file;
  BodyTemplate shape;
  shape.name = name, shape.source = source;
  if (kind < 0 || kind > 2) read.fail(fmt::format("/templates/kind[{}] = {}", t, kind));
  shape.kind = static_cast<BodyKind>(kind);
  const std::string group = fmt::format("/templates/{}", t);
  shape.radii = file.doubles(group + "/radii");
  const std::vector<double> c = read.rows(group + "/centres", 3, shape.radii.size());
  for (std::size_t i = 0; i < shape.radii.size(); ++i) {
    shape.centres.push_back({c[3 * i], c[3 * i + 1], c[3 * i + 2]});
    if (!(shape.radii[i] > 0.0)) read.fail(fmt::format("{}/radii[{}] must be > 0", group, i));
  }
  shape.bonds = read.pairs(group + "/bonds");
  for (const auto& [i, j] : shape.bonds)
    if (i < 0 || j <= i || static_cast<std::size_t>(j) >= shape.radii.size())
      read.fail(fmt::format("{}/bonds: pair ({}, {}) is not i < j < {}", group, i, j,
                            shape.radii.size()));
  shape.shape_volume = file.attribute_double(group, "shape_volume");
  shape.sphere_volume = file.attribute_double(group, "sphere_volume");
  const std::vector<double> inertia = read.sized(group + "/principal_inertia", 3);
  std::copy(inertia.begin(), inertia.end(), shape.principal_inertia.begin());
  if (shape.radii.empty() || !(shape.shape_volume > 0.0) || !(shape.sphere_volume > 0.0))
    read.fail(group + ": a template needs sub-spheres and volumes > 0");
  if (file.has_attribute(group, "body_volume")) {
    shape.body_volume = file.attribute_double(group, "body_volume");
    const std::vector<double> body = read.sized(group + "/body_inertia", 3);
    std::copy(body.begin(), body.end(), shape.body_inertia.begin());
    if (!(shape.body_volume > 0.0)) read.fail(group + ": body_volume must be > 0");
  }
  return shape;
}

void read_templates(const Reader& read, BodyPacking& p) {
  const H5Reader& file = read.file;
  const std::vector<std::string> names = file.strings("/templates/name");
  const std::vector<std::string> sources = file.strings("/templates/source");
  const std::vector<std::int32_t> kinds = file.int32s("/templates/kind");
  if (sources.size() != names.size() || kinds.size() != names.size())
    read.fail("/templates/name, /templates/source and /templates/kind differ in length");
  for (std::size_t t = 0; t < names.size(); ++t)
    p.templates.push_back(read_template(read, t, names[t], sources[t], kinds[t]));
}

// The bodies (after the templates they name): template, scale, pose, volumes, and where their
// particles start.
void read_bodies(const Reader& read, BodyPacking& p) {
  const H5Reader& file = read.file;
  const std::vector<std::int32_t> body_template = file.int32s("/bodies/template");
  const std::size_t m = body_template.size();
  const std::vector<double> scale = read.sized("/bodies/scale", m);
  const std::vector<double> orientation = read.sized("/bodies/orientation", 4 * m);
  const std::vector<double> centre = read.sized("/bodies/centre", 3 * m);
  const std::vector<double> shape_volume = read.sized("/bodies/shape_volume", m);
  const std::vector<double> sphere_volume = read.sized("/bodies/sphere_volume", m);
  const bool has_body_volume = file.has("/bodies/body_volume");
  const std::vector<double> body_volume =
      has_body_volume ? read.sized("/bodies/body_volume", m) : std::vector<double>{};
  p.first_particle = file.int32s("/bodies/first_particle");
  if (p.first_particle.size() != m + 1) read.fail("/bodies/first_particle must hold M + 1 values");
  for (std::size_t b = 0; b < m; ++b) {
    PackedBody body;
    body.template_index = body_template[b];
    if (body_template[b] < 0 || static_cast<std::size_t>(body_template[b]) >= p.templates.size())
      read.fail(fmt::format("/bodies/template[{}] = {} names no template", b, body_template[b]));
    if (!(scale[b] > 0.0)) read.fail(fmt::format("/bodies/scale[{}] must be > 0", b));
    body.scale = scale[b];
    body.orientation = normalized({orientation[4 * b], orientation[4 * b + 1],
                                   orientation[4 * b + 2], orientation[4 * b + 3]});
    body.centre = {centre[3 * b], centre[3 * b + 1], centre[3 * b + 2]};
    body.shape_volume = shape_volume[b];
    body.sphere_volume = sphere_volume[b];
    if (has_body_volume) body.body_volume = body_volume[b];
    p.bodies.push_back(body);
  }
}

// The particles (after the bodies): positions and radii, each body's run of them as many as its
// template's sub-spheres.
void read_particles(const Reader& read, BodyPacking& p) {
  const H5Reader& file = read.file;
  p.particles.radius = file.doubles("/particles/radius");
  const std::size_t n = p.particles.size();
  const std::vector<double> position = read.rows("/particles/position", 3, n);
  for (std::size_t i = 0; i < n; ++i) {
    p.particles.x.push_back(position[3 * i]);
    p.particles.y.push_back(position[3 * i + 1]);
    p.particles.z.push_back(position[3 * i + 2]);
    if (!(p.particles.radius[i] > 0.0)) read.fail(fmt::format("/particles/radius[{}] <= 0", i));
  }
  p.particle_body = file.int32s("/particles/body");
  if (p.particle_body.size() != n) read.fail("/particles/body must hold one value per particle");
  if (p.first_particle.front() != 0 || static_cast<std::size_t>(p.first_particle.back()) != n)
    read.fail("/bodies/first_particle must run from 0 to the particle count");
  for (std::size_t b = 0; b < p.bodies.size(); ++b) {
    const auto count = static_cast<std::size_t>(
        p.templates[static_cast<std::size_t>(p.bodies[b].template_index)].radii.size());
    if (p.first_particle[b + 1] - p.first_particle[b] != static_cast<std::int32_t>(count))
      read.fail(fmt::format("body {} holds {} particles, its template {}", b,
                            p.first_particle[b + 1] - p.first_particle[b], count));
    for (std::int32_t i = p.first_particle[b]; i < p.first_particle[b + 1]; ++i)
      if (p.particle_body[static_cast<std::size_t>(i)] != static_cast<std::int32_t>(b))
        read.fail(fmt::format("/particles/body[{}] is not {}", i, b));
  }
}

// The bonds (after the particles): each within one body, with a rest length > 0.
void read_bonds(const Reader& read, BodyPacking& p) {
  const std::size_t n = p.particles.size();
  p.bonds = read.pairs("/bonds/pairs");
  p.bond_rest_length = read.sized("/bonds/rest_length", p.bonds.size());
  for (std::size_t k = 0; k < p.bonds.size(); ++k) {
    const auto [i, j] = p.bonds[k];
    if (i < 0 || j <= i || static_cast<std::size_t>(j) >= n)
      read.fail(fmt::format("/bonds/pairs[{}] = ({}, {}) is not i < j < {}", k, i, j, n));
    if (p.particle_body[static_cast<std::size_t>(i)] !=
        p.particle_body[static_cast<std::size_t>(j)])
      read.fail(
          fmt::format("/bonds/pairs[{}] joins particles {} and {} of bodies {} and {}: a bond "
                      "lies within one body",
                      k, i, j, p.particle_body[static_cast<std::size_t>(i)],
                      p.particle_body[static_cast<std::size_t>(j)]));
    if (!(p.bond_rest_length[k] > 0.0))
      read.fail(fmt::format("/bonds/rest_length[{}] must be > 0", k));
  }
}

}  // namespace

bool is_body_packing(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext != ".h5" && ext != ".hdf5") return false;
  const H5Reader file(path);
  return file.has_attribute("/", "format") && file.attribute_string("/", "format") == format_name;
}

BodyPacking read_packing(const std::filesystem::path& path) {
  const H5Reader file(path);
  const Reader read{file};
  if (!file.has_attribute("/", "format") || file.attribute_string("/", "format") != format_name)
    read.fail(fmt::format("not a packing written by `shapepress pack` (no format = \"{}\")",
                          format_name));
  BodyPacking p;
  p.box.length_x = file.attribute_double("/", "box_x");
  p.box.length_y = file.attribute_double("/", "box_y");
  p.floor = file.attribute_double("/", "floor");
  p.top = file.attribute_double("/", "top");
  if (!(p.box.length_x > 0.0 && p.box.length_y > 0.0 && p.top > p.floor))
    read.fail("box_x and box_y must be > 0 and top above floor");
  read_templates(read, p);
  read_bodies(read, p);
  read_particles(read, p);
  read_bonds(read, p);
  if (file.has("/measures"))
    for_each_measure(p.measures, [&](const char* name, const char*, double& value) {
      const std::string dataset = fmt::format("/measures/{}", name);
      if (file.has(dataset)) value = read.sized(dataset, 1)[0];
    });
  complete_body_volumes(p);  // a packing from before body volumes
  return p;
}

}  // namespace shapepress::packing
