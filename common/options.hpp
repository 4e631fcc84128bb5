#pragma once
// One table per config section, each key bound once to the field it fills, with its unit, range,
// default and help. The same table reads the section (through ConfigTable, so every error names
// the file, line and key), writes the values back as TOML that reads to the same values (the
// effective config written beside a run's outputs), and documents the keys (`--help-config`,
// docs/config-reference.md). Defaults are the field's value in a default-constructed struct, so
// they are stated once, where the struct is declared.
//
// A key a stage knows but does not honour is bound with unused(): giving it is an error naming it,
// never a value silently ignored. Keys that only apply in one mode are bound with when(): given in
// another mode they are an error too. Rules across keys (mutually exclusive keys, a default taken
// from another table) stay as explicit checks in the stage's reader.
#include <array>
#include <concepts>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "common/config.hpp"
#include "common/error.hpp"
#include "common/option_doc.hpp"

namespace shapepress {

// TOML text of values that reads back to the same bits (17 significant digits; inf as inf).
std::string toml_number(double value);
std::string toml_string(std::string_view text);
std::string toml_numbers(const double* values, std::size_t count);

// The documented keys of one section: "[run]" (repeated: "[[material]]"; name empty: top level).
struct OptionSection {
  std::string name;
  std::string help;
  bool repeated = false;
  std::vector<OptionDoc> rows;
};

// The keys of a stage's config, section by section, for --help-config and the reference.
struct StageOptions {
  std::string stage;
  std::string help;
  std::vector<OptionSection> sections;
};
std::string options_text(const StageOptions& options);
std::string options_markdown(const StageOptions& options);

namespace options_detail {
template <class T>
struct is_optional : std::false_type {};
template <class T>
struct is_optional<std::optional<T>> : std::true_type {};
template <class T>
struct is_array : std::false_type {};
template <std::size_t N>
struct is_array<std::array<double, N>> : std::true_type {};
std::string dimension_unit(Dimension dimension);
std::string range_text(const Range& range);
}  // namespace options_detail

template <class S>
class OptionTable {
 public:
  explicit OptionTable(std::string name, std::string help = {}, S defaults = S{})
      : name_(std::move(name)), help_(std::move(help)), defaults_(std::move(defaults)) {}

  // Field types: `get` is a member pointer or a generic callable `[](auto& s) -> auto& { return
  // s.a.b; }` (called on S& to read and on const S& to write), so nested fields bind too.
  // double or std::optional<double> (absent: left empty), a number without a unit.
  template <class Get>
  OptionTable& number(std::string key, Get get, Range range, std::string help) {
    return real(std::move(key), get, dim::dimensionless, range, std::move(help));
  }
  // As number(), a number in SI or a string with a unit ("30 MPa"), of this dimension.
  template <class Get>
  OptionTable& quantity(std::string key, Get get, Dimension dimension, Range range,
                        std::string help) {
    return real(std::move(key), get, dimension, range, std::move(help));
  }
  // Any integral field.
  template <class Get>
  OptionTable& integer(std::string key, Get get, Range range, std::string help) {
    using F = field_type<Get>;
    static_assert(std::is_integral_v<F>);
    Row row = make_row(key, "", options_detail::range_text(range), help);
    row.read = [key, get, range](const ConfigTable& t, S& s, const Row& r) {
      F& field = std::invoke(get, s);
      const std::optional<std::int64_t> fallback =
          r.required ? std::nullopt : std::optional(static_cast<std::int64_t>(field));
      field = static_cast<F>(t.integer(key, fallback, r.range_from ? r.range_from(s) : range));
    };
    row.write = [get](const S& s) -> std::optional<std::string> {
      return fmt::format("{}", std::invoke(get, s));
    };
    return add(std::move(row));
  }
  template <class Get>
  OptionTable& boolean(std::string key, Get get, std::string help) {
    Row row = make_row(key, "", "true | false", help);
    row.read = [key, get](const ConfigTable& t, S& s, const Row& r) {
      bool& field = std::invoke(get, s);
      field = t.boolean(key, r.required ? std::nullopt : std::optional(field));
    };
    row.write = [get](const S& s) -> std::optional<std::string> {
      return std::invoke(get, s) ? "true" : "false";
    };
    return add(std::move(row));
  }
  // std::string; an empty default is documented as "none" (the field's own meaning of empty).
  template <class Get>
  OptionTable& string(std::string key, Get get, std::string help) {
    Row row = make_row(key, "", "text", help);
    row.read = [key, get](const ConfigTable& t, S& s, const Row& r) {
      std::string& field = std::invoke(get, s);
      if (r.required || t.has(key)) field = t.string(key);
    };
    row.write = [get](const S& s) -> std::optional<std::string> {
      const std::string& field = std::invoke(get, s);
      if (field.empty()) return std::nullopt;
      return toml_string(field);
    };
    return add(std::move(row));
  }
  // One of the named values (an enum, a bool, a string), written as its name.
  template <class Get, class V>
  OptionTable& choice(std::string key, Get get, std::vector<std::pair<std::string, V>> values,
                      std::string help) {
    std::vector<std::string> names;
    for (const auto& [name, value] : values)
      names.push_back(name);
    Row row = make_row(key, "", fmt::format("{}", fmt::join(names, " | ")), help);
    row.read = [key, get, values, names](const ConfigTable& t, S& s, const Row& r) {
      auto& field = std::invoke(get, s);
      std::optional<std::string> fallback;
      if (!r.required)
        for (const auto& [name, value] : values)
          if (value == field) fallback = name;
      const std::string name = t.choice(key, names, fallback);
      for (const auto& [n, value] : values)
        if (n == name) field = value;
    };
    row.write = [get, values](const S& s) -> std::optional<std::string> {
      const auto& field = std::invoke(get, s);
      for (const auto& [name, value] : values)
        if (value == field) return toml_string(name);
      throw std::logic_error("OptionTable::choice: a value with no name");
    };
    return add(std::move(row));
  }
  // std::vector<double> (absent: left as is) or std::array<double, N> (exactly N values).
  template <class Get>
  OptionTable& numbers(std::string key, Get get, Dimension dimension, Range range,
                       std::string help) {
    using F = field_type<Get>;
    Row row = make_row(key, options_detail::dimension_unit(dimension),
                       options_detail::range_text(range), help);
    row.read = [key, get, dimension, range](const ConfigTable& t, S& s, const Row& r) {
      F& field = std::invoke(get, s);
      if (!r.required && !t.has(key)) return;
      const std::vector<double> values = t.quantities(key, dimension, range);
      if constexpr (options_detail::is_array<F>::value) {
        if (values.size() != field.size())
          throw InputError(fmt::format("{}: key '{}' must be an array of {} numbers",
                                       t.source_name(), t.path_of(key), field.size()));
        std::copy(values.begin(), values.end(), field.begin());
      } else {
        field = values;
      }
    };
    row.write = [get](const S& s) -> std::optional<std::string> {
      const F& field = std::invoke(get, s);
      if constexpr (!options_detail::is_array<F>::value)
        if (field.empty()) return std::nullopt;
      return toml_numbers(field.data(), field.size());
    };
    return add(std::move(row));
  }

  // Modifiers of the row added last.
  OptionTable& required() {
    rows_.back().required = true;
    rows_.back().doc.default_value = "required";
    return *this;
  }
  OptionTable& default_text(std::string text) {
    rows_.back().doc.default_value = std::move(text);
    return *this;
  }
  // A default computed from the keys read before it (diameter_max = diameter_min).
  OptionTable& default_from(std::function<double(const S&)> f, std::string text) {
    rows_.back().default_from = std::move(f);
    rows_.back().doc.default_value = std::move(text);
    return *this;
  }
  // A range that depends on the keys read before it (ramp below max_deformation).
  OptionTable& range_from(std::function<Range(const S&)> f, std::string text) {
    rows_.back().range_from = std::move(f);
    rows_.back().doc.range = std::move(text);
    return *this;
  }
  // Read (and written) only when `active` holds for the keys read before it; given otherwise it
  // is an error: "key 'punch.speed' is not used <context>".
  OptionTable& when(std::function<bool(const S&)> active, std::string context) {
    rows_.back().active = std::move(active);
    rows_.back().inactive_context = context;
    rows_.back().doc.help += " (not used " + context + ")";
    return *this;
  }
  // Written to the effective config only when `write` holds (a form of several that excludes it).
  OptionTable& write_when(std::function<bool(const S&)> write) {
    rows_.back().write_when = std::move(write);
    return *this;
  }
  // A key other stages read and this one does not: giving it is an error with the reason.
  OptionTable& unused(std::string key, std::string reason) {
    Row row = make_row(key, "", "", "not used here: " + reason);
    row.doc.default_value = "-";
    row.read = [key, reason](const ConfigTable& t, S&, const Row&) {
      if (t.has(key))
        throw InputError(fmt::format("{}: key '{}' is not used by this stage: {}", t.source_name(),
                                     t.path_of(key), reason));
    };
    return add(std::move(row));
  }

  // Reads the keys of `table` (a view of this section) into `out`, whose fields hold the
  // defaults (a fresh S: the documented ones).
  void read(const ConfigTable& table, S& out) const {
    for (const Row& row : rows_) {
      if (row.active && !row.active(out)) {
        if (table.has(row.doc.key))
          throw InputError(fmt::format("{}: key '{}' is not used {}", table.source_name(),
                                       table.path_of(row.doc.key), row.inactive_context));
        continue;
      }
      row.read(table, out, row);
    }
  }
  S read(const ConfigTable& table) const {
    S out = defaults_;
    read(table, out);
    return out;
  }
  // "key = value" lines of every key that has a value, complete: read() gives `value` back.
  std::string lines(const S& value) const {
    std::string out;
    for (const Row& row : rows_) {
      if (!row.write) continue;
      if (row.active && !row.active(value)) continue;
      if (row.write_when && !row.write_when(value)) continue;
      if (std::optional<std::string> text = row.write(value))
        out += fmt::format("{} = {}\n", row.doc.key, *text);
    }
    return out;
  }
  // The section with its header ("[run]").
  std::string write(const S& value) const {
    return (name_.empty() ? std::string() : "[" + name_ + "]\n") + lines(value);
  }
  OptionSection docs() const {
    OptionSection section{name_, help_, false, {}};
    for (const Row& row : rows_)
      section.rows.push_back(row.doc);
    return section;
  }
  const std::string& name() const { return name_; }

 private:
  template <class Get>
  using field_type = std::remove_cvref_t<std::invoke_result_t<Get, S&>>;

  struct Row {
    OptionDoc doc;
    bool required = false;
    std::function<double(const S&)> default_from;
    std::function<Range(const S&)> range_from;
    std::function<bool(const S&)> active;
    std::string inactive_context;
    std::function<bool(const S&)> write_when;
    std::function<void(const ConfigTable&, S&, const Row&)> read;
    std::function<std::optional<std::string>(const S&)> write;
  };

  Row make_row(std::string key, std::string unit, std::string range, std::string help) const {
    Row row;
    row.doc = {std::move(key), std::move(unit), std::move(range), "", std::move(help)};
    return row;
  }
  OptionTable& add(Row row) {
    if (row.write && row.doc.default_value.empty())
      row.doc.default_value = row.write(defaults_).value_or("none");
    rows_.push_back(std::move(row));
    return *this;
  }

  template <class Get>
  OptionTable& real(std::string key, Get get, Dimension dimension, Range range, std::string help) {
    using F = field_type<Get>;
    Row row = make_row(key, options_detail::dimension_unit(dimension),
                       options_detail::range_text(range), help);
    row.read = [key, get, dimension, range](const ConfigTable& t, S& s, const Row& r) {
      F& field = std::invoke(get, s);
      const Range checked = r.range_from ? r.range_from(s) : range;
      std::optional<double> fallback;
      if constexpr (options_detail::is_optional<F>::value) {
        if (!r.required && !t.has(key)) {
          if (r.default_from) field = r.default_from(s);
          return;
        }
      } else if (!r.required) {
        fallback = r.default_from ? r.default_from(s) : field;
      }
      field = dimension == dim::dimensionless ? t.number(key, fallback, checked)
                                              : t.quantity(key, dimension, fallback, checked);
    };
    row.write = [get](const S& s) -> std::optional<std::string> {
      const F& field = std::invoke(get, s);
      if constexpr (options_detail::is_optional<F>::value) {
        if (!field) return std::nullopt;
        return toml_number(*field);
      } else {
        return toml_number(field);
      }
    };
    return add(std::move(row));
  }

  std::string name_, help_;
  S defaults_;
  std::vector<Row> rows_;
};

}  // namespace shapepress
