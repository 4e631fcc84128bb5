#pragma once
// The text outputs of the report: metrics.json and the self-contained report.html.
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/compaction.hpp"
#include "analysis/plate_analysis.hpp"
#include "analysis/runs.hpp"

namespace shapepress::analysis {

// One run folder, read and analysed.
struct LoadedRun {
  RunFiles files;
  std::string label;  // the folder's name
  std::optional<PunchCurve> punch;
  std::optional<CompactionMetrics> compaction;
  std::optional<PlateCurve> plate;
  std::optional<PlateMetrics> plate_metrics;
};

// How far apart several compaction runs are (seeds, resolutions): the spread (max − min)/mean
// of their loading stress at given strains, within the strain range all runs reach.
struct StressSpread {
  std::vector<double> strain;
  std::vector<double> spread;
};

struct ReportProvenance {
  std::string command_line;
  std::string version;
  std::string git_revision;
};

// {"provenance": {...}, "fit_windows": {...}, "stress_spread": {...} (2+ compaction runs), "runs":
// [{"folder", "kind", "csv", "source", "metrics": {name: {"value", "unit"}}}]}; non-finite numbers
// are null.
std::string metrics_json(const std::vector<LoadedRun>& runs, const FitWindows& windows,
                         const ReportProvenance& provenance,
                         const std::optional<StressSpread>& spread = std::nullopt);

// A plain page: the charts' SVGs inline, one metrics table per run, the provenance of every
// input (its CSV comment lines) and of the report. `charts` are (title, svg file).
std::string report_html(const std::vector<LoadedRun>& runs,
                        const std::vector<std::pair<std::string, std::filesystem::path>>& charts,
                        const ReportProvenance& provenance,
                        const std::optional<StressSpread>& spread = std::nullopt);

// Escapes for JSON string contents and HTML text.
std::string json_escape(std::string_view text);
std::string html_escape(std::string_view text);

}  // namespace shapepress::analysis
