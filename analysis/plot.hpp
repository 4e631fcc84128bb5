#pragma once
// Charts drawn by gnuplot (Debian gnuplot-nox) from a generated script: SVG for the HTML report,
// PNG for slides. Beside every chart go its data as CSV and the gnuplot script, so any chart can
// be re-plotted or restyled without re-running the analysis.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace shapepress::analysis {

// markers: large points, for maps of a few dozen runs.
enum class SeriesStyle { lines, dashed, points, markers };

struct Series {
  std::string title;
  std::vector<double> x;
  std::vector<double> y;
  SeriesStyle style = SeriesStyle::lines;
  int colour = 0;  // gnuplot line colour 1–8; 0: by position, so series sharing one (a run's
                   // load and unload, its points and fit) can be told from other runs
  // One per point: drawn as error bars of ± that much (a seed scatter), the points joined as the
  // style says; empty: none.
  std::vector<double> y_error = {};
};

struct Chart {
  std::string title;
  std::string x_label;  // with the unit, "stress [MPa]"
  std::string y_label;
  std::string x_column;  // CSV column names with units, "stress_MPa"
  std::string y_column;
  std::vector<Series> series;
  // Logarithmic axes, for differences that span decades (a ladder from spheres to fine bodies);
  // points at or below zero are then left out by gnuplot.
  bool log_x = false, log_y = false;
  // The lower end of a log axis (absent: gnuplot's autoscale, down to the smallest point): a
  // loading curve starts at stresses decades below its peak, which would squeeze the peaks.
  std::optional<double> log_x_from = std::nullopt, log_y_from = std::nullopt;
};

struct ChartFiles {
  std::filesystem::path svg, png, csv, script;
};

// The gnuplot script that draws `chart` into `svg` and `png` (data inline, as datablocks).
std::string gnuplot_script(const Chart& chart, const std::filesystem::path& svg,
                           const std::filesystem::path& png);

// Writes <stem>.csv (columns series index, x_column, y_column, and <y_column>_error when a
// series has error bars; a comment line "series k = title" per series), <stem>.gp, and, through
// gnuplot,
// <stem>.svg and <stem>.png; every file appears under its final name only when complete.
// ComputationError naming gnuplot if it is not on PATH or fails.
ChartFiles plot_chart(const Chart& chart, const std::filesystem::path& stem);

// The gnuplot executable found on PATH, or an empty path.
std::filesystem::path find_gnuplot();

}  // namespace shapepress::analysis
