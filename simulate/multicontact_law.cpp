#include "simulate/multicontact_law.hpp"

#include <fmt/format.h>

#include <cmath>

#include "common/error.hpp"
#include "simulate/materials.hpp"

namespace shapepress::simulate {

std::vector<OptionDoc> MulticontactLaw::options() {
  return {
      {"plasticity_ratio", "", "in (0, 1]", "1",
       "λp = k1/k2 of Eq. 6 (Giannis 2023): 1 is elastic; below 1 a contact unloads along the "
       "stiffer k2 and keeps a plastic overlap"},
      {"loading_stiffness", "N/m^1.5", "> 0", "4/3 E* sqrt(R*)",
       "k1 of Eq. 6, the loading branch k1 δ^{3/2} (a plain number: N/m^1.5 has no unit suffix)"},
      {"adhesion_stiffness", "N/m^1.5", ">= 0", "0",
       "kc of Eq. 6, the adhesive branch -kc δ^{3/2}"},
      {"pull_off_force", "N", "<= 0", "0", "F0 of Eq. 6, a constant attraction while touching"},
      {"multicontact_prefactor", "", ">= 0", "0",
       "β of the multi-contact term β ν A_ij P_ij of Eq. 6 (A_ij = π R* δ; P_ij: the pair's mean "
       "trace of the Love–Weber stress, a wall taking the sphere's own)"},
  };
}

MulticontactLaw MulticontactLaw::read(const ConfigTable& t) {
  MulticontactParameters m;
  m.plasticity_ratio = t.number("plasticity_ratio", 1.0, Range::open_closed(0.0, 1.0));
  if (t.has("loading_stiffness"))  // N/m^1.5: no unit suffix (not an integer dimension)
    m.loading_stiffness = t.number("loading_stiffness", std::nullopt, Range::positive());
  m.adhesion_stiffness = t.number("adhesion_stiffness", 0.0, Range::non_negative());
  m.pull_off_force =
      t.quantity("pull_off_force", dim::force, 0.0, Range{-HUGE_VAL, 0.0, true, true});
  m.prefactor = t.number("multicontact_prefactor", 0.0, Range::non_negative());
  return {m};
}

void MulticontactLaw::write_toml(std::string& out) const {
  const MulticontactParameters& m = parameters;
  out += fmt::format("plasticity_ratio = {:.17g}\n", m.plasticity_ratio);
  if (m.loading_stiffness)
    out += fmt::format("loading_stiffness = {:.17g}\n", *m.loading_stiffness);
  out += fmt::format("adhesion_stiffness = {:.17g}\npull_off_force = {:.17g}\n",
                     m.adhesion_stiffness, m.pull_off_force);
  out += fmt::format("multicontact_prefactor = {:.17g}\n", m.prefactor);
}

void MulticontactLaw::check(const std::string& where) const {
  const MulticontactParameters& m = parameters;
  if (!(m.plasticity_ratio > 0.0 && m.plasticity_ratio <= 1.0))
    throw InputError(where + ": plasticity_ratio must be in (0, 1]");
  if (m.loading_stiffness && !(*m.loading_stiffness > 0.0))
    throw InputError(where + ": loading_stiffness must be > 0");
  if (!(m.adhesion_stiffness >= 0.0)) throw InputError(where + ": adhesion_stiffness must be >= 0");
  if (!(m.pull_off_force <= 0.0))
    throw InputError(where + ": pull_off_force must be <= 0 (attractive)");
  if (!(m.prefactor >= 0.0)) throw InputError(where + ": multicontact_prefactor must be >= 0");
}

MulticontactLaw::Constants MulticontactLaw::constants(const Material& a, const Material& b) const {
  const MulticontactParameters& m = parameters;
  Constants k;
  k.loading_stiffness = m.loading_stiffness.value_or(0.0);
  k.unloading_factor = 1.0 / m.plasticity_ratio;
  k.plastic_fraction = 1.0 - m.plasticity_ratio;
  k.adhesion_stiffness = m.adhesion_stiffness;
  k.pull_off_force = m.pull_off_force;
  // ν of Eq. 6 for a pair (our choice; the paper has one material): the two Poisson ratios
  // weighted by compliance 1/E, so it is the particle's own ν between equal materials and
  // against a far stiffer tool. A_ij = π a², a² = R* δ (Hertz contact radius); P_ij the pair's
  // mean trace of the Love–Weber stress, ½(tr σ_i + tr σ_j) = 3 × the mean pressure the pair
  // loop passes: the reading Table 1's β = 1.71 implies for Fig. 1 (models.md, "Which reading
  // of Eq. 6").
  const double ca = 1.0 / a.youngs_modulus, cb = 1.0 / b.youngs_modulus;
  const double nu = (a.poisson_ratio * ca + b.poisson_ratio * cb) / (ca + cb);
  k.multicontact_factor = 3.0 * m.prefactor * nu * std::numbers::pi;
  // E*_L from the loading moduli as E* from the Young's moduli (Eq. 2, standard form): a stated
  // loading modulus of the particles reaches every contact through the same pair rule, a wall's
  // included, so one calibrated modulus sets the k1 of every size of contact.
  if (a.loading_modulus || b.loading_modulus) {
    const auto loading_solid = [](Material m) {
      m.youngs_modulus = m.loading_modulus.value_or(m.youngs_modulus);
      return m;
    };
    k.loading_factor = materials_effective_modulus(loading_solid(a), loading_solid(b)) /
                       materials_effective_modulus(a, b);
    k.loading_coefficient = 4.0 / 3.0 * k.loading_factor;
    k.loading_damping_factor = std::sqrt(k.loading_factor);
  }
  return k;
}

std::string MulticontactLaw::describe(const ElasticPair&, const Constants& k) {
  return fmt::format(
      "multicontact (Eq. 6), lambda_p = {:.6g}, k1 = {}, kc = {:.6g}, F0 = {:.6g} N, 3 beta nu pi "
      "= {:.6g}",
      1.0 / k.unloading_factor,
      k.loading_stiffness > 0.0 ? fmt::format("{:.6g} N/m^1.5", k.loading_stiffness)
      : k.loading_factor != 1.0
          ? fmt::format("4/3 E*_L sqrt(R*), E*_L = {:.6g} E*", k.loading_factor)
          : std::string("4/3 E* sqrt(R*)"),
      k.adhesion_stiffness, k.pull_off_force, k.multicontact_factor);
}

}  // namespace shapepress::simulate
