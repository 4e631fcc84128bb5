#include "simulate/materials.hpp"

#include <cmath>
#include <numbers>

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
}

void check_multicontact(const Interaction& in) {
  const std::string pair = "interaction " + in.first + "–" + in.second;
  if (!in.multicontact) return;
  if (in.normal_law != NormalLaw::multicontact)
    throw InputError(pair +
                     ": multi-contact parameters (plasticity_ratio, loading_stiffness, "
                     "adhesion_stiffness, pull_off_force, multicontact_prefactor) need "
                     "normal_law = \"multicontact\"");
  const MulticontactParameters& m = *in.multicontact;
  if (!(m.plasticity_ratio > 0.0 && m.plasticity_ratio <= 1.0))
    throw InputError(pair + ": plasticity_ratio must be in (0, 1]");
  if (m.loading_stiffness && !(*m.loading_stiffness > 0.0))
    throw InputError(pair + ": loading_stiffness must be > 0");
  if (!(m.adhesion_stiffness >= 0.0)) throw InputError(pair + ": adhesion_stiffness must be >= 0");
  if (!(m.pull_off_force <= 0.0))
    throw InputError(pair + ": pull_off_force must be <= 0 (attractive)");
  if (!(m.prefactor >= 0.0)) throw InputError(pair + ": multicontact_prefactor must be >= 0");
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
  p.normal_law = in.normal_law;
  if (in.normal_law == NormalLaw::multicontact) {
    const MulticontactParameters m = in.multicontact.value_or(MulticontactParameters{});
    p.loading_stiffness = m.loading_stiffness.value_or(0.0);
    p.unloading_factor = 1.0 / m.plasticity_ratio;
    p.plastic_fraction = 1.0 - m.plasticity_ratio;
    p.adhesion_stiffness = m.adhesion_stiffness;
    p.pull_off_force = m.pull_off_force;
    // ν of Eq. 6 for a pair (our choice; the paper has one material): the two Poisson ratios
    // weighted by compliance 1/E, so it is the particle's own ν between equal materials and
    // against a far stiffer tool. A_ij = π a², a² = R* δ (Hertz contact radius, models.md).
    const double ca = 1.0 / a.youngs_modulus, cb = 1.0 / b.youngs_modulus;
    const double nu = (a.poisson_ratio * ca + b.poisson_ratio * cb) / (ca + cb);
    p.multicontact_factor = m.prefactor * nu * std::numbers::pi;
  }
  return p;
}

}  // namespace

MaterialTable::MaterialTable(std::vector<Material> materials,
                             const std::vector<Interaction>& interactions)
    : materials_(std::move(materials)), count_(static_cast<int>(materials_.size())) {
  if (materials_.empty()) throw InputError("no material given: at least one [[material]]");
  for (const Material& m : materials_)
    check_material(m);
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
    check_multicontact(in);
    const int i = index_of(in.first);
    const int j = index_of(in.second);
    const PairConstants p = pair_constants(materials_[i], materials_[j], in);
    pairs_[i * n + j] = p;
    pairs_[j * n + i] = p;
    defined_[i * n + j] = defined_[j * n + i] = 1;
  }
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
