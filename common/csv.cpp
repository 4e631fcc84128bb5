#include "common/csv.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "common/error.hpp"

namespace shapepress {

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  return fmt::format("{:.10g}", value);
}

CsvWriter::CsvWriter(std::filesystem::path path, std::vector<std::string> columns)
    : file_(std::move(path)), columns_(std::move(columns)) {}

void CsvWriter::comment(std::string_view line) {
  if (header_written_) throw std::logic_error("CSV comments go before the header");
  file_.stream() << "# " << line << '\n';
}

void CsvWriter::write_header_once() {
  if (header_written_) return;
  header_written_ = true;
  file_.stream() << fmt::format("{}\n", fmt::join(columns_, ","));
}

void CsvWriter::row(std::span<const double> values) {
  if (values.size() != columns_.size())
    throw std::logic_error(fmt::format("CSV {}: row of {} values for {} columns",
                                       file_.path().string(), values.size(), columns_.size()));
  write_header_once();
  std::ostream& out = file_.stream();
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) out << ',';
    out << format_number(values[i]);
  }
  out << '\n';
}

void CsvWriter::row_text(const std::vector<std::string>& cells) {
  if (cells.size() != columns_.size())
    throw std::logic_error(fmt::format("CSV {}: row of {} cells for {} columns",
                                       file_.path().string(), cells.size(), columns_.size()));
  write_header_once();
  file_.stream() << fmt::format("{}\n", fmt::join(cells, ","));
}

void CsvWriter::commit() {
  write_header_once();
  file_.commit();
}

std::vector<double> CsvTable::column(std::string_view name) const {
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (columns[c] != name) continue;
    std::vector<double> values;
    values.reserve(rows.size());
    for (const auto& r : rows)
      values.push_back(r[c]);
    return values;
  }
  throw InputError(
      fmt::format("{}: no column '{}' (columns: {})", source, name, fmt::join(columns, ", ")));
}

std::vector<double> CsvTable::finite_column(std::string_view name) const {
  std::vector<double> values = column(name);
  for (std::size_t k = 0; k < values.size(); ++k)
    if (!std::isfinite(values[k]))
      throw InputError(fmt::format("{}: column '{}', data row {}: {} is not a finite number",
                                   source, name, k + 1, values[k]));
  return values;
}

CsvTable read_csv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open the CSV file", path.string()));
  CsvTable table;
  table.source = path.string();
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();  // a file saved on Windows
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ','))
      cells.push_back(cell);
    if (table.columns.empty()) {
      table.columns = cells;
      continue;
    }
    if (cells.size() != table.columns.size())
      throw InputError(fmt::format("{}:{}: {} cells, the header has {}", path.string(), line_number,
                                   cells.size(), table.columns.size()));
    std::vector<double> row;
    for (const std::string& c : cells) {
      std::size_t used = 0;
      double value = NAN;
      try {
        if (c != "nan") value = std::stod(c, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      // The whole cell, not a number's prefix ("12abc", "1,5" split in two are wrong).
      if (c != "nan" && (used == 0 || c.find_first_not_of(" \t", used) != std::string::npos))
        throw InputError(fmt::format("{}:{}: '{}' is not a number", path.string(), line_number, c));
      row.push_back(value);
    }
    table.rows.push_back(std::move(row));
  }
  if (table.columns.empty()) throw InputError(fmt::format("{}: no header row", path.string()));
  return table;
}

}  // namespace shapepress
