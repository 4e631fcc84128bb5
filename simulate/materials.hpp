#pragma once
// Materials and the per-pair constants the contact loop reads (paper Table 3 layout: each pair of
// materials, particle–particle and particle–wall, has its own restitution and friction).
// Everything the force kernel needs that does not depend on the contact's geometry is computed
// here once, so the hot loop holds no pow and no logarithm (docs/architecture.md).
#include <cstddef>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "simulate/law_types.hpp"
#include "simulate/normal_laws.hpp"

namespace shapepress::simulate {

// What a user states about a pair of materials.
struct Interaction {
  std::string first;
  std::string second;
  double restitution = 0.5;       // e in (0, 1]
  double sliding_friction = 0.5;  // μs
  double rolling_friction = 0.0;  // μr (CDT, Ai et al. 2011 model A)
  // The normal sub-model with its parameters (normal_laws.hpp): Hertz, or the multi-contact
  // adhesive elastic–plastic law of Giannis et al. 2023 Eq. 6, …
  NormalLawChoice normal_law = HertzLaw{};
  // E* of the pair, replacing the one the two materials' E and ν give (G* scaled alike, so the
  // pair keeps its materials' ratio G*/E*). A bonded sub-sphere's contact material stands for
  // the body's interior, not its surface: against a plate, the stiffness of a contact is a
  // separate choice from the stiffness between sub-spheres (docs/models.md, "BMS: an elastic
  // network"). Absent: from the materials.
  std::optional<double> effective_modulus = std::nullopt;
  // `contact_radius = "body"`: a contact between sub-spheres of two different bodies takes R* of
  // the two bodies (their volume-equivalent radii) in its normal law, so that two bodies touch
  // with the curvature of the particles they stand for and not of the sub-spheres that happen to
  // meet; within a body, and against a wall, R* stays the sub-spheres' (docs/models.md, "Contacts
  // between bodies").
  bool body_contact_radius = false;
};

// Precomputed for a pair of material indices: the constants every law reads (ElasticPair) and
// those of the pair's normal law.
struct PairConstants : ElasticPair {
  std::size_t law = 0;  // index of the normal law in NormalLaws (NormalLawChoice::index())
  NormalLawConstants constants{};

  template <class Law>
  const typename Law::Constants& constants_of() const {
    return std::get<normal_law_index<Law>>(constants);
  }
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
  // The index of the one normal law every defined pair uses, or none when the pairs mix laws:
  // the pair loop is then compiled for that law alone (forces.cpp).
  std::optional<std::size_t> single_law() const { return single_law_; }

 private:
  std::vector<Material> materials_;
  int count_ = 0;  // materials_.size(), kept so the pair lookup in the contact loop is one multiply
  std::vector<PairConstants> pairs_;
  std::vector<char> defined_;
  std::optional<std::size_t> single_law_;
};

}  // namespace shapepress::simulate
