#include "simulate/materials.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <type_traits>
#include <variant>

#include "common/error.hpp"

namespace shapepress::simulate {

double restitution_damping_factor(double restitution) {
  const double log_e = std::log(restitution);
  const double beta = log_e / std::sqrt(log_e * log_e + std::numbers::pi * std::numbers::pi);
  return -2.0 * std::sqrt(5.0 / 6.0) * beta;
}

double materials_effective_modulus(const Material& a, const Material& b) {
  return 1.0 / ((1.0 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus +
                (1.0 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus);
}

namespace {

void check_material(const Material& m) {
  if (!(m.youngs_modulus > 0.0))
    throw InputError("material '" + m.name + "': Young's modulus must be > 0");
  if (!(m.poisson_ratio > -1.0 && m.poisson_ratio < 0.5))
    throw InputError("material '" + m.name + "': Poisson's ratio must be in (-1, 0.5)");
  if (!(m.density >= 0.0)) throw InputError("material '" + m.name + "': density must be >= 0");
  if (m.loading_modulus && !(*m.loading_modulus > 0.0 && std::isfinite(*m.loading_modulus)))
    throw InputError("material '" + m.name + "': loading_modulus must be > 0");
}

// A loading modulus and a stated k1 or E* of the same pair would each set the loading branch.
void check_loading_modulus(const Material& a, const Material& b, const Interaction& in) {
  const Material* stated = a.loading_modulus ? &a : b.loading_modulus ? &b : nullptr;
  if (!stated) return;
  const std::string pair = "interaction " + in.first + "–" + in.second;
  const auto* law = std::get_if<MulticontactLaw>(&in.normal_law);
  if (law && law->parameters.loading_stiffness)
    throw InputError(pair + ": loading_stiffness and the loading_modulus of material '" +
                     stated->name + "' both set k1: give one");
  if (law && in.effective_modulus)
    throw InputError(pair + ": effective_modulus and the loading_modulus of material '" +
                     stated->name + "' both set the loading branch's modulus: give one");
}

// A loading modulus no multi-contact interaction reads would be silently ignored.
void check_loading_modulus_read(const std::vector<Material>& materials,
                                const std::vector<Interaction>& interactions) {
  for (const Material& m : materials) {
    if (!m.loading_modulus) continue;
    const bool read = std::any_of(interactions.begin(), interactions.end(), [&](const auto& in) {
      return (in.first == m.name || in.second == m.name) &&
             std::holds_alternative<MulticontactLaw>(in.normal_law);
    });
    if (!read)
      throw InputError("material '" + m.name +
                       "': loading_modulus is read by the multi-contact law only, and no "
                       "[[interaction]] of this material has normal_law = \"multicontact\"");
  }
}

PairConstants pair_constants(const Material& a, const Material& b, const Interaction& in) {
  // Eq. 2 of Giannis 2023 in its standard (non-inverted) form, models.md.
  const double shear_a = a.youngs_modulus / (2.0 * (1.0 + a.poisson_ratio));
  const double shear_b = b.youngs_modulus / (2.0 * (1.0 + b.poisson_ratio));
  PairConstants p;
  p.effective_modulus = materials_effective_modulus(a, b);
  p.effective_shear_modulus =
      1.0 / ((2.0 - a.poisson_ratio) / shear_a + (2.0 - b.poisson_ratio) / shear_b);
  if (in.effective_modulus) {  // Interaction::effective_modulus
    const double scale = *in.effective_modulus / p.effective_modulus;
    p.effective_modulus *= scale;
    p.effective_shear_modulus *= scale;
  }
  p.damping_factor = restitution_damping_factor(in.restitution);
  p.normal_damping_scale = p.damping_factor * std::sqrt(2.0 * p.effective_modulus);
  p.tangential_damping_scale = p.damping_factor * std::sqrt(8.0 * p.effective_shear_modulus);
  p.sliding_friction = in.sliding_friction;
  p.rolling_friction = in.rolling_friction;
  p.body_contact_radius = in.body_contact_radius;
  p.law = in.normal_law.index();
  std::visit(
      [&](const auto& law) {
        using Law = std::decay_t<decltype(law)>;
        std::get<normal_law_index<Law>>(p.constants) = law.constants(a, b);
      },
      in.normal_law);
  return p;
}

}  // namespace

MaterialTable::MaterialTable(std::vector<Material> materials,
                             const std::vector<Interaction>& interactions)
    : materials_(std::move(materials)), count_(static_cast<int>(materials_.size())) {
  if (materials_.empty()) throw InputError("no material given: at least one [[material]]");
  for (const Material& m : materials_)
    check_material(m);
  check_loading_modulus_read(materials_, interactions);
  const int n = count();
  pairs_.assign(static_cast<std::size_t>(n * n), PairConstants{});
  defined_.assign(static_cast<std::size_t>(n * n), 0);
  for (const Interaction& in : interactions) {
    if (!(in.restitution > 0.0 && in.restitution <= 1.0))
      throw InputError("interaction " + in.first + "–" + in.second +
                       ": restitution must be in (0, 1]");
    if (!(in.sliding_friction >= 0.0) || !(in.rolling_friction >= 0.0))
      throw InputError("interaction " + in.first + "–" + in.second +
                       ": friction coefficients must be >= 0");
    if (in.effective_modulus &&
        !(*in.effective_modulus > 0.0 && std::isfinite(*in.effective_modulus)))
      throw InputError("interaction " + in.first + "–" + in.second +
                       ": effective_modulus must be > 0");
    std::visit([&](const auto& law) { law.check("interaction " + in.first + "–" + in.second); },
               in.normal_law);
    const int i = index_of(in.first);
    const int j = index_of(in.second);
    check_loading_modulus(materials_[i], materials_[j], in);
    // The MDR law splits the overlap between the two spheres' own radii (mdr_law.hpp): the
    // bodies' R* would be silently unread.
    if (in.body_contact_radius && std::holds_alternative<MdrLaw>(in.normal_law))
      throw InputError("interaction " + in.first + "–" + in.second +
                       ": contact_radius = \"body\" is not read by normal_law = \"mdr\"");
    const PairConstants p = pair_constants(materials_[i], materials_[j], in);
    pairs_[i * n + j] = p;
    pairs_[j * n + i] = p;
    defined_[i * n + j] = defined_[j * n + i] = 1;
  }
  bool mixed = false;
  for (int k = 0; k < n * n; ++k)
    if (defined_[k]) {
      if (!single_law_) single_law_ = pairs_[k].law;
      mixed = mixed || *single_law_ != pairs_[k].law;
    }
  if (mixed) single_law_.reset();
}

int MaterialTable::index_of(const std::string& name) const {
  std::string known;
  for (int i = 0; i < count(); ++i) {
    if (materials_[i].name == name) return i;
    known += (i ? ", " : "") + materials_[i].name;
  }
  throw InputError("unknown material '" + name + "' (known: " + known + ")");
}

void MaterialTable::require_pair(int i, int j) const {
  if (!has_pair(i, j))
    throw InputError("no [[interaction]] between materials '" + materials_[i].name + "' and '" +
                     materials_[j].name + "'");
}

}  // namespace shapepress::simulate
