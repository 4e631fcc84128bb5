#include "common/units.hpp"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "common/error.hpp"

namespace shapepress {
namespace {

Dimension operator+(Dimension a, Dimension b) {
  return {a.length + b.length, a.mass + b.mass, a.time + b.time};
}
Dimension operator*(int k, Dimension a) {
  return {k * a.length, k * a.mass, k * a.time};
}

struct Unit {
  std::string_view symbol;
  double factor;  // to SI
  Dimension dimension;
};

// Base symbols; kilogram is the SI base, so the gram carries 1e-3.
constexpr std::array base_units{
    Unit{"m", 1.0, dim::length},
    Unit{"g", 1e-3, dim::mass},
    Unit{"s", 1.0, dim::time},
    Unit{"N", 1.0, dim::force},
    Unit{"Pa", 1.0, dim::pressure},
    Unit{"J", 1.0, dim::energy},
    Unit{"Hz", 1.0, dim::frequency},
    Unit{"W", 1.0, Dimension{2, 1, -3}},
    Unit{"rad", 1.0, dim::dimensionless},
    Unit{"%", 0.01, dim::dimensionless},
    Unit{"deg", std::numbers::pi / 180.0, dim::dimensionless},
};

struct Prefix {
  std::string_view symbol;
  double factor;
};
constexpr std::array prefixes{
    Prefix{"G", 1e9},  Prefix{"M", 1e6},   Prefix{"k", 1e3},       Prefix{"c", 1e-2},
    Prefix{"m", 1e-3}, Prefix{"u", 1e-6},  Prefix{"\u00b5", 1e-6}, Prefix{"\u03bc", 1e-6},
    Prefix{"n", 1e-9}, Prefix{"p", 1e-12},
};

std::optional<Unit> find_unit(std::string_view symbol) {
  for (const Unit& u : base_units)
    if (u.symbol == symbol) return u;
  for (const Prefix& p : prefixes) {
    if (!symbol.starts_with(p.symbol)) continue;
    std::string_view rest = symbol.substr(p.symbol.size());
    for (const Unit& u : base_units)
      if (u.symbol == rest && u.symbol != "%" && u.symbol != "deg")
        return Unit{symbol, p.factor * u.factor, u.dimension};
  }
  return std::nullopt;
}

bool is_symbol_char(unsigned char c) {
  return std::isalpha(c) != 0 || c == '%' || c >= 0x80;  // UTF-8 bytes of µ, μ
}

// Reads an exponent after a symbol: "3", "^3", "^-2", "²", "³".
int read_exponent(std::string_view& rest) {
  if (rest.starts_with("\u00b2")) {
    rest.remove_prefix(2);
    return 2;
  }
  if (rest.starts_with("\u00b3")) {
    rest.remove_prefix(2);
    return 3;
  }
  if (rest.starts_with('^')) rest.remove_prefix(1);
  int exponent = 1;
  auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), exponent);
  if (ec != std::errc{}) return 1;
  rest.remove_prefix(static_cast<std::size_t>(end - rest.data()));
  return exponent;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())))
    s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())))
    s.remove_suffix(1);
  return s;
}

// Parses "kg/m^3", "N/m3", "m/s2", "N·m", "kg*m^2" into a factor and a dimension.
std::pair<double, Dimension> parse_unit_expression(std::string_view text, std::string_view key,
                                                   std::string_view whole) {
  double factor = 1.0;
  Dimension dimension;
  int sign = +1;
  std::string_view rest = trim(text);
  while (!rest.empty()) {
    std::size_t n = 0;
    while (n < rest.size() && is_symbol_char(static_cast<unsigned char>(rest[n])) &&
           !rest.substr(n).starts_with("\u00b7") && !rest.substr(n).starts_with("\u00b2") &&
           !rest.substr(n).starts_with("\u00b3"))
      n += 1;
    std::string_view symbol = rest.substr(0, n);
    std::optional<Unit> unit = find_unit(symbol);
    if (symbol.empty() || !unit)
      throw InputError(
          fmt::format("key '{}': '{}' has an unknown unit '{}' (expected e.g. um, "
                      "mm, MPa, kg/m^3, N/m^3, s)",
                      key, whole, symbol.empty() ? rest : symbol));
    rest.remove_prefix(n);
    int exponent = sign * read_exponent(rest);
    factor *= std::pow(unit->factor, exponent);
    dimension = dimension + exponent * unit->dimension;
    rest = trim(rest);
    sign = +1;
    if (rest.starts_with('/')) {
      sign = -1;
      rest.remove_prefix(1);
    } else if (rest.starts_with('*')) {
      rest.remove_prefix(1);
    } else if (rest.starts_with("\u00b7")) {
      rest.remove_prefix(2);
    }
    rest = trim(rest);
  }
  return {factor, dimension};
}

}  // namespace

std::string dimension_name(Dimension d) {
  static constexpr std::array<std::pair<Dimension, std::string_view>, 15> names{{
      {dim::dimensionless, "dimensionless number"},
      {dim::length, "length"},
      {dim::mass, "mass"},
      {dim::time, "time"},
      {dim::frequency, "frequency"},
      {dim::velocity, "velocity"},
      {dim::acceleration, "acceleration"},
      {dim::force, "force"},
      {dim::pressure, "pressure"},
      {dim::energy, "energy"},
      {dim::density, "density"},
      {dim::stiffness, "stiffness (N/m)"},
      {dim::stiffness_per_area, "stiffness per area (N/m^3)"},
      {dim::area, "area"},
      {dim::volume, "volume"},
  }};
  for (const auto& [dimension, name] : names)
    if (dimension == d) return std::string(name);
  return si_unit(d);
}

std::string si_unit(Dimension d) {
  if (d == dim::pressure) return "Pa";
  if (d == dim::force) return "N";
  if (d == dim::energy) return "J";
  if (d == dim::stiffness) return "N/m";
  if (d == dim::stiffness_per_area) return "N/m^3";
  if (d == dim::dimensionless) return "1";
  std::string out;
  auto term = [&out](std::string_view symbol, int exponent) {
    if (exponent == 0) return;
    if (!out.empty()) out += "*";
    out += symbol;
    if (exponent != 1) out += fmt::format("^{}", exponent);
  };
  term("kg", d.mass);
  term("m", d.length);
  term("s", d.time);
  return out;
}

Quantity parse_quantity(std::string_view text, std::string_view key) {
  std::string_view s = trim(text);
  if (s.starts_with('+')) s.remove_prefix(1);
  double number = 0.0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), number);
  if (ec != std::errc{} || end == s.data())
    throw InputError(
        fmt::format("key '{}': '{}' is not a number with a unit (e.g. 0.5um, 30MPa)", key, text));
  if (!std::isfinite(number))
    throw InputError(fmt::format("key '{}': '{}' is not a finite number", key, text));
  std::string_view unit_text = s.substr(static_cast<std::size_t>(end - s.data()));
  auto [factor, dimension] = parse_unit_expression(unit_text, key, text);
  return Quantity{number * factor, dimension};
}

double parse_quantity(std::string_view text, Dimension expected, std::string_view key) {
  Quantity q = parse_quantity(text, key);
  std::string_view unit_text = trim(text);
  bool has_unit =
      !unit_text.empty() && is_symbol_char(static_cast<unsigned char>(unit_text.back()));
  // A bare number is SI in the expected dimension.
  if (q.dimension == dim::dimensionless && !has_unit) return q.value;
  if (q.dimension != expected)
    throw InputError(fmt::format("key '{}': '{}' is a {}, a {} was expected (SI unit {})", key,
                                 text, dimension_name(q.dimension), dimension_name(expected),
                                 si_unit(expected)));
  return q.value;
}

}  // namespace shapepress
