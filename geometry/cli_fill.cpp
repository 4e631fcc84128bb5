#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "common/error.hpp"
#include "common/progress.hpp"
#include "common/run_metadata.hpp"
#include "common/units.hpp"
#include "geometry/cli.hpp"
#include "geometry/cli_mesh_input.hpp"
#include "geometry/mesh_distance.hpp"
#include "geometry/templates_file.hpp"

namespace shapepress::geometry {
namespace {

struct FillCli {
  std::vector<std::string> meshes;
  std::string sphere;     // radius of an analytic sphere
  std::string ellipsoid;  // "a,b,c" semi-axes
  std::string kind = "bms";
  int count = 0;  // 0: 350 for bms, 150 for cms (the paper's counts)
  std::string radius;
  std::string lattice = "fcc";
  std::string placement = "inside";
  double bond_multiplier = 1.15;
  int resolution = 64;
  std::string mesh_unit = "1 m";
  std::uint64_t seed = 1;
  std::string out;
};

// A shape to fill. A mesh's signed-distance grid (about 4 MB at resolution 64) is made when its
// template is filled and dropped after it, so that a fill of thousands of meshes holds one grid,
// not all of them; the meshes are read and checked before the first template, so that a bad one
// is exit 2 before any work.
struct NamedShape {
  std::string name, source;
  SignedDistance distance;           // analytic shapes
  std::optional<TriangleMesh> mesh;  // meshes: the grid is made from it at fill time
  MassProperties mass;
};

SignedDistance distance_of(const NamedShape& shape, int resolution) {
  return shape.mesh ? mesh_distance(*shape.mesh, resolution, shape.source) : shape.distance;
}

Vec3 parse_semi_axes(const std::string& text) {
  std::vector<double> values;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    values.push_back(parse_quantity(item, dim::length, "ellipsoid"));
  if (values.size() != 3 || values[0] <= 0.0 || values[1] <= 0.0 || values[2] <= 0.0)
    throw InputError(
        fmt::format("--ellipsoid '{}': expected three positive semi-axes 'a,b,c' "
                    "(e.g. 100um,84um,80um)",
                    text));
  return {values[0], values[1], values[2]};
}

std::vector<NamedShape> shapes_of(const FillCli& cli) {
  std::vector<NamedShape> shapes;
  if (!cli.sphere.empty()) {
    const double r = parse_quantity(cli.sphere, dim::length, "sphere");
    if (!(r > 0.0)) throw InputError(fmt::format("--sphere '{}' must be > 0", cli.sphere));
    shapes.push_back({"sphere", "analytic sphere", sphere_distance(r), std::nullopt,
                      ellipsoid_mass_properties(Vec3::Constant(r))});
  }
  if (!cli.ellipsoid.empty()) {
    const Vec3 e = parse_semi_axes(cli.ellipsoid);
    shapes.push_back({"ellipsoid", "analytic ellipsoid", ellipsoid_distance(e), std::nullopt,
                      ellipsoid_mass_properties(e)});
  }
  std::set<std::string> names;
  for (const std::string& path : cli.meshes) {
    const TriangleMesh mesh = load_checked_mesh(path, cli.mesh_unit);
    std::string name = std::filesystem::path(path).stem().string();
    for (int k = 2; names.count(name); ++k)
      name = fmt::format("{}_{}", name, k);
    names.insert(name);
    shapes.push_back({name, path, {}, mesh, mesh_mass_properties(mesh)});
  }
  if (shapes.empty())
    throw InputError("fill: give meshes, --sphere or --ellipsoid (nothing to fill)");
  return shapes;
}

int run(const FillCli& cli, const RunContext& context) {
  if (cli.kind != "bms" && cli.kind != "cms")
    throw InputError(fmt::format("--kind '{}': expected bms or cms", cli.kind));
  const bool bonded = cli.kind == "bms";
  const std::vector<NamedShape> shapes = shapes_of(cli);
  ProgressReporter progress("fill", static_cast<double>(shapes.size()),
                            {.quiet = context.quiet, .unit = "templates"});
  std::vector<TemplateRecord> records;
  // Vbody: the body's volume in a bed (the union closed by a ball of the sub-spheres' radius) over
  // the shape's, what its solid fraction and mass are by.
  fmt::print("{:<24} {:>4} {:>6} {:>8} {:>8} {:>8} {:>8} {:>8} {:>6} {:>8}\n", "template", "kind",
             "N", "Vfrac", "Verr", "rms/d", "haus/d", "inertia", "bonds", "Vbody");
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    const NamedShape& shape = shapes[i];
    const SignedDistance distance = distance_of(shape, cli.resolution);
    const std::uint64_t seed = cli.seed + i;
    SphereTemplate filled;
    if (bonded) {
      BondedFillOptions options;
      options.target_count = cli.count > 0 ? cli.count : 350;
      options.sub_sphere_radius =
          cli.radius.empty() ? 0.0 : parse_quantity(cli.radius, dim::length, "radius");
      options.lattice = lattice_from_name(cli.lattice);
      options.placement = cli.placement == "centre" ? Placement::centre : Placement::inside;
      options.bond_multiplier = cli.bond_multiplier;
      options.seed = seed;
      filled = fill_bonded(distance, options);
    } else {
      RigidFillOptions options;
      options.sphere_count = cli.count > 0 ? cli.count : 150;
      options.resolution = cli.resolution;
      filled = fill_rigid(distance, options);
    }
    const FillQuality quality = assess_fill(filled, distance, shape.mass);
    if (bonded && !quality.connected)
      throw ComputationError(
          fmt::format("fill: the bond graph of '{}' is not connected", shape.name));
    TemplateRecord record = make_template_record(
        shape.name, shape.source, filled, template_mass_properties(filled), shape.mass, quality);
    record.seed = seed;
    record.bond_multiplier = bonded ? cli.bond_multiplier : 0.0;
    fmt::print("{:<24} {:>4} {:>6} {:>8.4f} {:>8.4f} {:>8.4f} {:>8.4f} {:>8.4f} {:>6} {:>8.4f}\n",
               shape.name, cli.kind, quality.sphere_count, quality.volume_fraction,
               quality.volume_error, quality.surface_rms_relative, quality.hausdorff_relative,
               quality.inertia_error, quality.bond_count,
               record.body_mass.volume / shape.mass.volume);
    records.push_back(std::move(record));
    progress.update(static_cast<double>(i + 1));
  }
  progress.finish();
  write_templates(cli.out, records, Provenance{context.command_line, "", cli.seed});
  // --out is a file (two fills may share a folder): the run.json goes beside it.
  RunMetadata meta("fill", context.command_line);
  for (const std::string& mesh : cli.meshes)
    meta.input("mesh", mesh);
  nlohmann::json names = nlohmann::json::array(), counts = nlohmann::json::array(),
                 bonds = nlohmann::json::array(), body_fractions = nlohmann::json::array();
  for (const TemplateRecord& record : records) {
    names.push_back(record.name);
    counts.push_back(record.quality.sphere_count);
    bonds.push_back(record.quality.bond_count);
    body_fractions.push_back(record.body_mass.volume / record.shape_mass.volume);
  }
  meta.output(std::filesystem::path(cli.out).filename())
      .fact("particle_kind", cli.kind)
      .fact("templates", records.size())
      .fact("template_names", names)
      .fact("sub_spheres", counts)
      .fact("bonds", bonds)
      .fact("body_volume_fractions", body_fractions)
      .fact("requested_count", cli.count > 0 ? cli.count
                               : bonded      ? 350
                                             : 150)
      .fact("resolution", cli.resolution)
      .fact("mesh_unit", cli.mesh_unit)
      .fact("seed", cli.seed);
  // The analytic shapes as given, so that a later fill of the same shapes (advise's re-fill at
  // another count) can ask for them again.
  if (!cli.sphere.empty()) meta.fact("sphere", cli.sphere);
  if (!cli.ellipsoid.empty()) meta.fact("ellipsoid", cli.ellipsoid);
  if (bonded)
    meta.fact("lattice", cli.lattice)
        .fact("placement", cli.placement)
        .fact("bond_multiplier", cli.bond_multiplier);
  if (bonded && !cli.radius.empty())
    meta.fact("sub_sphere_radius_m", parse_quantity(cli.radius, dim::length, "radius"));
  meta.write(run_metadata_beside(cli.out));
  spdlog::info("fill: {} {} templates in {}", records.size(), cli.kind, cli.out);
  return 0;
}

}  // namespace

StageRunner setup_fill_cli(CLI::App& app) {
  auto cli = std::make_shared<FillCli>();
  app.add_option("meshes", cli->meshes, "closed particle meshes (.stl, .off, .ply)");
  app.add_option("--sphere", cli->sphere, "fill an analytic sphere of this radius (e.g. 1cm)");
  app.add_option("--ellipsoid", cli->ellipsoid, "fill an analytic ellipsoid, semi-axes 'a,b,c'");
  app.add_option("--kind", cli->kind, "bms (bonded, touching) or cms (rigid, overlapping)")
      ->check(CLI::IsMember({"bms", "cms"}))
      ->capture_default_str();
  app.add_option("--count", cli->count, "sub-spheres per template (default 350 bms, 150 cms)")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--radius", cli->radius, "bms: fixed sub-sphere radius instead of a count");
  app.add_option("--lattice", cli->lattice,
                 "bms: fcc or hcp lattice, random (a jammed dense random packing), shell "
                 "(random, with an outer layer of sub-spheres touching the surface) or carved "
                 "(the shape cut out of a larger random packing: no wall-ordered outer layer)")
      ->check(CLI::IsMember(
          std::vector<std::string>(std::begin(lattice_names), std::end(lattice_names))))
      ->capture_default_str();
  app.add_option("--placement", cli->placement,
                 "bms: 'inside' (spheres wholly inside) or 'centre' (centres inside)")
      ->check(CLI::IsMember({"inside", "centre"}))
      ->capture_default_str();
  app.add_option("--bond-multiplier", cli->bond_multiplier, "m_b of Eq. 10")->capture_default_str();
  app.add_option("--resolution", cli->resolution,
                 "voxels along a mesh's longest side (level set and cms grid)")
      ->check(CLI::Range(8, 1024))
      ->capture_default_str();
  app.add_option("--mesh-unit", cli->mesh_unit, "length of one mesh coordinate unit (1mm, 1um)")
      ->capture_default_str();
  app.add_option("--seed", cli->seed, "seed of the lattice orientations")->capture_default_str();
  app.add_option("--out", cli->out, "templates file (HDF5)")->required();
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::geometry
