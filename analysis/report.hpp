#pragma once
// The report of one or several runs: charts (SVG + PNG + data CSV), metrics.json and a
// self-contained report.html (docs/architecture.md, "The data walk").
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/compaction.hpp"
#include "analysis/plot.hpp"
#include "analysis/report_html.hpp"

namespace shapepress::analysis {

struct ReportOptions {
  std::vector<std::filesystem::path> runs;  // run folders: punch.csv or force.csv inside
  std::filesystem::path out;
  FitWindows windows;
  std::optional<double> poisson_ratio;  // plate runs: ν of the sphere, for Tatara
  // Plate runs: the deformation Δ/(2R) the comparisons with Hertz and Tatara start at (the
  // paper's 5–40 %: 0.05); absent: 5 % of the run's deepest deformation.
  std::optional<double> plate_compare_from;
  // Extra curves on the plate chart (another method's force–deformation, e.g. a BMS run or a
  // digitised experiment): label and a CSV with columns deformation and force_N or top_force_N.
  std::vector<std::pair<std::string, std::filesystem::path>> plate_curves;
  // The convergence study (CMS against BMS): smallest N of each method's spread, by the
  // particle kind of force.csv ("cms" → 150 for the paper's 150…3000); default its two finest.
  std::map<std::string, int> spread_from;
  // Measured compaction curves to overlay (stress–strain or solid fraction–stress, the unit in
  // each column name; analysis/measured_curve.hpp), each compared with every compaction run.
  std::vector<std::filesystem::path> experiments;
  // advise folders (advice.csv, run.json): their speed–accuracy chart (bed_speed_accuracy for a
  // bed's ladder), stability map and table.
  std::vector<std::filesystem::path> advice;
  std::string command_line;  // provenance of the report
};

struct ReportResult {
  std::vector<std::filesystem::path> charts;  // the SVGs written
  std::filesystem::path metrics;
  std::filesystem::path html;
  int compaction_runs = 0;
  int plate_runs = 0;
};

// The representative volume: the peak stress, elastic recovery and Py of beds of one particle
// (kind and sub-spheres per body) in more than one size, against their bodies (seeds of a size
// show its scatter beside the size's trend); empty when no particle has two sizes.
std::vector<Chart> bed_size_charts(const std::vector<LoadedRun>& runs);

// Reads every run (InputError naming the folder, file or column that is wrong), then writes the
// charts, metrics.json and report.html into options.out.
ReportResult write_report(const ReportOptions& options);

}  // namespace shapepress::analysis
