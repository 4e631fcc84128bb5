#include "analysis/report_html.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "common/csv.hpp"

namespace shapepress::analysis {
namespace {

struct Metric {
  std::string name;
  double value;
  std::string unit;
  std::string meaning;
};

std::vector<Metric> compaction_metrics(const CompactionMetrics& m) {
  const double nan = NAN;
  std::vector<Metric> rows = {
      {"H0", m.reference_gap, "m", "reference gap of strain and Kawakita V0 (from punch.csv)"},
      {"peak_stress", m.peak_stress, "Pa", "maximum punch stress"},
      {"peak_force", m.peak_force, "N", "punch force at the peak stress"},
      {"solid_fraction_at_peak", m.solid_fraction_at_peak, "1", "D at the peak stress"},
      {"strain_at_peak", m.strain_at_peak, "1", "(H0-H)/H0 at the peak stress"},
      {"minimum_gap", m.minimum_gap, "m", "H_min"},
      {"unloaded_gap", m.unloaded ? m.unloaded_gap : nan, "m", "H at the end of unloading"},
      {"elastic_recovery", m.unloaded ? m.elastic_recovery : nan, "1",
       "(H_unloaded - H_min)/H_min"},
      {"work_of_compaction", m.work_of_compaction, "J", "integral of F d(-H), load and hold"},
      {"work_of_unloading", m.unloaded ? m.work_of_unloading : nan, "J",
       "integral of F dH while unloading"},
      {"heckel_K", m.heckel.k, "1/Pa", "ln(1/(1-D)) = K P + A"},
      {"heckel_A", m.heckel.a, "1", ""},
      {"heckel_yield_pressure", m.heckel.yield_pressure, "Pa", "Py = 1/K"},
      {"heckel_r_squared", m.heckel.r_squared, "1", ""},
      {"heckel_points", static_cast<double>(m.heckel.points), "1", ""},
      {"heckel_stress_lower", m.heckel.stress_lower, "Pa", "fitted window"},
      {"heckel_stress_upper", m.heckel.stress_upper, "Pa", ""},
      {"kawakita_a", m.kawakita.a, "1", "P/C = P/a + 1/(a b), C = (H0-H)/H0"},
      {"kawakita_b", m.kawakita.b, "1/Pa", ""},
      {"kawakita_r_squared", m.kawakita.r_squared, "1", ""},
      {"kawakita_points", static_cast<double>(m.kawakita.points), "1", ""},
      {"kawakita_stress_lower", m.kawakita.stress_lower, "Pa", "fitted window"},
      {"kawakita_stress_upper", m.kawakita.stress_upper, "Pa", ""},
      {"density_scale", m.density_scale, "1", "mass scaling: particle density x this"},
      {"max_kinetic_to_work", m.max_kinetic_to_work, "1",
       "quasi-static figure: kinetic energy / punch work (<= 0.01)"},
      {"mean_force_imbalance", m.mean_force_imbalance, "1",
       "quasi-static figure: mean |top - bottom| / top (<= 0.05)"},
  };
  return rows;
}

std::vector<Metric> plate_metrics(const PlateMetrics& m) {
  std::vector<Metric> rows = {
      {"radius", m.radius, "m", "R = approach/(2 deformation)"},
      {"effective_modulus", m.effective_modulus, "Pa", "E* from the run's Hertz column"},
      {"max_deformation", m.max_deformation, "1", "Delta/(2R)"},
      {"max_force", m.max_force, "N", ""},
      {"compared_from_deformation", m.compared_from, "1", "comparison over [this, max]"},
      {"hertz_rms_relative_error", m.versus_hertz.rms_relative, "1", "simulated vs Hertz"},
      {"hertz_max_relative_error", m.versus_hertz.max_relative, "1", ""},
  };
  if (m.versus_tatara) {
    rows.push_back({"poisson_ratio", *m.poisson_ratio, "1", "given with --poisson-ratio"});
    rows.push_back(
        {"tatara_rms_relative_error", m.versus_tatara->rms_relative, "1", "simulated vs Tatara"});
    rows.push_back({"tatara_max_relative_error", m.versus_tatara->max_relative, "1", ""});
  }
  return rows;
}

std::vector<Metric> metrics_of(const LoadedRun& run) {
  return run.compaction ? compaction_metrics(*run.compaction) : plate_metrics(*run.plate_metrics);
}

std::string json_number(double v) {
  return std::isfinite(v) ? format_number(v) : "null";
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The <svg> element of a gnuplot SVG file, without the XML prologue and doctype.
std::string inline_svg(const std::filesystem::path& path) {
  const std::string text = read_text(path);
  const std::size_t start = text.find("<svg");
  return start == std::string::npos ? std::string() : text.substr(start);
}

}  // namespace

std::string json_escape(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          out += fmt::format("\\u{:04x}", static_cast<int>(c));
        else
          out += c;
    }
  }
  return out;
}

std::string html_escape(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string metrics_json(const std::vector<LoadedRun>& runs, const FitWindows& windows,
                         const ReportProvenance& provenance,
                         const std::optional<StressSpread>& spread) {
  std::string s = "{\n";
  s += fmt::format(
      "  \"provenance\": {{\"command_line\": \"{}\", \"shapepress_version\": \"{}\", "
      "\"git_revision\": \"{}\"}},\n",
      json_escape(provenance.command_line), json_escape(provenance.version),
      json_escape(provenance.git_revision));
  s += fmt::format(
      "  \"fit_windows\": {{\"unit\": \"fraction of the peak stress, loading branch\", "
      "\"heckel\": [{}, {}], \"kawakita\": [{}, {}]}},\n",
      json_number(windows.heckel_lower), json_number(windows.heckel_upper),
      json_number(windows.kawakita_lower), json_number(windows.kawakita_upper));
  if (spread) {
    s += "  \"stress_spread\": {\"meaning\": \"(max - min)/mean of the loading stress of the "
         "compaction runs at each strain\", \"strain\": [";
    for (std::size_t i = 0; i < spread->strain.size(); ++i)
      s += (i == 0 ? "" : ", ") + json_number(spread->strain[i]);
    s += "], \"spread\": [";
    for (std::size_t i = 0; i < spread->spread.size(); ++i)
      s += (i == 0 ? "" : ", ") + json_number(spread->spread[i]);
    s += "]},\n";
  }
  s += "  \"runs\": [";
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const LoadedRun& run = runs[r];
    s += r == 0 ? "\n" : ",\n";
    s += fmt::format(
        "    {{\"label\": \"{}\", \"folder\": \"{}\", \"kind\": \"{}\", \"csv\": \"{}\",\n",
        json_escape(run.label), json_escape(run.files.folder.string()),
        run.compaction ? "compaction" : "plate", json_escape(run.files.csv.string()));
    s += "     \"source\": [";
    for (std::size_t i = 0; i < run.files.comments.size(); ++i)
      s += fmt::format("{}\"{}\"", i == 0 ? "" : ", ", json_escape(run.files.comments[i]));
    s += "],\n     \"metrics\": {";
    const std::vector<Metric> metrics = metrics_of(run);
    for (std::size_t i = 0; i < metrics.size(); ++i)
      s += fmt::format("{}\n       \"{}\": {{\"value\": {}, \"unit\": \"{}\"}}", i == 0 ? "" : ",",
                       metrics[i].name, json_number(metrics[i].value), metrics[i].unit);
    s += "}}";
  }
  return s + "\n  ]\n}\n";
}

std::string report_html(const std::vector<LoadedRun>& runs,
                        const std::vector<std::pair<std::string, std::filesystem::path>>& charts,
                        const ReportProvenance& provenance,
                        const std::optional<StressSpread>& spread) {
  std::string s =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<title>shapepress report</title>\n<style>\n"
      "body{font-family:sans-serif;max-width:960px;margin:2em auto;color:#222}\n"
      "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:2px 8px;"
      "text-align:left}td.num{text-align:right;font-family:monospace}\n"
      "figure{margin:1em 0}pre{background:#f4f4f4;padding:0.5em;white-space:pre-wrap}\n"
      "</style>\n</head>\n<body>\n<h1>shapepress report</h1>\n";
  s += fmt::format(
      "<p>{} run(s). Charts have their data beside them as CSV and a gnuplot script "
      "(same name, .csv and .gp); all numbers are in metrics.json.</p>\n",
      runs.size());
  s += "<h2>Charts</h2>\n";
  for (const auto& [title, svg] : charts)
    s += fmt::format("<figure>\n{}\n<figcaption>{} ({})</figcaption>\n</figure>\n", inline_svg(svg),
                     html_escape(title), html_escape(svg.filename().string()));
  s += "<h2>Metrics</h2>\n";
  for (const LoadedRun& run : runs) {
    s += fmt::format(
        "<h3>{} ({})</h3>\n<table>\n<tr><th>metric</th><th>value</th><th>unit</th>"
        "<th>meaning</th></tr>\n",
        html_escape(run.label), run.compaction ? "compaction" : "plate");
    for (const Metric& m : metrics_of(run))
      s += fmt::format("<tr><td>{}</td><td class=\"num\">{}</td><td>{}</td><td>{}</td></tr>\n",
                       m.name, std::isfinite(m.value) ? fmt::format("{:.6g}", m.value) : "-",
                       m.unit, html_escape(m.meaning));
    s += "</table>\n";
  }
  if (spread) {
    s += "<h3>Spread of the compaction runs</h3>\n<p>(max - min)/mean of the loading stress at "
         "each strain.</p>\n<table>\n<tr><th>strain</th><th>spread</th></tr>\n";
    for (std::size_t i = 0; i < spread->strain.size(); ++i)
      s += fmt::format("<tr><td class=\"num\">{:.4g}</td><td class=\"num\">{:.4g}</td></tr>\n",
                       spread->strain[i], spread->spread[i]);
    s += "</table>\n";
  }
  s += "<h2>Provenance</h2>\n";
  for (const LoadedRun& run : runs) {
    s += fmt::format("<p><b>{}</b>: {}</p>\n<pre>", html_escape(run.label),
                     html_escape(run.files.csv.string()));
    for (const std::string& line : run.files.comments)
      s += html_escape(line) + "\n";
    s += "</pre>\n";
  }
  s += fmt::format("<p>Report made by shapepress {} (git {}) with: <code>{}</code></p>\n",
                   html_escape(provenance.version), html_escape(provenance.git_revision),
                   html_escape(provenance.command_line));
  return s + "</body>\n</html>\n";
}

}  // namespace shapepress::analysis
