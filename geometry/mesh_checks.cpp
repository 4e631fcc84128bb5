#include "geometry/mesh_checks.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <fmt/format.h>

#include "common/error.hpp"

namespace shapepress::geometry {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Polygon = std::vector<std::size_t>;

struct Soup {
  std::vector<Point> points;
  std::vector<Polygon> polygons;
};

Soup to_soup(const TriangleMesh& mesh) {
  Soup soup;
  for (const Vec3& p : mesh.vertices)
    soup.points.emplace_back(p.x(), p.y(), p.z());
  for (const auto& t : mesh.triangles)
    soup.polygons.push_back({static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]),
                             static_cast<std::size_t>(t[2])});
  return soup;
}

TriangleMesh from_surface_mesh(Mesh& sm) {
  sm.collect_garbage();
  TriangleMesh mesh;
  for (Mesh::Vertex_index v : sm.vertices()) {
    const Point& p = sm.point(v);
    mesh.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (Mesh::Face_index f : sm.faces()) {
    std::array<std::int32_t, 3> t{};
    int k = 0;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(sm.halfedge(f), sm))
      if (k < 3) t[static_cast<std::size_t>(k++)] = static_cast<std::int32_t>(v.idx());
    mesh.triangles.push_back(t);
  }
  return mesh;
}

bool soup_is_manifold_mesh(const Soup& soup) {
  return PMP::is_polygon_soup_a_polygon_mesh(soup.polygons);
}

}  // namespace

MeshCheck check_mesh(const TriangleMesh& mesh) {
  MeshCheck check;
  const Soup soup = to_soup(mesh);
  check.manifold = soup_is_manifold_mesh(soup);
  if (!check.manifold) return check;
  Mesh sm;
  PMP::polygon_soup_to_polygon_mesh(soup.points, soup.polygons, sm);
  check.closed = CGAL::is_closed(sm);
  check.self_intersecting = PMP::does_self_intersect(sm);
  return check;
}

TriangleMesh prepare_mesh(const TriangleMesh& input, const std::string& name,
                          std::vector<std::string>* repairs, double min_size_m) {
  auto note = [&](std::string sentence) {
    if (repairs != nullptr) repairs->push_back(std::move(sentence));
  };
  const Aabb box = bounding_box(input.vertices);
  const double longest = box.size().maxCoeff();
  if (input.triangles.size() < 4)
    throw InputError(fmt::format("mesh '{}': degenerate, {} triangles cannot enclose a volume",
                                 name, input.triangles.size()));
  if (!(longest >= min_size_m))
    throw InputError(
        fmt::format("mesh '{}': tiny, its longest side is {:.3g} m (< {:.3g} m); is "
                    "it in other units? (give --mesh-unit)",
                    name, longest, min_size_m));
  Soup soup = to_soup(input);
  const std::size_t points_before = soup.points.size(), polygons_before = soup.polygons.size();
  PMP::repair_polygon_soup(soup.points, soup.polygons);
  if (soup.points.size() != points_before || soup.polygons.size() != polygons_before)
    note(
        fmt::format("merged or removed {} duplicate/unused points and {} degenerate/duplicate "
                    "triangles",
                    points_before - soup.points.size(), polygons_before - soup.polygons.size()));
  if (!soup_is_manifold_mesh(soup)) {
    const std::size_t before = soup.points.size();
    PMP::orient_polygon_soup(soup.points, soup.polygons);
    note(fmt::format(
        "re-oriented the triangles consistently{}",
        soup.points.size() > before
            ? fmt::format(" and split {} non-manifold vertices", soup.points.size() - before)
            : std::string()));
  }
  if (!soup_is_manifold_mesh(soup))
    throw InputError(fmt::format("mesh '{}': not a 2-manifold and CGAL could not repair it", name));
  Mesh sm;
  PMP::polygon_soup_to_polygon_mesh(soup.points, soup.polygons, sm);
  if (!CGAL::is_closed(sm)) {
    const std::size_t stitched = PMP::stitch_borders(sm);
    if (stitched > 0) note(fmt::format("stitched {} pairs of border edges", stitched));
  }
  if (!CGAL::is_closed(sm)) {
    std::vector<Mesh::Halfedge_index> borders;
    for (Mesh::Halfedge_index h : sm.halfedges())
      if (sm.is_border(h)) borders.push_back(h);
    std::size_t holes = 0;
    std::vector<bool> done(sm.number_of_halfedges(), false);
    for (Mesh::Halfedge_index h : borders) {
      if (done[h.idx()] || !sm.is_border(h)) continue;
      for (Mesh::Halfedge_index g : CGAL::halfedges_around_face(h, sm))
        done[g.idx()] = true;
      std::vector<Mesh::Face_index> patch;
      PMP::triangulate_hole(sm, h, std::back_inserter(patch));
      ++holes;
    }
    if (holes > 0) note(fmt::format("filled {} holes", holes));
  }
  if (!CGAL::is_closed(sm))
    throw InputError(
        fmt::format("mesh '{}': open (has border edges) and CGAL could not close it", name));
  if (PMP::does_self_intersect(sm))
    throw InputError(
        fmt::format("mesh '{}': self-intersecting; repair it in a mesh editor "
                    "(CGAL cannot do it safely)",
                    name));
  const double volume = PMP::volume(sm);
  const Vec3 size = box.size();
  if (std::abs(volume) <= 1e-6 * size.prod())
    throw InputError(
        fmt::format("mesh '{}': degenerate, it encloses {:.3g} m^3, nearly none of "
                    "its {:.3g} m^3 box (flat?)",
                    name, volume, size.prod()));
  if (volume < 0.0)
    throw InputError(
        fmt::format("mesh '{}': inside-out, its triangles face inwards (signed "
                    "volume {:.3g} m^3); flip their orientation",
                    name, volume));
  return from_surface_mesh(sm);
}

}  // namespace shapepress::geometry
