#include "analysis/plot.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "common/atomic_file.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"

namespace shapepress::analysis {
namespace {

// gnuplot strings are single-quoted; a quote inside is doubled.
std::string gp_quoted(std::string_view text) {
  std::string out = "'";
  for (char c : text) {
    out += c;
    if (c == '\'') out += '\'';
  }
  return out + "'";
}

bool has_error_bars(const Series& series) {
  return !series.y_error.empty();
}

std::string style_of(SeriesStyle style, int given_colour, int index, bool error_bars) {
  const int colour = given_colour > 0 ? (given_colour - 1) % 8 + 1 : index % 8 + 1;
  if (error_bars)
    return style == SeriesStyle::lines || style == SeriesStyle::dashed
               ? fmt::format("with yerrorlines pt 7 ps 1 lw 2 lc {}{}", colour,
                             style == SeriesStyle::dashed ? " dt 2" : "")
               : fmt::format("with yerrorbars pt 7 ps {} lc {}",
                             style == SeriesStyle::markers ? 2 : 1, colour);
  switch (style) {
    case SeriesStyle::points:
      return fmt::format("with points pt 7 ps 0.5 lc {}", colour);
    case SeriesStyle::markers:
      return fmt::format("with points pt 7 ps 2 lc {}", colour);
    case SeriesStyle::dashed:
      return fmt::format("with lines dt 2 lw 2 lc {}", colour);
    case SeriesStyle::lines:
      break;
  }
  return fmt::format("with lines lw 2 lc {}", colour);
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

std::filesystem::path find_gnuplot() {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return {};
  std::stringstream folders(path);
  std::string folder;
  while (std::getline(folders, folder, ':')) {
    if (folder.empty()) continue;
    const std::filesystem::path candidate = std::filesystem::path(folder) / "gnuplot";
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

std::string gnuplot_script(const Chart& chart, const std::filesystem::path& svg,
                           const std::filesystem::path& png) {
  std::string s = "# shapepress report chart; run with: gnuplot <this file>\n";
  for (std::size_t k = 0; k < chart.series.size(); ++k) {
    s += fmt::format("$series{} << EOD\n", k);
    const Series& series = chart.series[k];
    for (std::size_t i = 0; i < series.x.size(); ++i) {
      if (!std::isfinite(series.x[i]) || !std::isfinite(series.y[i])) continue;
      if (has_error_bars(series))
        s += fmt::format("{:.10g} {:.10g} {:.10g}\n", series.x[i], series.y[i],
                         i < series.y_error.size() && std::isfinite(series.y_error[i])
                             ? series.y_error[i]
                             : 0.0);
      else
        s += fmt::format("{:.10g} {:.10g}\n", series.x[i], series.y[i]);
    }
    s += "EOD\n";
  }
  s += fmt::format("set title {} noenhanced\nset xlabel {} noenhanced\nset ylabel {} noenhanced\n",
                   gp_quoted(chart.title), gp_quoted(chart.x_label), gp_quoted(chart.y_label));
  // A map (markers only: a point per run) keeps its points off the frame and the key off them.
  const bool map = std::all_of(chart.series.begin(), chart.series.end(), [](const Series& series) {
    return series.style == SeriesStyle::markers || series.style == SeriesStyle::points;
  });
  s += "set grid\n";
  s += map ? "set key outside right top noenhanced box\n"
           : "set key left top noenhanced box opaque\n";
  s += "set autoscale\n";
  if (map) s += "set offsets graph 0.06, graph 0.06, graph 0.06, graph 0.06\n";
  if (chart.log_x) s += "set logscale x\n";
  if (chart.log_y) s += "set logscale y\n";
  if (chart.log_x && chart.log_x_from)
    s += fmt::format("set xrange [{:.6g}:*]\n", *chart.log_x_from);
  if (chart.log_y && chart.log_y_from)
    s += fmt::format("set yrange [{:.6g}:*]\n", *chart.log_y_from);
  std::string plot = "plot ";
  for (std::size_t k = 0; k < chart.series.size(); ++k) {
    if (k > 0) plot += ", ";
    const Series& series = chart.series[k];
    const bool bars = has_error_bars(series);
    plot += fmt::format("$series{} using {} title {} {}", k, bars ? "1:2:3" : "1:2",
                        gp_quoted(series.title),
                        style_of(series.style, series.colour, static_cast<int>(k), bars));
  }
  s += fmt::format("set terminal svg size 800,560 dynamic font 'sans,12'\nset output {}\n{}\n",
                   gp_quoted(svg.string()), plot);
  s += fmt::format("set terminal pngcairo size 1200,840 font 'sans,14'\nset output {}\n{}\n",
                   gp_quoted(png.string()), plot);
  return s + "set output\n";
}

ChartFiles plot_chart(const Chart& chart, const std::filesystem::path& stem) {
  ChartFiles files{stem, stem, stem, stem};
  files.svg += ".svg", files.png += ".png", files.csv += ".csv", files.script += ".gp";
  ensure_parent_directory(files.csv);

  // All-numeric so read_csv (and any spreadsheet) takes it; series titles in the comments.
  const bool error_bars = std::any_of(chart.series.begin(), chart.series.end(), has_error_bars);
  std::vector<std::string> columns{"series", chart.x_column, chart.y_column};
  if (error_bars) columns.push_back(chart.y_column + "_error");
  CsvWriter csv(files.csv, columns);
  csv.comment(fmt::format("{}: data of {}", chart.title, files.svg.filename().string()));
  for (std::size_t k = 0; k < chart.series.size(); ++k)
    csv.comment(fmt::format("series {} = {}", k, chart.series[k].title));
  for (std::size_t k = 0; k < chart.series.size(); ++k) {
    const Series& series = chart.series[k];
    for (std::size_t i = 0; i < series.x.size(); ++i) {
      std::vector<double> row{static_cast<double>(k), series.x[i], series.y[i]};
      if (error_bars) row.push_back(i < series.y_error.size() ? series.y_error[i] : std::nan(""));
      csv.row(row);
    }
  }
  csv.commit();
  // The saved script names the final files; the one run here writes temporary ones.
  write_file_atomically(files.script,
                        gnuplot_script(chart, files.svg.filename(), files.png.filename()));

  const std::filesystem::path gnuplot = find_gnuplot();
  if (gnuplot.empty())
    throw ComputationError(fmt::format(
        "cannot draw {}: gnuplot is not on PATH (install it: apt-get install gnuplot-nox)",
        files.svg.string()));
  const std::filesystem::path svg_tmp = temporary_path_for(files.svg);
  const std::filesystem::path png_tmp = temporary_path_for(files.png);
  const std::filesystem::path script_tmp = temporary_path_for(files.script);
  const std::filesystem::path log_tmp = temporary_path_for(stem.string() + ".log");
  write_file_atomically(script_tmp, gnuplot_script(chart, svg_tmp, png_tmp));
  const std::string command =
      fmt::format("'{}' '{}' > '{}' 2>&1", gnuplot.string(), script_tmp.string(), log_tmp.string());
  const int status = std::system(command.c_str());
  const std::string log = read_text(log_tmp);
  std::filesystem::remove(script_tmp);
  std::filesystem::remove(log_tmp);
  const bool ok = status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0 &&
                  std::filesystem::exists(svg_tmp) && std::filesystem::exists(png_tmp);
  if (!ok) {
    std::filesystem::remove(svg_tmp);
    std::filesystem::remove(png_tmp);
    throw ComputationError(fmt::format("gnuplot ({}) failed to draw {}: {}", gnuplot.string(),
                                       files.svg.string(), log));
  }
  commit_temporary_file(svg_tmp, files.svg);
  commit_temporary_file(png_tmp, files.png);
  return files;
}

}  // namespace shapepress::analysis
