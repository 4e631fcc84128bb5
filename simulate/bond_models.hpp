#pragma once
// The registry of bond models: the constitutive law of a parallel bond (bonds.hpp), as
// normal_laws.hpp is the registry of the normal contact laws. Everything that depends on which
// models exist derives from the one list below: the `[bond] model` choice and its keys
// (read_bond_model, bond_model_toml, bond_model_options), the model's per-bond history
// (BondSet::History::model) and its snapshot datasets (snapshot.cpp), and the bond loop, which
// returns a yielding model's forces to its limits (bonds.cpp).
//
// A model is a value type holding its parameters, with
//   name, yields, history_fields, options(), read(ConfigTable), write_toml(out), check(),
// its history fields one per bond mode (normal, shear, twist, bending) when it has any.
// tests/unit/simulate/bond_model_reference_test.cpp replays tests/data/bond_models/<name>.csv
// (written by tests/data/bond_models/make_reference.py from the closed form) for every model
// listed here.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "common/config.hpp"
#include "common/option_doc.hpp"
#include "simulate/law_types.hpp"

namespace shapepress::simulate {

// Potyondy & Cundall 2004's linear elastic parallel bond (bonds.hpp): every mode elastic up to
// breakage. The default.
struct ElasticBond {
  static constexpr std::string_view name = "elastic";
  static constexpr bool yields = false;
  static constexpr std::array<HistoryField, 0> history_fields{};
  static std::vector<OptionDoc> options() { return {}; }
  static ElasticBond read(const ConfigTable&) { return {}; }
  void write_toml(std::string&) const {}
  void check() const {}
  friend bool operator==(const ElasticBond&, const ElasticBond&) = default;
};

// The elastic bond whose every mode yields at a stated stress and hardens linearly, keeping its
// plastic deformation on unloading (docs/models.md, "Elastic–plastic bonds"; after MUSEN's
// ElasticPerfectlyPlastic solid bond, which caps its normal and shear stresses each at the yield
// strength, and LAMMPS' bpm/spring/plastic, whose rest length follows the plastic strain). Each
// mode's elastic trial increment of P&C 2004's incremental law is returned to the mode's yield
// limit (return_to_yield below). The limits are independent per mode, as MUSEN's, each the force
// or moment at which that mode alone brings the rim of the bond's cross-section (A = π R̄²,
// I = π R̄⁴/4, J = π R̄⁴/2) to the yield stress, the terms of P&C's strength test (Eq. 11) taken
// one at a time:
//   |Fn| ≤ σy A,   |Fs| ≤ τy A,   |Mt| ≤ τy J/R̄,   |Mb| ≤ σy I/R̄,
// the same in tension and compression. A combined criterion (σ = |Fn|/A + |Mb| R̄/I ≤ σy) would
// couple the modes' returns into one system per bond; per-mode limits return each on its own, in
// closed form, and reduce to the combined one when one mode dominates.
// Hardening is isotropic and linear in the mode's accumulated plastic displacement κ = Σ|Δu_p|
// (m for the forces, rad for the moments): the limit grows as F_y(κ) = F_y0 + H k κ, with k the
// mode's elastic spring and H the stated hardening_ratio (the plastic modulus over the elastic;
// 0: elastic–perfectly plastic), so past yield the mode's tangent is k H/(1 + H) ≤ k.
struct ElasticPlasticBond {
  double yield_stress = std::numeric_limits<double>::infinity();        // σy [Pa]
  double shear_yield_stress = std::numeric_limits<double>::infinity();  // τy [Pa]
  double hardening_ratio = 0.0;                                         // H ≥ 0

  static constexpr std::string_view name = "elastic_plastic";
  static constexpr bool yields = true;
  static constexpr std::array<HistoryField, 4> history_fields{{
      {"normal_plastic_path", "m", "κn = Σ|Δun_p|, the accumulated plastic stretch and shortening"},
      {"shear_plastic_path", "m", "κs = Σ|Δus_p|, the accumulated plastic slip"},
      {"twist_plastic_path", "rad", "κt = Σ|Δθt_p|, the accumulated plastic twist"},
      {"bend_plastic_path", "rad", "κb = Σ|Δθb_p|, the accumulated plastic bending"},
  }};
  static std::vector<OptionDoc> options();
  static ElasticPlasticBond read(const ConfigTable& bond);
  void write_toml(std::string& out) const;
  void check() const;  // InputError naming the key
  friend bool operator==(const ElasticPlasticBond&, const ElasticPlasticBond&) = default;

  // The yield limits at κ = 0 of a bond of radius R̄, per mode (normal, shear, twist, bending):
  // σy A, τy A, τy J/R̄, σy I/R̄ [N, N, N m, N m].
  std::array<double, 4> yield_limits(double bond_radius) const;
};

// The registration: one entry per model, the first the default of `model`.
template <class... Models>
struct BondModelList {};
using BondModels = BondModelList<ElasticBond, ElasticPlasticBond>;

namespace bond_model_detail {

template <class List>
struct Registry;

template <class... Models>
struct Registry<BondModelList<Models...>> {
  using Choice = std::variant<Models...>;
  static constexpr std::size_t count = sizeof...(Models);
  // History arrays per bond: the most any model keeps (one model per run).
  static constexpr std::size_t history_size = std::max({Models::history_fields.size()...});
  static_assert(((Models::history_fields.size() == 0 || Models::history_fields.size() == 4) && ...),
                "a bond model's history is one field per mode, or none");
  template <class F>
  static void for_each(F&& f) {
    (f.template operator()<Models>(), ...);
  }
};

using Bond = Registry<BondModels>;

}  // namespace bond_model_detail

// A run's bond model with its parameters, as [bond] states it.
using BondModelChoice = bond_model_detail::Bond::Choice;
inline constexpr std::size_t bond_model_count = bond_model_detail::Bond::count;
// Doubles of model history per bond (BondSet::History::model).
inline constexpr std::size_t bond_model_history_size = bond_model_detail::Bond::history_size;

// f.template operator()<Model>() for every registered model, in order.
template <class F>
void for_each_bond_model(F&& f) {
  bond_model_detail::Bond::for_each(std::forward<F>(f));
}

// The registered models' names, the first the default ("elastic", "elastic_plastic").
std::vector<std::string> bond_model_names();
// The name of a model as `model` states it.
std::string bond_model_name(const BondModelChoice& model);
// Whether the model's modes yield (the bond loop then returns them to their limits).
inline bool bond_model_yields(const BondModelChoice& model) {
  return std::visit([](const auto& m) { return std::decay_t<decltype(m)>::yields; }, model);
}
// The history fields of the model (one per mode, or none).
std::vector<HistoryField> bond_model_history_fields(const BondModelChoice& model);

// Reads `model` and that model's keys from [bond]; `where` names the table in messages. A key of
// another model is an InputError naming the model it needs, so no key is silently unused; a bad
// value is one naming the key.
BondModelChoice read_bond_model(const ConfigTable& bond, const std::string& where);
// `model = "<name>"` and every parameter of the model, one `key = value` line each, as
// read_bond_model reads them back to the same values; empty for the default model, whose [bond]
// needs no line (so the default's written configs stay as they were).
std::string bond_model_toml(const BondModelChoice& model);
// The config reference rows: `model`, then every model's keys.
std::vector<OptionDoc> bond_model_options();

// One mode's return to its yield limit, after its elastic trial increment (the bond loop's
// increment of P&C 2004's law): with F* the trial force (or moment) and F_y = limit + hardening κ
// the present limit (hardening = H k),
//   |F*| ≤ F_y:  elastic, nothing changes;
//   |F*| > F_y:  Δκ = (|F*| - F_y)/(k + H k),  F = F* (1 - k Δκ/|F*|),  κ += Δκ,
// the backward-Euler return of linear isotropic hardening (Simo & Hughes 1998, Computational
// Inelasticity, §1.4.2), exact for any increment along a straight path. The vector modes (shear
// force, bending moment) return radially: the direction of F* is kept, its length reduced.
// Written without a branch, so that the bond loop's blocks vectorize it (GCC does not if-convert
// a division under a condition with trapping math): Δκ = max(|F*| - F_y, 0)/(k + H k), zero for
// an elastic trial, where F* (1 - k·0/|F*|) is F* to the bit and κ + 0 is κ (a +inf limit: the
// elastic model's bits). The divisor max(|F*|, DBL_MIN) keeps 0/0 out of a mode at rest, which
// never yields.
inline void return_to_yield(double& force, double& path, double spring, double limit,
                            double hardening) {
  const double magnitude = std::fabs(force);
  const double excess = magnitude - (limit + hardening * path);
  const double slip = std::max(excess, 0.0) / (spring + hardening);
  force = force * (1.0 - spring * slip / std::max(magnitude, std::numeric_limits<double>::min()));
  path = path + slip;
}
inline void return_to_yield(double force[3], double& path, double spring, double limit,
                            double hardening) {
  const double magnitude =
      std::sqrt(force[0] * force[0] + force[1] * force[1] + force[2] * force[2]);
  const double excess = magnitude - (limit + hardening * path);
  const double slip = std::max(excess, 0.0) / (spring + hardening);
  const double scale =
      1.0 - spring * slip / std::max(magnitude, std::numeric_limits<double>::min());
  for (int c = 0; c < 3; ++c)
    force[c] = force[c] * scale;
  path = path + slip;
}

}  // namespace shapepress::simulate
