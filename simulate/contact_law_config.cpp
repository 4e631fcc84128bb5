#include "simulate/contact_law_config.hpp"

#include <algorithm>
#include <variant>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "common/error.hpp"

namespace shapepress::simulate {

std::vector<std::string> normal_law_names() {
  std::vector<std::string> names;
  for_each_normal_law([&]<class Law>() { names.emplace_back(Law::name); });
  return names;
}

std::string normal_law_name(const NormalLawChoice& law) {
  return std::visit([](const auto& l) { return std::string(std::decay_t<decltype(l)>::name); },
                    law);
}

NormalLawChoice read_normal_law(const ConfigTable& t, const std::string& where,
                                const std::optional<std::string>& replace) {
  const std::vector<std::string> names = normal_law_names();
  std::string name = t.choice("normal_law", names, names.front());
  if (replace) {
    if (std::find(names.begin(), names.end(), *replace) == names.end())
      throw InputError(
          fmt::format("unknown normal law '{}' (known: {})", *replace, fmt::join(names, ", ")));
    name = *replace;
  }
  std::optional<NormalLawChoice> out;
  std::vector<std::string> own_keys;
  for_each_normal_law([&]<class Law>() {
    if (Law::name != name) return;
    out = Law::read(t);
    for (const OptionDoc& o : Law::options())
      own_keys.push_back(o.key);
  });
  for_each_normal_law([&]<class Law>() {
    if (Law::name == name) return;
    std::vector<std::string> foreign;
    for (const OptionDoc& o : Law::options())
      if (t.has(o.key) && std::find(own_keys.begin(), own_keys.end(), o.key) == own_keys.end())
        foreign.push_back(o.key);
    if (!foreign.empty())
      throw InputError(
          fmt::format("{}: {} need normal_law = \"{}\" (the interaction's law is \"{}\")", where,
                      fmt::join(foreign, ", "), Law::name, name));
  });
  return *out;
}

std::string normal_law_toml(const NormalLawChoice& law) {
  std::string out = fmt::format("normal_law = \"{}\"\n", normal_law_name(law));
  std::visit([&](const auto& l) { l.write_toml(out); }, law);
  return out;
}

std::vector<OptionDoc> normal_law_options() {
  const std::vector<std::string> names = normal_law_names();
  std::vector<OptionDoc> rows = {
      {"normal_law", "", fmt::format("one of {}", fmt::join(names, ", ")), names.front(),
       "the normal contact law of the pair; the keys below belong to one law each"}};
  for_each_normal_law([&]<class Law>() {
    for (OptionDoc o : Law::options()) {
      o.help = fmt::format("(normal_law = \"{}\") {}", Law::name, o.help);
      rows.push_back(std::move(o));
    }
  });
  return rows;
}

std::string describe_normal_law(const PairConstants& pair) {
  return with_normal_law(
      pair.law, [&]<class Law>() { return Law::describe(pair, pair.constants_of<Law>()); });
}

}  // namespace shapepress::simulate
