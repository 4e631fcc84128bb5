#pragma once
// The rows of a reference file kept as data (tests/data/contact_laws/*.csv,
// tests/data/bond_models/*.csv): `#` lines are comments (the formulas and the script that wrote
// the values), the first other line names the columns, every later line is one row.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace shapepress::testing {

struct ReferenceRow {
  int line = 0;
  std::map<std::string, std::string> cells;
  double number(const std::string& column) const {
    const auto it = cells.find(column);
    if (it == cells.end() || it->second.empty())
      throw std::runtime_error("line " + std::to_string(line) + ": no value for " + column);
    return std::stod(it->second);
  }
  const std::string& text(const std::string& column) const { return cells.at(column); }
};

// A CSV line's cells; a trailing comma is a last, empty cell.
inline std::vector<std::string> reference_cells(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ','))
    out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

inline std::vector<ReferenceRow> read_reference_rows(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::string> header;
  std::vector<ReferenceRow> rows;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> cells = reference_cells(line);
    if (header.empty()) {
      header = cells;
      continue;
    }
    EXPECT_EQ(cells.size(), header.size()) << path << " line " << number;
    ReferenceRow row{number, {}};
    for (std::size_t k = 0; k < std::min(cells.size(), header.size()); ++k)
      row.cells[header[k]] = cells[k];
    rows.push_back(row);
  }
  return rows;
}

}  // namespace shapepress::testing
