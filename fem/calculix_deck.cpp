#include "fem/calculix_deck.hpp"

#include <fmt/format.h>

namespace shapepress::fem {
namespace {

// The plate reaches this far out (× R): beyond the contact radius at 80 % deformation plus the
// sphere's bulge, so the sphere never slides off its edge.
constexpr double plate_half_width = 1.8;
constexpr double plate_thickness = 0.1;  // × R; its nodes are all prescribed, so it is rigid

void append_ids(std::string& deck, const std::vector<int>& ids) {
  for (std::size_t i = 0; i < ids.size(); ++i)
    deck += fmt::format("{}{}", ids[i], (i + 1) % 16 == 0 || i + 1 == ids.size() ? ",\n" : ",");
}

}  // namespace

NeoHookeConstants neo_hooke_constants(double youngs_modulus, double poisson_ratio) {
  return {youngs_modulus / (4.0 * (1.0 + poisson_ratio)),
          6.0 * (1.0 - 2.0 * poisson_ratio) / youngs_modulus};
}

std::string material_cards(const FemPlateConfig& config, double modulus, const std::string& elset) {
  std::string cards = fmt::format("*MATERIAL,NAME={}_MATERIAL\n", elset);
  if (config.material == MaterialModel::neo_hookean) {
    const NeoHookeConstants c = neo_hooke_constants(modulus, config.poisson_ratio);
    cards += fmt::format("*HYPERELASTIC,NEO HOOKE\n{:.15g},{:.15g}\n", c.c10, c.d1);
  } else {
    cards += fmt::format("*ELASTIC\n{:.15g},{:.15g}\n", modulus, config.poisson_ratio);
    if (config.plastic()) cards += plastic_card(config);
  }
  // The plate's material never strains (every plate node is prescribed); it only has to exist.
  cards += "*MATERIAL,NAME=PLATE_MATERIAL\n*ELASTIC\n210000,0.3\n";
  cards += fmt::format("*SOLID SECTION,ELSET={0},MATERIAL={0}_MATERIAL\n", elset);
  cards += "*SOLID SECTION,ELSET=PLATE_ELEMENTS,MATERIAL=PLATE_MATERIAL\n";
  return cards;
}

std::string plastic_card(const FemPlateConfig& config) {
  // CalculiX interpolates the table linearly in εp and holds its last stress beyond it: the
  // second point is far past any strain a pressed particle reaches, so the line is the law.
  const double yield = *config.yield_stress * deck_stress_per_pa;
  const double hardening = config.hardening_modulus * deck_stress_per_pa;
  std::string card = fmt::format("*PLASTIC\n{:.15g},0\n", yield);
  if (hardening > 0.0)
    card += fmt::format("{:.15g},{:.15g}\n", yield + hardening * plastic_table_strain,
                        plastic_table_strain);
  return card;
}

std::string plate_contact_interaction(const FemPlateConfig& config, double stiffness) {
  std::string cards = "*SURFACE INTERACTION,NAME=PLATE_CONTACT\n";
  cards += fmt::format("*SURFACE BEHAVIOR,PRESSURE-OVERCLOSURE=LINEAR\n{:.6g}\n", stiffness);
  if (config.friction > 0.0)
    cards += fmt::format("*FRICTION\n{:.6g},{:.6g}\n", config.friction, stiffness);
  return cards;
}

std::string static_step_head(const FemPlateConfig& config) {
  const double increment = 1.0 / config.increments;
  return fmt::format("*STEP,{}INC={}\n*STATIC\n{:.10g},1.0,{:.10g},{:.10g}\n",
                     config.nonlinear_geometry ? "NLGEOM," : "", 100 * config.increments + 1000,
                     increment, config.minimum_increment, increment);
}

std::string unload_step(const FemPlateConfig& config, const std::string& boundary,
                        const std::string& prints) {
  if (!config.unload) return {};
  return static_step_head(config) + boundary + prints + "*END STEP\n";
}

std::string plate_deck(const QuarterDiscMesh& mesh, const FemPlateConfig& config) {
  const double mm = deck_length_per_m;
  const double radius = mesh.radius * mm;
  const double polar_radius = mesh.polar_radius * mm;
  const double modulus = config.youngs_modulus * deck_stress_per_pa;
  std::string deck = fmt::format(
      "** shapepress fem-plate: a sphere of R = {} mm (polar semi-axis {} mm) between rigid "
      "plates,\n"
      "** axisymmetric (CAX4), the quarter r, z >= 0 of its meridian section; units mm, N, MPa\n",
      radius, polar_radius);
  deck += "*NODE\n";
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i)
    deck +=
        fmt::format("{},{:.15g},{:.15g}\n", i + 1, mesh.nodes[i][0] * mm, mesh.nodes[i][1] * mm);
  // The plate: one row of elements whose lower face, z = c (the pole), is the contact's master
  // surface.
  const int plate_columns = static_cast<int>(mesh.arc_faces.size());
  const int first_plate_node = static_cast<int>(mesh.nodes.size()) + 1;
  for (int row = 0; row < 2; ++row)
    for (int i = 0; i <= plate_columns; ++i)
      deck += fmt::format("{},{:.15g},{:.15g}\n", first_plate_node + row * (plate_columns + 1) + i,
                          plate_half_width * radius * i / plate_columns,
                          polar_radius + plate_thickness * radius * row);
  deck += "*ELEMENT,TYPE=CAX4,ELSET=SPHERE\n";
  for (std::size_t e = 0; e < mesh.quads.size(); ++e) {
    const auto& q = mesh.quads[e];
    deck += fmt::format("{},{},{},{},{}\n", e + 1, q[0], q[1], q[2], q[3]);
  }
  deck += "*ELEMENT,TYPE=CAX4,ELSET=PLATE_ELEMENTS\n";
  const int first_plate_element = static_cast<int>(mesh.quads.size()) + 1;
  for (int i = 0; i < plate_columns; ++i) {
    const int a = first_plate_node + i;
    const int b = a + plate_columns + 1;
    deck += fmt::format("{},{},{},{},{}\n", first_plate_element + i, a, a + 1, b + 1, b);
  }
  std::vector<int> plate_nodes;
  for (int i = 0; i < 2 * (plate_columns + 1); ++i)
    plate_nodes.push_back(first_plate_node + i);
  deck += fmt::format("*NSET,NSET={}\n", plate_node_set);
  append_ids(deck, plate_nodes);
  deck += "*NSET,NSET=AXIS\n";
  append_ids(deck, mesh.axis_nodes);
  deck += "*NSET,NSET=EQUATOR\n";
  append_ids(deck, mesh.equator_nodes);
  deck += fmt::format("*NSET,NSET=POLE\n{},\n", mesh.pole_node);
  deck += "*SURFACE,NAME=SPHERE_SURFACE,TYPE=ELEMENT\n";
  for (const auto& [element, face] : mesh.arc_faces)
    deck += fmt::format("{},S{}\n", element, face);
  // Face 1 of a plate element joins its first two nodes: the lower face.
  deck += "*SURFACE,NAME=PLATE_SURFACE,TYPE=ELEMENT\n";
  for (int i = 0; i < plate_columns; ++i)
    deck += fmt::format("{},S1\n", first_plate_element + i);

  deck += material_cards(config, modulus, "SPHERE");

  // Penalty contact: pressure = K × overclosure. K = factor × E / h at the pole keeps the
  // overclosure a small fraction of the pole element at the contact pressures (of order E).
  const double stiffness = config.penalty_factor * modulus / (pole_element_size(mesh) * mm);
  deck += plate_contact_interaction(config, stiffness);
  deck += "*CONTACT PAIR,INTERACTION=PLATE_CONTACT,TYPE=SURFACE TO SURFACE\n";
  deck += "SPHERE_SURFACE,PLATE_SURFACE\n";
  deck += "*BOUNDARY\nAXIS,1,1,0\nEQUATOR,2,2,0\n";

  // The step: the plate moves down by Δ/2 = max_deformation · c (the equator plane is the symmetry
  // plane, so the total approach of two plates is twice it), linearly in step time.
  deck += static_step_head(config);
  deck += fmt::format("*BOUNDARY\n{0},1,1,0\n{0},2,2,{1:.15g}\n", plate_node_set,
                      -config.max_deformation * polar_radius);
  const std::string prints = fmt::format("*NODE PRINT,NSET={},TOTALS=ONLY\nRF\n", plate_node_set) +
                             "*NODE PRINT,NSET=POLE\nU\n";
  deck += prints;
  deck += "*END STEP\n";
  // Unloading: the plate back to where it first touched (displacements are totals, ramped from
  // the first step's end over the second).
  deck += unload_step(config, fmt::format("*BOUNDARY\n{},2,2,0\n", plate_node_set), prints);
  return deck;
}

}  // namespace shapepress::fem
