#pragma once
// Materials and the per-pair constants the contact loop reads (paper Table 3 layout: each pair of
// materials, particle–particle and particle–wall, has its own restitution and friction).
// Everything the force kernel needs that does not depend on the contact's geometry is computed
// here once, so the hot loop holds no pow and no logarithm (DESIGN.md "Pair constants").
#include <string>
#include <vector>

namespace shapepress::simulate {

struct Material {
  std::string name;
  double youngs_modulus = 0.0;  // E, Pa
  double poisson_ratio = 0.0;   // ν
  double density = 0.0;         // ρ, kg/m³ (unused for walls)
};

// The normal sub-model of a material pair. Only Hertz exists now; the multi-contact
// elastic–plastic law (paper Eq. 6) becomes one more enumerator and one more branch of
// normal_force() in contact_law.hpp, keeping its plastic overlap in ContactHistory.
enum class NormalLaw { hertz };

// What a user states about a pair of materials.
struct Interaction {
  std::string first;
  std::string second;
  double restitution = 0.5;       // e in (0, 1]
  double sliding_friction = 0.5;  // μs
  double rolling_friction = 0.0;  // μr (CDT, Ai et al. 2011 model A)
  NormalLaw normal_law = NormalLaw::hertz;
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
};

// β-damping factor of LIGGGHTS `gran model hertz`: -2√(5/6) ln e / √(ln² e + π²).
double restitution_damping_factor(double restitution);

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
