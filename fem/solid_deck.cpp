#include "fem/solid_deck.hpp"

#include <cmath>

#include <fmt/format.h>

#include "fem/calculix_deck.hpp"

namespace shapepress::fem {
namespace {

constexpr int plate_cells = 4;           // per side: the plate is flat, its mesh only has to exist
constexpr double plate_thickness = 0.1;  // × the plate's half-width

void append_ids(std::string& deck, const std::vector<int>& ids) {
  for (std::size_t i = 0; i < ids.size(); ++i)
    deck += fmt::format("{}{}", ids[i], (i + 1) % 16 == 0 || i + 1 == ids.size() ? ",\n" : ",");
}

// A square plate of C3D8 bricks with its contact face at z = `face`, the brick above it
// (`above`) or below it. Appends nodes and elements from the given first ids; returns its node
// ids and writes its element ids.
std::vector<int> plate_nodes(std::string& nodes, std::string& elements, int first_node,
                             int first_element, double half_width, double face, bool above,
                             std::vector<int>& element_ids) {
  const double thickness = plate_thickness * half_width;
  const double lower = above ? face : face - thickness;
  const int n = plate_cells + 1;
  std::vector<int> ids;
  for (int layer = 0; layer < 2; ++layer)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int id = first_node + layer * n * n + j * n + i;
        ids.push_back(id);
        nodes += fmt::format("{},{:.15g},{:.15g},{:.15g}\n", id,
                             half_width * (2.0 * i / plate_cells - 1.0),
                             half_width * (2.0 * j / plate_cells - 1.0), lower + layer * thickness);
      }
  int id = first_element;
  for (int j = 0; j < plate_cells; ++j)
    for (int i = 0; i < plate_cells; ++i) {
      const int a = first_node + j * n + i;  // lower layer, counter-clockwise seen from +z
      const int b = a + 1, c = a + n + 1, d = a + n;
      elements += fmt::format("{},{},{},{},{},{},{},{},{}\n", id, a, b, c, d, a + n * n, b + n * n,
                              c + n * n, d + n * n);
      element_ids.push_back(id++);
    }
  return ids;
}

}  // namespace

double deck_units_per_m(double height) {
  return std::pow(10.0, std::ceil(std::log10(10.0 / height)));
}

double deck_force_in_newtons(double units_per_m) {
  return 1.0 / (deck_stress_per_pa * units_per_m * units_per_m);
}

std::string solid_plate_deck(const TetMesh& mesh, const SolidPlates& plates,
                             const FemPlateConfig& config) {
  const double mm = plates.units_per_m;
  const double modulus = config.youngs_modulus * deck_stress_per_pa;
  std::string deck = fmt::format(
      "** shapepress fem-plate: a particle of height {:.6g} units between rigid plates, 3D, "
      "C3D10 tetrahedra; length unit {:.6g} m, stress MPa, force {:.6g} N\n",
      (plates.top - plates.bottom) * mm, 1.0 / mm, deck_force_in_newtons(mm));
  deck += "*NODE\n";
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i)
    deck += fmt::format("{},{:.15g},{:.15g},{:.15g}\n", i + 1, mesh.nodes[i].x() * mm,
                        mesh.nodes[i].y() * mm, mesh.nodes[i].z() * mm);
  std::string plate_elements;
  std::vector<int> top_elements, bottom_elements;
  const int first_plate_node = static_cast<int>(mesh.nodes.size()) + 1;
  const int first_plate_element = static_cast<int>(mesh.elements.size()) + 1;
  const int plate_node_count = 2 * (plate_cells + 1) * (plate_cells + 1);
  const std::vector<int> top_nodes =
      plate_nodes(deck, plate_elements, first_plate_node, first_plate_element,
                  plates.half_width * mm, plates.top * mm, true, top_elements);
  const std::vector<int> bottom_nodes =
      plate_nodes(deck, plate_elements, first_plate_node + plate_node_count,
                  first_plate_element + plate_cells * plate_cells, plates.half_width * mm,
                  plates.bottom * mm, false, bottom_elements);
  deck += "*ELEMENT,TYPE=C3D10,ELSET=PARTICLE\n";
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    deck += fmt::format("{}", e + 1);
    for (int n : mesh.elements[e])
      deck += fmt::format(",{}", n + 1);
    deck += "\n";
  }
  deck += "*ELEMENT,TYPE=C3D8,ELSET=PLATE_ELEMENTS\n" + plate_elements;
  deck += fmt::format("*NSET,NSET={}\n", top_plate_node_set);
  append_ids(deck, top_nodes);
  deck += fmt::format("*NSET,NSET={}\n", bottom_plate_node_set);
  append_ids(deck, bottom_nodes);
  // The particle's faces facing each plate: the boundary faces above (below) the centroid.
  std::string top_faces, bottom_faces;
  for (const auto& [element, face] : boundary_faces(mesh)) {
    const auto corners = face_corners(mesh.elements[static_cast<std::size_t>(element)], face);
    const double z =
        (mesh.nodes[corners[0]].z() + mesh.nodes[corners[1]].z() + mesh.nodes[corners[2]].z()) /
        3.0;
    (z > 0.0 ? top_faces : bottom_faces) += fmt::format("{},S{}\n", element + 1, face);
  }
  deck += "*SURFACE,NAME=PARTICLE_TOP,TYPE=ELEMENT\n" + top_faces;
  deck += "*SURFACE,NAME=PARTICLE_BOTTOM,TYPE=ELEMENT\n" + bottom_faces;
  // C3D8 face 1 is nodes 1-2-3-4 (the lower layer), face 2 nodes 5-8 (the upper).
  deck += "*SURFACE,NAME=TOP_PLATE_FACE,TYPE=ELEMENT\n";
  for (int e : top_elements)
    deck += fmt::format("{},S1\n", e);
  deck += "*SURFACE,NAME=BOTTOM_PLATE_FACE,TYPE=ELEMENT\n";
  for (int e : bottom_elements)
    deck += fmt::format("{},S2\n", e);

  deck += material_cards(config, modulus, "PARTICLE");
  // Penalty contact as in the axisymmetric deck: K = factor × E / h at the contact.
  const double stiffness = config.penalty_factor * modulus / (plates.contact_size * mm);
  deck += plate_contact_interaction(config, stiffness);
  deck +=
      "*CONTACT PAIR,INTERACTION=PLATE_CONTACT,TYPE=SURFACE TO SURFACE\n"
      "PARTICLE_TOP,TOP_PLATE_FACE\n";
  deck +=
      "*CONTACT PAIR,INTERACTION=PLATE_CONTACT,TYPE=SURFACE TO SURFACE\n"
      "PARTICLE_BOTTOM,BOTTOM_PLATE_FACE\n";
  // 3-2-1: statically determinate, so the constraints hold only the rigid-body modes.
  deck += fmt::format("*BOUNDARY\n{0},1,3,0\n{1},2,3,0\n{2},3,3,0\n", mesh.anchors.at(0) + 1,
                      mesh.anchors.at(1) + 1, mesh.anchors.at(2) + 1);

  const double approach = config.max_deformation * (plates.top - plates.bottom) * mm;
  deck += static_step_head(config);
  deck += fmt::format("*BOUNDARY\n{0},1,2,0\n{0},3,3,{1:.15g}\n{2},1,2,0\n{2},3,3,{3:.15g}\n",
                      top_plate_node_set, -0.5 * approach, bottom_plate_node_set, 0.5 * approach);
  const std::string prints =
      fmt::format("*NODE PRINT,NSET={},TOTALS=ONLY\nRF\n", top_plate_node_set) +
      fmt::format("*NODE PRINT,NSET={},TOTALS=ONLY\nRF\n", bottom_plate_node_set);
  deck += prints;
  deck += "*END STEP\n";
  deck += unload_step(
      config,
      fmt::format("*BOUNDARY\n{},3,3,0\n{},3,3,0\n", top_plate_node_set, bottom_plate_node_set),
      prints);
  return deck;
}

}  // namespace shapepress::fem
