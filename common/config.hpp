#pragma once
// TOML configs where every mistake is an error that names the file, the line and the key:
// unknown keys (a typo must not be silently ignored), wrong types, NaN, out-of-range values and
// quantities of the wrong dimension. Keys are read with typed getters; check_unknown_keys()
// then rejects whatever the stage did not ask for: every config key is used or rejected.
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/units.hpp"

namespace shapepress {

// An allowed interval for a number; the message says which bound was broken.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_inclusive = true;
  bool max_inclusive = true;

  static Range any() { return {}; }
  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), false, true}; }
  static Range non_negative() { return {0.0, std::numeric_limits<double>::infinity(), true, true}; }
  static Range closed(double lo, double hi) { return {lo, hi, true, true}; }
  static Range open_closed(double lo, double hi) { return {lo, hi, false, true}; }
  static Range at_least(double lo) {
    return {lo, std::numeric_limits<double>::infinity(), true, true};
  }

  bool contains(double v) const;
  std::string describe() const;  // "> 0", "in [0, 1]"
};

class ConfigTable {
 public:
  // Throws InputError naming the file (and the line of a syntax error).
  static ConfigTable load_file(const std::filesystem::path& path);
  static ConfigTable parse(std::string_view text, std::string source_name);

  bool has(std::string_view key) const;
  // Getters: a missing key takes `fallback`; with no fallback it is an error naming the key.
  double number(std::string_view key, std::optional<double> fallback = std::nullopt,
                Range range = Range::any()) const;
  std::int64_t integer(std::string_view key, std::optional<std::int64_t> fallback = std::nullopt,
                       Range range = Range::any()) const;
  bool boolean(std::string_view key, std::optional<bool> fallback = std::nullopt) const;
  std::string string(std::string_view key,
                     std::optional<std::string> fallback = std::nullopt) const;
  // One of `choices`; the message lists them.
  std::string choice(std::string_view key, const std::vector<std::string>& choices,
                     std::optional<std::string> fallback = std::nullopt) const;
  // A number (taken as SI) or a string with a unit ("30 MPa"), checked against `dimension`.
  double quantity(std::string_view key, Dimension dimension,
                  std::optional<double> fallback = std::nullopt, Range range = Range::any()) const;
  std::vector<double> numbers(std::string_view key, Range range = Range::any()) const;
  std::vector<double> quantities(std::string_view key, Dimension dimension,
                                 Range range = Range::any()) const;

  // Sub-tables share the bookkeeping of used keys with their parent.
  ConfigTable table(std::string_view key) const;
  std::vector<ConfigTable> tables(std::string_view key) const;  // [[array.of.tables]]

  // Every key of the whole document that no getter asked for is an error; all are listed.
  void check_unknown_keys() const;

  const std::string& source_name() const;
  const std::string& text() const;                  // the whole document, for provenance
  std::string path_of(std::string_view key) const;  // "material.E"

 private:
  struct Document;
  struct Lookup;
  Lookup lookup(std::string_view key) const;  // marks the key used
  ConfigTable(std::shared_ptr<Document> document, const void* node, std::string prefix);
  std::shared_ptr<Document> document_;
  const void* node_ = nullptr;  // the toml::table this view reads (kept out of the header)
  std::string prefix_;
};

}  // namespace shapepress
