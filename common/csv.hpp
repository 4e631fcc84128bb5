#pragma once
// CSV tables with a header row and units in the column names ("stress_Pa"), written atomically.
// Numbers are written with 10 significant digits: enough for any curve, short enough to read.
#include <filesystem>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include "common/atomic_file.hpp"

namespace shapepress {

class CsvWriter {
 public:
  CsvWriter(std::filesystem::path path, std::vector<std::string> columns);
  // Lines starting with '#' before the header (source, H0, parameters); spreadsheets skip them
  // with a comment setting, pandas with comment='#'.
  void comment(std::string_view line);
  void row(std::span<const double> values);
  void row(std::initializer_list<double> values) { row(std::span(values.begin(), values.size())); }
  // A row of preformatted cells (text columns).
  void row_text(const std::vector<std::string>& cells);
  void commit();
  std::size_t columns() const { return columns_.size(); }

 private:
  void write_header_once();
  AtomicOutputFile file_;
  std::vector<std::string> columns_;
  bool header_written_ = false;
};

std::string format_number(double value);

// Reads a CSV with a header (lines starting with '#' skipped) into columns by name.
struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  // The values of one column; InputError naming the file and the column if it is missing.
  std::vector<double> column(std::string_view name) const;
  // The same, every value finite: InputError naming the file, the column and the line's row
  // otherwise (a measured curve has no NaN).
  std::vector<double> finite_column(std::string_view name) const;
  std::string source;
};
CsvTable read_csv(const std::filesystem::path& path);

}  // namespace shapepress
