#pragma once
// SI quantities with units, for the CLI and the configs: "0.5um", "30MPa", "2.58e8 Pa",
// "1e-6 s", "225 µm", "1.15e6 N/m3", "1541 kg/m^3". Values are stored in SI; the dimension is
// checked, so a mass given where a length is needed is an error that names the key.
#include <string>
#include <string_view>

namespace shapepress {

// Exponents of metre, kilogram and second. Angles are dimensionless (radians).
struct Dimension {
  int length = 0;
  int mass = 0;
  int time = 0;
  friend constexpr bool operator==(Dimension, Dimension) = default;
};

namespace dim {
inline constexpr Dimension dimensionless{0, 0, 0};
inline constexpr Dimension length{1, 0, 0};
inline constexpr Dimension mass{0, 1, 0};
inline constexpr Dimension time{0, 0, 1};
inline constexpr Dimension frequency{0, 0, -1};
inline constexpr Dimension velocity{1, 0, -1};
inline constexpr Dimension acceleration{1, 0, -2};
inline constexpr Dimension force{1, 1, -2};
inline constexpr Dimension pressure{-1, 1, -2};
inline constexpr Dimension energy{2, 1, -2};
inline constexpr Dimension density{-3, 1, 0};
inline constexpr Dimension stiffness{0, 1, -2};            // N/m
inline constexpr Dimension stiffness_per_area{-2, 1, -2};  // N/m^3, bond stiffness (P&C 2004)
inline constexpr Dimension area{2, 0, 0};
inline constexpr Dimension volume{3, 0, 0};
}  // namespace dim

// "length", "pressure", or "m^-2·kg·s^-2" for a dimension without a common name.
std::string dimension_name(Dimension d);
// The SI unit written out: "m", "Pa", "N/m^3".
std::string si_unit(Dimension d);

struct Quantity {
  double value = 0.0;  // SI
  Dimension dimension;
};

// Parses a number followed by an optional unit expression. A bare number is taken as SI.
// Throws InputError naming `key` when the text is not a quantity.
Quantity parse_quantity(std::string_view text, std::string_view key);

// Parses and checks the dimension: "key 'pixel-size': '3 kg' is a mass, a length was expected".
double parse_quantity(std::string_view text, Dimension expected, std::string_view key);

}  // namespace shapepress
