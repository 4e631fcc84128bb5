#include "analysis/runs.hpp"

#include <algorithm>
#include <fstream>
#include <string_view>

#include <fmt/format.h>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/run_metadata.hpp"

namespace shapepress::analysis {
namespace {

// The run.json beside a run's CSV. Missing: an error naming the folder and the file (no guessing
// from the comment lines: runs from before run.json are run again, the CSV alone is not enough).
RunRecord run_record_of(const std::filesystem::path& csv, std::string_view carries) {
  const std::filesystem::path folder = csv.parent_path().empty() ? "." : csv.parent_path();
  const std::filesystem::path path = folder / run_metadata_name;
  if (!std::filesystem::exists(path))
    throw InputError(fmt::format(
        "{}: no {} beside {} (the record its stage writes, carrying {}); runs made before "
        "run.json existed must be run again",
        folder.string(), run_metadata_name, csv.filename().string(), carries));
  return RunRecord::read(path);
}

constexpr std::string_view punch_facts = "H0 and the die area";
constexpr std::string_view plate_facts = "the particle kind, sub-sphere count and fills";

}  // namespace

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
  const bool compaction = run.kind == RunKind::compaction;
  const RunRecord record = run_record_of(run.csv, compaction ? punch_facts : plate_facts);
  run.metadata = record.path();
  // A CSV from one stage beside the run.json of another is a folder mixed up by hand; calibrate
  // writes either, the run of its fitted values.
  const std::string& stage = record.stage();
  if (stage != "calibrate" &&
      (compaction ? stage != "compact" : (stage != "plate" && stage != "fem-plate")))
    throw InputError(
        fmt::format("{}: stage \"{}\", but the folder holds {} (written by {})",
                    run.metadata.string(), stage, run.csv.filename().string(),
                    compaction ? "compact or calibrate" : "plate, calibrate or fem-plate"));
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

PunchCurve read_punch_curve(const std::filesystem::path& path) {
  const CsvTable table = read_csv(path);
  PunchCurve curve;
  curve.time = table.finite_column("time_s");
  curve.gap = table.finite_column("gap_m");
  curve.top_force = table.finite_column("top_force_N");
  curve.stress = table.finite_column("stress_Pa");
  curve.solid_fraction = table.finite_column("solid_fraction");
  for (double p : table.column("phase")) {
    if (p < 0 || p > 4 || p != static_cast<int>(p))
      throw InputError(fmt::format(
          "{}: column 'phase' has {}, expected 0, 1, 2, 3 or 4 (load, hold, unload, done, release)",
          path.string(), p));
    curve.phase.push_back(static_cast<int>(p));
  }
  const RunRecord record = run_record_of(path, punch_facts);
  curve.reference_gap = record.number("reference_gap_m");
  curve.die_area = record.number("die_area_m2");
  if (record.has("density_scale")) curve.density_scale = record.number("density_scale");
  if (record.has("max_kinetic_to_work"))
    curve.max_kinetic_to_work = record.number("max_kinetic_to_work");
  if (record.has("mean_force_imbalance"))
    curve.mean_force_imbalance = record.number("mean_force_imbalance");
  if (!(curve.reference_gap > 0.0) || !(curve.die_area > 0.0))
    throw InputError(fmt::format("{}: reference_gap_m (H0) {} and die_area_m2 {} must be > 0",
                                 record.path().string(), curve.reference_gap, curve.die_area));
  try {
    curve.check();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", path.string(), e.what()));
  }
  return curve;
}

std::string config_name(const std::filesystem::path& run_json) {
  const RunRecord record = RunRecord::read(run_json);
  const nlohmann::json& inputs = record.json().value("inputs", nlohmann::json::array());
  for (const nlohmann::json& input : inputs)
    if (input.is_object() && input.value("role", "") == "config" && input.contains("path") &&
        input["path"].is_string())
      return std::filesystem::path(input["path"].get<std::string>()).stem().string();
  return {};
}

PlateCurve read_plate_curve(const std::filesystem::path& path) {
  const CsvTable table = read_csv(path);
  PlateCurve curve;
  curve.deformation = table.finite_column("deformation");
  curve.approach = table.finite_column("approach_m");
  curve.top_force = table.finite_column("top_force_N");
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
  const RunRecord record = run_record_of(path, plate_facts);
  curve.particle = record.text("particle_kind");
  curve.sub_spheres = static_cast<int>(record.integer("sub_spheres"));
  curve.fills = static_cast<int>(record.integer("fills"));
  if (record.has("normal_law")) curve.normal_law = record.text("normal_law");
  if (curve.particle == "fem") curve.elements = static_cast<int>(record.integer("elements"));
  if (curve.sub_spheres < 1 || curve.fills < 1)
    throw InputError(fmt::format("{}: sub_spheres {} and fills {} must be >= 1",
                                 record.path().string(), curve.sub_spheres, curve.fills));
  if (curve.fills > 1 && curve.top_force_sd.empty())
    throw InputError(fmt::format("{}: a mean of {} fills without the top_force_sd_N column",
                                 path.string(), curve.fills));
  return curve;
}

}  // namespace shapepress::analysis
