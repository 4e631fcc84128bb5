#include "common/options.hpp"

#include <cmath>

namespace shapepress {

std::string toml_number(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  // fmt's shortest form reads back to the same double; TOML takes "1e-05" and integers alike.
  return fmt::format("{}", value);
}

std::string toml_string(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string toml_numbers(const double* values, std::size_t count) {
  std::string out = "[";
  for (std::size_t i = 0; i < count; ++i)
    out += (i ? ", " : "") + toml_number(values[i]);
  return out + "]";
}

namespace options_detail {

std::string dimension_unit(Dimension dimension) {
  return dimension == dim::dimensionless ? std::string() : si_unit(dimension);
}

std::string range_text(const Range& range) {
  return std::isfinite(range.min) || std::isfinite(range.max) ? range.describe() : std::string();
}

}  // namespace options_detail

namespace {

std::string section_title(const OptionSection& section) {
  if (section.name.empty()) return "top level";
  return section.repeated ? "[[" + section.name + "]]" : "[" + section.name + "]";
}

// A Markdown table cell: pipes would end the cell.
std::string cell(std::string_view text) {
  std::string out;
  for (const char c : text) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

std::string options_text(const StageOptions& options) {
  std::string out = fmt::format(
      "shapepress {}: config keys. A quantity is a number in the SI unit shown or a string with a "
      "unit (\"30 MPa\", \"0.1 mm\").\n",
      options.stage);
  for (const OptionSection& section : options.sections) {
    out += fmt::format("\n{}{}\n", section_title(section),
                       section.help.empty() ? std::string() : "  " + section.help);
    for (const OptionDoc& row : section.rows) {
      std::string facts;
      if (!row.unit.empty()) facts += row.unit;
      if (!row.range.empty()) facts += (facts.empty() ? "" : ", ") + row.range;
      const bool plain = row.default_value == "required" || row.default_value == "-";
      facts +=
          (facts.empty() ? "" : ", ") + (plain ? "" : std::string("default ")) + row.default_value;
      out += fmt::format("  {:<24} {}\n      {}\n", row.key, facts, row.help);
    }
  }
  return out;
}

std::string options_markdown(const StageOptions& options) {
  std::string out = fmt::format("## shapepress {}\n\n", options.stage);
  if (!options.help.empty()) out += options.help + "\n\n";
  for (const OptionSection& section : options.sections) {
    out += fmt::format("### {}\n\n", section_title(section));
    if (!section.help.empty()) out += section.help + "\n\n";
    out += "| key | unit | range | default | meaning |\n|---|---|---|---|---|\n";
    for (const OptionDoc& row : section.rows)
      out += fmt::format("| `{}` | {} | {} | {} | {} |\n", row.key, cell(row.unit), cell(row.range),
                         cell(row.default_value), cell(row.help));
    out += "\n";
  }
  return out;
}

}  // namespace shapepress
