#pragma once
// The text outputs of the report: metrics.json and the self-contained report.html.
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/advise.hpp"
#include "analysis/beds.hpp"
#include "analysis/compaction.hpp"
#include "analysis/measured_curve.hpp"
#include "analysis/plate_analysis.hpp"
#include "analysis/runs.hpp"

namespace shapepress::analysis {

// One run folder, read and analysed.
struct LoadedRun {
  RunFiles files;
  std::string label;  // its config and what it pressed, or its folder (report.cpp load_runs)
  std::optional<PunchCurve> punch;
  std::optional<CompactionMetrics> compaction;
  std::optional<PlateCurve> plate;
  std::optional<PlateMetrics> plate_metrics;
  std::optional<BedFacts> bed;  // compaction runs: the bed before the punch, and its bodies
};

// How far apart several compaction runs are (seeds, resolutions): the spread (max − min)/mean
// of their loading stress at given strains, within the strain range all runs reach.
struct StressSpread {
  std::vector<double> strain;
  std::vector<double> spread;
};

// A measured curve (report --experiment) and how far each compaction run is from it.
struct ExperimentComparison {
  MeasuredCurve curve;
  std::vector<std::pair<std::string, MeasuredMismatch>> runs;  // run label, mismatch
};

struct ReportProvenance {
  std::string command_line;
  std::string version;
  std::string git_revision;
};

// {"provenance": {...}, "fit_windows": {...}, "stress_spread": {...} (2+ compaction runs), "runs":
// [{"folder", "kind", "csv", "source", "metrics": {name: {"value", "unit"}}}]}; non-finite numbers
// are null.
// "experiments": [{"file", "axes", "x_column", "y_column", "rows", "runs": [{"label",
// "points", "x_from", "x_to", "x_unit", "rms", "max", "at_x", "unit", "rms_relative",
// "max_relative"}]}] when experiments are given (SI units, as every number there).
// "advice": [{"folder", "pick", "reference", "tolerance", "pick_error_vs_reference",
// "cost_saved_factor", "predicted_full_run_cpu_s", "seed_scatter", "rungs": [{"label", "status",
// "cause", "sub_spheres", "time_step_fraction", "density_scale", "seed", "cpu_s", "error"}]}]
// for each advise folder (report --advice).
std::string metrics_json(const std::vector<LoadedRun>& runs, const FitWindows& windows,
                         const ReportProvenance& provenance,
                         const std::optional<StressSpread>& spread = std::nullopt,
                         const std::vector<ExperimentComparison>& experiments = {},
                         const std::vector<AdviceRecord>& advice = {});

// A plain page: the charts' SVGs inline, one metrics table per run, the comparison with each
// experiment, the provenance of every input (its CSV comment lines) and of the report.
// `charts` are (title, svg file). Tables show the units people read (MPa, mm, mJ, %);
// metrics.json keeps SI.
std::string report_html(const std::vector<LoadedRun>& runs,
                        const std::vector<std::pair<std::string, std::filesystem::path>>& charts,
                        const ReportProvenance& provenance,
                        const std::optional<StressSpread>& spread = std::nullopt,
                        const std::vector<ExperimentComparison>& experiments = {},
                        const std::vector<AdviceRecord>& advice = {});

// The table of beds, one row per compaction run (paper §4.4's comparison of shapes): particle
// kind, bodies, sub-spheres per body, the bodies' projected aspect ratio, settled and
// pre-compressed solid fraction, peak stress, elastic recovery, Heckel Py, Kawakita a and 1/b,
// the work of compaction, and the pack's and the compaction's wall seconds. CSV with the unit in
// each column name (MPa, %, mJ, s), an empty cell where a fact is unknown.
std::string beds_csv(const std::vector<LoadedRun>& runs);

// A value in SI with its unit as a table shows it: Pa as MPa, m as mm, J as mJ, 1/Pa as 1/MPa,
// a fraction as %; `fraction` says whether a dimensionless value is a fraction (a solid
// fraction, a strain, a relative error) or a plain number (R², an intercept).
struct ShownValue {
  double value;
  std::string unit;
};
ShownValue shown_value(double in_si, std::string_view unit, bool fraction = false);
// "30.12" (4 significant digits), "52340" from 1e4 on, an exponent only below 1e-3 or from 1e9;
// "-" when not finite.
std::string shown_text(double value);

// Escapes for JSON string contents and HTML text.
std::string json_escape(std::string_view text);
std::string html_escape(std::string_view text);

}  // namespace shapepress::analysis
