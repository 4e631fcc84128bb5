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

CsvTable read_csv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open the CSV file", path.string()));
  CsvTable table;
  table.source = path.string();
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
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
      try {
        row.push_back(c == "nan" ? NAN : std::stod(c));
      } catch (const std::exception&) {
        throw InputError(fmt::format("{}:{}: '{}' is not a number", path.string(), line_number, c));
      }
    }
    table.rows.push_back(std::move(row));
  }
  if (table.columns.empty()) throw InputError(fmt::format("{}: no header row", path.string()));
  return table;
}

}  // namespace shapepress
