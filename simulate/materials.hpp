#pragma once
// Materials and the per-pair constants the contact loop reads (paper Table 3 layout: each pair of
// materials, particle–particle and particle–wall, has its own restitution and friction).
// Everything the force kernel needs that does not depend on the contact's geometry is computed
// here once, so the hot loop holds no pow and no logarithm (docs/architecture.md).
#include <optional>
#include <string>
#include <vector>

namespace shapepress::simulate {

struct Material {
  std::string name;
  double youngs_modulus = 0.0;  // E, Pa
  double poisson_ratio = 0.0;   // ν
  double density = 0.0;         // ρ, kg/m³ (unused for walls)
};

// The normal sub-model of a material pair: Hertz, or the multi-contact adhesive elastic–plastic
// law of Giannis et al. 2023 Eq. 6 (multicontact_law.hpp), which keeps its largest overlap in
// ContactHistory and reads the particles' Love–Weber pressure.
enum class NormalLaw { hertz, multicontact };

// What a user states for the multi-contact law (models.md "Multi-contact adhesive elastic–plastic
// law"). The defaults make it Hertz–Mindlin: λp = 1, kc = 0, F0 = 0, β = 0.
struct MulticontactParameters {
  std::optional<double> loading_stiffness =
      std::nullopt;                 // k1, N/m^1.5; absent: 4/3 E* √R* per contact
  double plasticity_ratio = 1.0;    // λp = k1/k2 in (0, 1]; 1: elastic
  double adhesion_stiffness = 0.0;  // kc ≥ 0, N/m^1.5
  double pull_off_force = 0.0;      // F0 ≤ 0, N (constant attraction while touching)
  double prefactor = 0.0;           // β ≥ 0 of the term β ν A_ij P_ij
};

// What a user states about a pair of materials.
struct Interaction {
  std::string first;
  std::string second;
  double restitution = 0.5;       // e in (0, 1]
  double sliding_friction = 0.5;  // μs
  double rolling_friction = 0.0;  // μr (CDT, Ai et al. 2011 model A)
  NormalLaw normal_law = NormalLaw::hertz;
  // Given only with normal_law = multicontact (an InputError otherwise: no silently unused key).
  std::optional<MulticontactParameters> multicontact = std::nullopt;
  // E* of the pair, replacing the one the two materials' E and ν give (G* scaled alike, so the
  // pair keeps its materials' ratio G*/E*). A bonded sub-sphere's contact material stands for
  // the body's interior, not its surface: against a plate, the stiffness of a contact is a
  // separate choice from the stiffness between sub-spheres (docs/models.md, "BMS: an elastic
  // network"). Absent: from the materials.
  std::optional<double> effective_modulus = std::nullopt;
};

// Precomputed for a pair of material indices (models.md "Hertz–Mindlin with restitution").
struct PairConstants {
  double effective_modulus = 0.0;        // E*: 1/E* = (1-νi²)/Ei + (1-νj²)/Ej
  double effective_shear_modulus = 0.0;  // G*: 1/G* = (2-νi)/Gi + (2-νj)/Gj
  double damping_factor = 0.0;           // -2 √(5/6) β ≥ 0, β = ln e / √(ln² e + π²)
  // γn = normal_damping_scale √(√(R*δ) m*), γt = tangential_damping_scale √(√(R*δ) m*): the
  // damping of contact_law.hpp with the constant roots taken here, so a contact needs one sqrt.
  double normal_damping_scale = 0.0;      // damping_factor √(2 E*)
  double tangential_damping_scale = 0.0;  // damping_factor √(8 G*)
  double sliding_friction = 0.0;
  double rolling_friction = 0.0;
  NormalLaw normal_law = NormalLaw::hertz;
  // Multi-contact law (Eq. 6), unused by Hertz:
  double loading_stiffness = 0.0;    // k1, N/m^1.5; 0: 4/3 E* √R* per contact (Hertz)
  double unloading_factor = 1.0;     // k2/k1 = 1/λp
  double plastic_fraction = 0.0;     // 1 - λp: δp^{3/2} = (1 - k1/k2) δmax^{3/2}
  double adhesion_stiffness = 0.0;   // kc
  double pull_off_force = 0.0;       // F0 ≤ 0
  double multicontact_factor = 0.0;  // β ν π: β ν A_ij P_ij with A_ij = π R* δ
};

// β-damping factor of LIGGGHTS `gran model hertz`: -2√(5/6) ln e / √(ln² e + π²).
double restitution_damping_factor(double restitution);

// E* of two materials in contact: 1/E* = (1-νa²)/Ea + (1-νb²)/Eb (before any stated
// Interaction::effective_modulus).
double materials_effective_modulus(const Material& a, const Material& b);

// Pair tables for n materials: pair(i, j) == pair(j, i). Every pair of materials that can meet
// needs an Interaction; a missing one is an InputError naming both materials.
class MaterialTable {
 public:
  MaterialTable(std::vector<Material> materials, const std::vector<Interaction>& interactions);

  int count() const { return count_; }
  const Material& material(int index) const { return materials_[index]; }
  int index_of(const std::string& name) const;  // InputError listing the known names
  const PairConstants& pair(int i, int j) const { return pairs_[i * count_ + j]; }
  bool has_pair(int i, int j) const { return defined_[i * count() + j] != 0; }
  // InputError naming the two materials when their interaction was not given.
  void require_pair(int i, int j) const;

 private:
  std::vector<Material> materials_;
  int count_ = 0;  // materials_.size(), kept so the pair lookup in the contact loop is one multiply
  std::vector<PairConstants> pairs_;
  std::vector<char> defined_;
};

}  // namespace shapepress::simulate
