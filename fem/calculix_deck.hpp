#pragma once
// The CalculiX input deck (.inp) of the plate test: the sphere's meridian quarter as CAX4
// elements, a rigid flat plate above it pushed down by a prescribed displacement, penalty
// contact between them, symmetry at the axis and the equator plane. One static step, and a
// second that takes the plate back when the config unloads.
#include <string>

#include "fem/fem_plate_config.hpp"
#include "fem/quarter_disc_mesh.hpp"

namespace shapepress::fem {

// The deck is written in mm, N and MPa (consistent units; CalculiX's contact and convergence
// tolerances are tuned for engineering magnitudes, not 1e-5 m and 1e7 Pa). Its node set PLATE
// holds every plate node; its *NODE PRINT gives the plate's total reaction per increment.
inline constexpr const char* plate_node_set = "PLATE";
inline constexpr double deck_length_per_m = 1e3;    // mm per m
inline constexpr double deck_stress_per_pa = 1e-6;  // MPa per Pa

// CalculiX expands an axisymmetric element into a 2° wedge and reports its forces for that
// wedge (CalculiX 2.20 manual, "CAX" elements): the whole ring carries 180 times the printed
// reaction.
inline constexpr double axisymmetric_force_factor = 180.0;

// Neo-Hookean constants from the small-strain E and ν (CalculiX/Abaqus form
// W = C10 (Ī₁ − 3) + (J − 1)²/D1, so μ = 2 C10 and K = 2/D1):
// C10 = E / (4(1 + ν)), D1 = 6(1 − 2ν)/E.
struct NeoHookeConstants {
  double c10 = 0.0;
  double d1 = 0.0;
};
NeoHookeConstants neo_hooke_constants(double youngs_modulus, double poisson_ratio);

// Cards both plate decks share (the axisymmetric one here, the tetrahedral one in solid_deck):
// the particle's material (neo-Hookean or elastic, NAME=<elset>_MATERIAL) and the rigid plates'
// placeholder material, each with its solid section;
std::string material_cards(const FemPlateConfig& config, double modulus, const std::string& elset);
// the von Mises plasticity of a config with a yield stress: *PLASTIC, the yield stress against
// the equivalent plastic strain, σ = σy + H εp, as two points (0 and plastic_table_strain);
std::string plastic_card(const FemPlateConfig& config);
inline constexpr double plastic_table_strain = 10.0;
// the penalty contact PLATE_CONTACT of stiffness K (pressure = K × overclosure), with Coulomb
// friction when the config has it;
std::string plate_contact_interaction(const FemPlateConfig& config, double stiffness);
// the head of a static step, in config.increments equal increments;
std::string static_step_head(const FemPlateConfig& config);
// the unloading step when config.unload (else nothing): a static step with `boundary` (the
// plates' displacements back to zero) and the same `prints` as the loading step.
std::string unload_step(const FemPlateConfig& config, const std::string& boundary,
                        const std::string& prints);

std::string plate_deck(const QuarterDiscMesh& mesh, const FemPlateConfig& config);

}  // namespace shapepress::fem
