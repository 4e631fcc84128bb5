#include "common/config.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "common/error.hpp"
#include "common/suggest.hpp"

namespace shapepress {

struct ConfigTable::Document {
  std::string source_name;
  std::string text;
  toml::table root;
  mutable std::set<std::string> used;   // dotted paths a getter asked for and found
  mutable std::set<std::string> asked;  // every path a getter asked for (the known keys)
};

bool Range::contains(double v) const {
  bool above = min_inclusive ? v >= min : v > min;
  bool below = max_inclusive ? v <= max : v < max;
  return above && below;
}

std::string Range::describe() const {
  bool has_min = std::isfinite(min);
  bool has_max = std::isfinite(max);
  if (has_min && has_max)
    return fmt::format("in {}{:g}, {:g}{}", min_inclusive ? '[' : '(', min, max,
                       max_inclusive ? ']' : ')');
  if (has_min) return fmt::format("{} {:g}", min_inclusive ? ">=" : ">", min);
  if (has_max) return fmt::format("{} {:g}", max_inclusive ? "<=" : "<", max);
  return "any number";
}

namespace {

const toml::table& as_table(const void* node) {
  return *static_cast<const toml::table*>(node);
}

std::string where(const std::string& source, const toml::node& node) {
  const toml::source_region& region = node.source();
  if (region.begin.line == 0) return source;
  return fmt::format("{}:{}", source, region.begin.line);
}

}  // namespace

ConfigTable::ConfigTable(std::shared_ptr<Document> document, const void* node, std::string prefix)
    : document_(std::move(document)), node_(node), prefix_(std::move(prefix)) {}

ConfigTable ConfigTable::parse(std::string_view text, std::string source_name) {
  auto document = std::make_shared<Document>();
  document->source_name = std::move(source_name);
  document->text = std::string(text);
  try {
    document->root = toml::parse(document->text, document->source_name);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}:{}: malformed TOML: {}", document->source_name,
                                 e.source().begin.line, e.source().begin.column, e.description()));
  }
  const void* root = &document->root;
  return ConfigTable(std::move(document), root, "");
}

ConfigTable ConfigTable::load_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the config file", path.string()));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw InputError(fmt::format("{}: cannot read the config file", path.string()));
  return parse(buffer.str(), path.string());
}

std::string ConfigTable::path_of(std::string_view key) const {
  return prefix_ + std::string(key);
}
const std::string& ConfigTable::source_name() const {
  return document_->source_name;
}
const std::string& ConfigTable::text() const {
  return document_->text;
}

bool ConfigTable::has(std::string_view key) const {
  return as_table(node_).contains(key);
}

struct ConfigTable::Lookup {
  const toml::node* node;
  std::string full;      // dotted path, "material.E"
  std::string location;  // "file:line" of the value, or the file when the key is absent
};

ConfigTable::Lookup ConfigTable::lookup(std::string_view key) const {
  const toml::node* node = as_table(node_).get(key);
  std::string full = path_of(key);
  if (node != nullptr) document_->used.insert(full);
  document_->asked.insert(full);
  std::string location = node ? where(document_->source_name, *node) : document_->source_name;
  return {node, std::move(full), std::move(location)};
}

namespace {

[[noreturn]] void wrong_type(const std::string& location, const std::string& key,
                             std::string_view expected, const toml::node* given = nullptr) {
  std::string value;
  if (given != nullptr) {
    std::ostringstream text;
    given->visit([&](const auto& value) { text << value; });
    value = text.str();
    if (value.size() > 60) value = value.substr(0, 57) + "...";
    value = fmt::format(", not {}", value);
  }
  throw InputError(fmt::format("{}: key '{}' must be {}{}", location, key, expected, value));
}

[[noreturn]] void missing(const std::string& source, const std::string& key,
                          std::string_view expected) {
  throw InputError(fmt::format("{}: missing required key '{}' ({})", source, key, expected));
}

void check_range(const std::string& location, const std::string& key, double value, Range range,
                 std::string_view unit = "") {
  if (std::isnan(value))
    throw InputError(fmt::format("{}: key '{}' is NaN, a number {} was expected", location, key,
                                 range.describe()));
  if (!range.contains(value))
    throw InputError(fmt::format("{}: key '{}' = {:g}{}{} is out of range: must be {}", location,
                                 key, value, unit.empty() ? "" : " ", unit, range.describe()));
}

std::optional<double> numeric(const toml::node& node) {
  if (auto f = node.as_floating_point()) return f->get();
  if (auto i = node.as_integer()) return static_cast<double>(i->get());
  return std::nullopt;
}

}  // namespace

double ConfigTable::number(std::string_view key, std::optional<double> fallback,
                           Range range) const {
  auto [node, full, location] = lookup(key);
  if (node == nullptr) {
    if (!fallback) missing(location, full, "a number");
    return *fallback;
  }
  std::optional<double> value = numeric(*node);
  if (!value) wrong_type(location, full, "a number", node);
  check_range(location, full, *value, range);
  return *value;
}

std::int64_t ConfigTable::integer(std::string_view key, std::optional<std::int64_t> fallback,
                                  Range range) const {
  auto [node, full, location] = lookup(key);
  if (node == nullptr) {
    if (!fallback) missing(location, full, "an integer");
    return *fallback;
  }
  auto value = node->as_integer();
  if (value == nullptr) wrong_type(location, full, "an integer", node);
  check_range(location, full, static_cast<double>(value->get()), range);
  return value->get();
}

bool ConfigTable::boolean(std::string_view key, std::optional<bool> fallback) const {
  auto [node, full, location] = lookup(key);
  if (node == nullptr) {
    if (!fallback) missing(location, full, "true or false");
    return *fallback;
  }
  auto value = node->as_boolean();
  if (value == nullptr) wrong_type(location, full, "true or false", node);
  return value->get();
}

std::string ConfigTable::string(std::string_view key, std::optional<std::string> fallback) const {
  auto [node, full, location] = lookup(key);
  if (node == nullptr) {
    if (!fallback) missing(location, full, "a string");
    return *fallback;
  }
  auto value = node->as_string();
  if (value == nullptr) wrong_type(location, full, "a string", node);
  return value->get();
}

std::string ConfigTable::choice(std::string_view key, const std::vector<std::string>& choices,
                                std::optional<std::string> fallback) const {
  std::string value = string(key, std::move(fallback));
  for (const std::string& c : choices)
    if (c == value) return value;
  const toml::node* node = as_table(node_).get(key);
  std::string location = node ? where(document_->source_name, *node) : document_->source_name;
  throw InputError(fmt::format("{}: key '{}' = \"{}\" is not one of: {}", location, path_of(key),
                               value, fmt::join(choices, ", ")));
}

double ConfigTable::quantity(std::string_view key, Dimension dimension,
                             std::optional<double> fallback, Range range) const {
  auto [node, full, location] = lookup(key);
  std::string expected = fmt::format("a {} (number in {} or a string with a unit)",
                                     dimension_name(dimension), si_unit(dimension));
  if (node == nullptr) {
    if (!fallback) missing(location, full, expected);
    return *fallback;
  }
  double value = 0.0;
  if (std::optional<double> n = numeric(*node)) {
    value = *n;
  } else if (auto s = node->as_string()) {
    try {
      value = parse_quantity(s->get(), dimension, full);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", location, e.what()));
    }
  } else {
    wrong_type(location, full, expected, node);
  }
  check_range(location, full, value, range, si_unit(dimension));
  return value;
}

std::vector<double> ConfigTable::numbers(std::string_view key, Range range) const {
  return quantities(key, dim::dimensionless, range);
}

std::vector<double> ConfigTable::quantities(std::string_view key, Dimension dimension,
                                            Range range) const {
  auto [node, full, location] = lookup(key);
  if (node == nullptr) missing(location, full, "an array of numbers");
  const toml::array* array = node->as_array();
  if (array == nullptr) wrong_type(location, full, "an array of numbers", node);
  std::vector<double> values;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& item = *array->get(i);
    std::string item_key = fmt::format("{}[{}]", full, i);
    double value = 0.0;
    if (std::optional<double> n = numeric(item)) {
      value = *n;
    } else if (auto s = item.as_string(); s != nullptr && !(dimension == dim::dimensionless)) {
      try {
        value = parse_quantity(s->get(), dimension, item_key);
      } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", location, e.what()));
      }
    } else {
      wrong_type(location, item_key, "a number", &item);
    }
    check_range(location, item_key, value, range);
    values.push_back(value);
  }
  return values;
}

ConfigTable ConfigTable::table(std::string_view key) const {
  auto [node, full, location] = lookup(key);
  if (node == nullptr) missing(location, full, "a table [" + full + "]");
  const toml::table* t = node->as_table();
  if (t == nullptr) wrong_type(location, full, "a table", node);
  return ConfigTable(document_, t, full + ".");
}

std::vector<ConfigTable> ConfigTable::tables(std::string_view key) const {
  auto [node, full, location] = lookup(key);
  std::vector<ConfigTable> out;
  if (node == nullptr) return out;
  const toml::array* array = node->as_array();
  if (array == nullptr) wrong_type(location, full, "an array of tables [[" + full + "]]", node);
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::table* t = array->get(i)->as_table();
    if (t == nullptr) wrong_type(location, fmt::format("{}[{}]", full, i), "a table");
    std::string element = fmt::format("{}[{}]", full, i);
    document_->used.insert(element);
    out.push_back(ConfigTable(document_, t, element + "."));
  }
  return out;
}

namespace {

// The keys a getter asked for in the table at `prefix` ("run." , "material[0]."): what a
// misspelt key there was probably meant to be.
std::vector<std::string> known_keys(const std::set<std::string>& asked, const std::string& prefix) {
  std::vector<std::string> keys;
  for (const std::string& path : asked)
    if (path.starts_with(prefix) && path.find_first_of(".[", prefix.size()) == std::string::npos)
      keys.push_back(path.substr(prefix.size()));
  return keys;
}

void collect_unknown(const toml::table& table, const std::string& prefix,
                     const std::set<std::string>& used, const std::set<std::string>& asked,
                     const std::string& source, std::vector<std::string>& unknown) {
  for (const auto& [k, node] : table) {
    std::string path = prefix + std::string(k.str());
    if (!used.contains(path)) {
      const std::optional<std::string> meant = closest_match(k.str(), known_keys(asked, prefix));
      unknown.push_back(fmt::format(
          "{}: unknown key '{}'{}", where(source, node), path,
          meant ? fmt::format(" (did you mean '{}{}'?)", prefix, *meant) : std::string()));
      continue;
    }
    if (const toml::table* sub = node.as_table()) {
      collect_unknown(*sub, path + ".", used, asked, source, unknown);
    } else if (const toml::array* array = node.as_array()) {
      for (std::size_t i = 0; i < array->size(); ++i)
        if (const toml::table* element = array->get(i)->as_table())
          collect_unknown(*element, fmt::format("{}[{}].", path, i), used, asked, source, unknown);
    }
  }
}

}  // namespace

void ConfigTable::check_unknown_keys() const {
  std::vector<std::string> unknown;
  collect_unknown(document_->root, "", document_->used, document_->asked, document_->source_name,
                  unknown);
  if (!unknown.empty())
    throw InputError(fmt::format("{}\n(a misspelt key would otherwise be silently ignored)",
                                 fmt::join(unknown, "\n")));
}

}  // namespace shapepress
