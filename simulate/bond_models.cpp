#include "simulate/bond_models.hpp"

#include <numbers>
#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "common/error.hpp"
#include "common/units.hpp"

namespace shapepress::simulate {

std::vector<OptionDoc> ElasticPlasticBond::options() {
  return {
      {"yield_stress", "Pa", "> 0", "inf",
       "σy: the normal force yields at σy A and the bending moment at σy I/R̄, in tension and "
       "compression (inf: those modes stay elastic)"},
      {"shear_yield_stress", "Pa", "> 0", "inf",
       "τy: the shear force yields at τy A and the twisting moment at τy J/R̄ (inf: those modes "
       "stay elastic)"},
      {"hardening_ratio", "", ">= 0", "0",
       "H: each mode's plastic modulus over its elastic, the limit growing by H k per unit of "
       "accumulated plastic displacement (tangent k H/(1 + H) past yield; 0: perfectly plastic)"},
  };
}

ElasticPlasticBond ElasticPlasticBond::read(const ConfigTable& t) {
  ElasticPlasticBond m;
  m.yield_stress = t.quantity("yield_stress", dim::pressure, m.yield_stress, Range::positive());
  m.shear_yield_stress =
      t.quantity("shear_yield_stress", dim::pressure, m.shear_yield_stress, Range::positive());
  m.hardening_ratio = t.number("hardening_ratio", m.hardening_ratio, Range::non_negative());
  if (!std::isfinite(m.hardening_ratio))
    throw InputError(t.source_name() + ": key '" + t.path_of("hardening_ratio") +
                     "' must be finite");
  return m;
}

void ElasticPlasticBond::write_toml(std::string& out) const {
  // TOML spells infinity `inf`; {:.17g} writes it so.
  out += fmt::format("yield_stress = {:.17g}\nshear_yield_stress = {:.17g}\n", yield_stress,
                     shear_yield_stress);
  out += fmt::format("hardening_ratio = {:.17g}\n", hardening_ratio);
}

void ElasticPlasticBond::check() const {
  if (!(yield_stress > 0.0))
    throw InputError(fmt::format("yield_stress = {} Pa must be > 0", yield_stress));
  if (!(shear_yield_stress > 0.0))
    throw InputError(fmt::format("shear_yield_stress = {} Pa must be > 0", shear_yield_stress));
  if (!(hardening_ratio >= 0.0 && std::isfinite(hardening_ratio)))
    throw InputError(fmt::format("hardening_ratio = {} must be >= 0", hardening_ratio));
}

std::array<double, 4> ElasticPlasticBond::yield_limits(double r) const {
  const double area = std::numbers::pi * r * r;
  const double polar = 0.5 * std::numbers::pi * r * r * r * r;  // J = π R̄⁴/2, I = J/2
  return {yield_stress * area, shear_yield_stress * area, shear_yield_stress * polar / r,
          yield_stress * 0.5 * polar / r};
}

std::vector<std::string> bond_model_names() {
  std::vector<std::string> names;
  for_each_bond_model([&]<class Model>() { names.emplace_back(Model::name); });
  return names;
}

std::string bond_model_name(const BondModelChoice& model) {
  return std::visit([](const auto& m) { return std::string(std::decay_t<decltype(m)>::name); },
                    model);
}

std::vector<HistoryField> bond_model_history_fields(const BondModelChoice& model) {
  return std::visit(
      [](const auto& m) {
        const auto& fields = std::decay_t<decltype(m)>::history_fields;
        return std::vector<HistoryField>(fields.begin(), fields.end());
      },
      model);
}

BondModelChoice read_bond_model(const ConfigTable& t, const std::string& where) {
  const std::vector<std::string> names = bond_model_names();
  const std::string name = t.choice("model", names, names.front());
  std::optional<BondModelChoice> out;
  std::vector<std::string> own_keys;
  for_each_bond_model([&]<class Model>() {
    if (Model::name != name) return;
    out = Model::read(t);
    for (const OptionDoc& o : Model::options())
      own_keys.push_back(o.key);
  });
  for_each_bond_model([&]<class Model>() {
    if (Model::name == name) return;
    std::vector<std::string> foreign;
    for (const OptionDoc& o : Model::options())
      if (t.has(o.key) && std::find(own_keys.begin(), own_keys.end(), o.key) == own_keys.end())
        foreign.push_back(o.key);
    if (!foreign.empty())
      throw InputError(fmt::format("{}: {} need model = \"{}\" (the bonds' model is \"{}\")", where,
                                   fmt::join(foreign, ", "), Model::name, name));
  });
  try {
    std::visit([](const auto& m) { m.check(); }, *out);
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
  return *out;
}

std::string bond_model_toml(const BondModelChoice& model) {
  if (model.index() == 0) return {};
  std::string out = fmt::format("model = \"{}\"\n", bond_model_name(model));
  std::visit([&](const auto& m) { m.write_toml(out); }, model);
  return out;
}

std::vector<OptionDoc> bond_model_options() {
  const std::vector<std::string> names = bond_model_names();
  std::vector<OptionDoc> rows = {
      {"model", "", fmt::format("one of {}", fmt::join(names, ", ")), names.front(),
       "the bonds' constitutive model: elastic (Potyondy–Cundall), or elastic_plastic (every mode "
       "yields at a stated stress and hardens linearly, keeping its plastic deformation); the "
       "keys below belong to one model each"}};
  for_each_bond_model([&]<class Model>() {
    for (OptionDoc o : Model::options()) {
      o.help = fmt::format("(model = \"{}\") {}", Model::name, o.help);
      rows.push_back(std::move(o));
    }
  });
  return rows;
}

}  // namespace shapepress::simulate
