#include "analysis/runs.hpp"

#include <algorithm>
#include <fstream>
#include <regex>

#include <fmt/format.h>

#include "common/csv.hpp"
#include "common/error.hpp"

namespace shapepress::analysis {

RunFiles find_run(const std::filesystem::path& folder) {
  if (!std::filesystem::is_directory(folder))
    throw InputError(fmt::format("{}: no such run folder", folder.string()));
  RunFiles run;
  run.folder = folder;
  if (std::filesystem::exists(folder / "punch.csv")) {
    run.csv = folder / "punch.csv";
    run.kind = RunKind::compaction;
  } else if (std::filesystem::exists(folder / "force.csv")) {
    run.csv = folder / "force.csv";
    run.kind = RunKind::plate;
  } else {
    throw InputError(fmt::format(
        "{}: neither punch.csv (shapepress compact) nor force.csv (shapepress plate) in the folder",
        folder.string()));
  }
  run.comments = csv_comments(run.csv);
  return run;
}

std::vector<std::string> csv_comments(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open the CSV file", path.string()));
  std::vector<std::string> comments;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] != '#') break;
    const std::size_t start = line.find_first_not_of("# ");
    comments.push_back(start == std::string::npos ? std::string() : line.substr(start));
  }
  return comments;
}

namespace {

// "strain from H0 = 0.0235 m; die area 0.000144 m^2" (simulate/cli_compact.cpp).
void read_reference(const std::filesystem::path& path, PunchCurve& curve) {
  const std::regex h0(R"(H0\s*=\s*([-+0-9.eE]+)\s*m\b)");
  const std::regex area(R"(die area\s*=?\s*([-+0-9.eE]+)\s*m\^2)");
  for (const std::string& line : csv_comments(path)) {
    std::smatch match;
    if (std::regex_search(line, match, h0)) curve.reference_gap = std::stod(match[1]);
    if (std::regex_search(line, match, area)) curve.die_area = std::stod(match[1]);
  }
  if (!(curve.reference_gap > 0.0))
    throw InputError(fmt::format(
        "{}: no comment line '# ... strain from H0 = <value> m' giving the reference gap H0",
        path.string()));
}

}  // namespace

PunchCurve read_punch_curve(const std::filesystem::path& path) {
  const CsvTable table = read_csv(path);
  PunchCurve curve;
  curve.time = table.column("time_s");
  curve.gap = table.column("gap_m");
  curve.top_force = table.column("top_force_N");
  curve.stress = table.column("stress_Pa");
  curve.solid_fraction = table.column("solid_fraction");
  for (double p : table.column("phase")) {
    if (p < 0 || p > 3 || p != static_cast<int>(p))
      throw InputError(
          fmt::format("{}: column 'phase' has {}, expected 0, 1, 2 or 3", path.string(), p));
    curve.phase.push_back(static_cast<int>(p));
  }
  read_reference(path, curve);
  try {
    curve.check();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", path.string(), e.what()));
  }
  return curve;
}

PlateCurve read_plate_curve(const std::filesystem::path& path) {
  const CsvTable table = read_csv(path);
  PlateCurve curve;
  curve.deformation = table.column("deformation");
  curve.approach = table.column("approach_m");
  curve.top_force = table.column("top_force_N");
  curve.hertz_force = table.column("hertz_force_N");
  if (curve.approach.size() < 3)
    throw InputError(
        fmt::format("{}: {} rows, at least 3 needed", path.string(), curve.approach.size()));
  const auto has = [&](std::string_view name) {
    return std::find(table.columns.begin(), table.columns.end(), name) != table.columns.end();
  };
  if (has("cpu_s")) curve.cpu_seconds = table.column("cpu_s").back();
  if (has("wall_s")) curve.wall_seconds = table.column("wall_s").back();
  if (has("contacts")) curve.contacts = table.column("contacts");
  if (has("top_force_sd_N")) curve.top_force_sd = table.column("top_force_sd_N");
  const std::regex count(R"(sub_spheres\s*=\s*([0-9]+))");
  const std::regex fills(R"(^fills\s*=\s*([0-9]+))");
  const std::regex particle(R"(^particle\s*=\s*([A-Za-z_]+))");
  for (const std::string& line : csv_comments(path)) {
    std::smatch match;
    if (std::regex_search(line, match, count)) curve.sub_spheres = std::stoi(match[1]);
    if (std::regex_search(line, match, particle)) curve.particle = match[1];
    if (std::regex_search(line, match, fills)) curve.fills = std::stoi(match[1]);
  }
  if (curve.fills > 1 && curve.top_force_sd.empty())
    throw InputError(fmt::format("{}: a mean of {} fills without the top_force_sd_N column",
                                 path.string(), curve.fills));
  return curve;
}

}  // namespace shapepress::analysis
