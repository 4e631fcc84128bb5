#include "analysis/report_html.hpp"

#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "common/csv.hpp"

namespace shapepress::analysis {
namespace {

// A text cell of a CSV, quoted (RFC 4180) when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text)
    quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

struct Metric {
  std::string name;
  double value;
  std::string unit;
  std::string meaning;
  // A dimensionless value that is a fraction, shown in %; counts and coefficients are not.
  bool fraction = false;
};

std::vector<Metric> compaction_metrics(const CompactionMetrics& m) {
  const double nan = NAN;
  std::vector<Metric> rows = {
      {"H0", m.reference_gap, "m",
       "reference gap of the strain (from punch.csv); Kawakita's V0 is the gap where loading "
       "starts"},
      {"peak_stress", m.peak_stress, "Pa", "maximum punch stress"},
      {"peak_force", m.peak_force, "N", "punch force at the peak stress"},
      {"solid_fraction_at_peak", m.solid_fraction_at_peak, "1", "D at the peak stress", true},
      {"strain_at_peak", m.strain_at_peak, "1", "(H0-H)/H0 at the peak stress", true},
      {"minimum_gap", m.minimum_gap, "m", "H_min"},
      {"unloaded_gap", m.unloaded ? m.unloaded_gap : nan, "m", "H at the end of unloading"},
      {"elastic_recovery", m.unloaded ? m.elastic_recovery : nan, "1", "(H_unloaded - H_min)/H_min",
       true},
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
      {"kawakita_a", m.kawakita.a, "1", "P/C = P/a + 1/(a b), C = (H0-H)/H0", true},
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
      {"max_deformation", m.max_deformation, "1", "Delta/(2R)", true},
      {"max_force", m.max_force, "N", ""},
      {"compared_from_deformation", m.compared_from, "1", "comparison over [this, max]", true},
      {"hertz_rms_relative_error", m.versus_hertz.rms_relative, "1", "simulated vs Hertz", true},
      {"hertz_max_relative_error", m.versus_hertz.max_relative, "1", "", true},
  };
  if (m.versus_tatara) {
    rows.push_back({"poisson_ratio", *m.poisson_ratio, "1", "given with --poisson-ratio"});
    rows.push_back({"tatara_rms_relative_error", m.versus_tatara->rms_relative, "1",
                    "simulated vs Tatara", true});
    rows.push_back({"tatara_max_relative_error", m.versus_tatara->max_relative, "1", "", true});
  }
  return rows;
}

// A bed's own facts (metrics.json's "bed"): its state before the punch, and the loops' wall
// seconds; NaN where a fact is unknown. Counts are plain numbers (unit "1", not a fraction).
std::vector<Metric> bed_state_metrics(const BedFacts& bed) {
  const auto known = [](const std::optional<double>& v) { return v.value_or(NAN); };
  return {
      {"bodies", static_cast<double>(bed.bodies), "1", "bodies (spheres for a sphere bed)"},
      {"sub_spheres_per_body", bed.sub_spheres_per_body, "1", ""},
      {"projected_aspect_ratio", known(bed.projected_aspect_ratio), "1",
       "mean over the bodies of Feret min/max in 64 random views"},
      {"projected_aspect_ratio_sd", known(bed.projected_aspect_ratio_sd), "1", "over the bodies"},
      {"settled_solid_fraction", known(bed.settled_solid_fraction), "1",
       "by shape volume, after the settle", true},
      {"precompression_solid_fraction", known(bed.precompression_solid_fraction), "1",
       "what the pack's punch pressed the bed to", true},
  };
}
std::vector<Metric> bed_wall_metrics(const BedFacts& bed) {
  const auto known = [](const std::optional<double>& v) { return v.value_or(NAN); };
  return {
      {"pack_wall", known(bed.pack_seconds), "s", "the pack's stepping loop"},
      {"compaction_wall", known(bed.compaction_seconds), "s", "the compaction's stepping loop"},
  };
}

// The row of a compaction run in the table of beds: its state, the compaction's figures, the
// wall seconds.
std::vector<Metric> bed_table_row(const BedFacts& bed, const CompactionMetrics& m) {
  std::vector<Metric> row = bed_state_metrics(bed);
  row.insert(row.end(),
             {
                 {"peak_stress", m.peak_stress, "Pa", ""},
                 {"elastic_recovery", m.unloaded ? m.elastic_recovery : NAN, "1", "", true},
                 {"heckel_yield_pressure", m.heckel.yield_pressure, "Pa", "Heckel Py"},
                 {"kawakita_a", m.kawakita.a, "1", "", true},
                 {"kawakita_1_over_b", m.kawakita.b > 0 ? 1 / m.kawakita.b : NAN, "Pa", ""},
                 {"work_of_compaction", m.work_of_compaction, "J", ""},
             });
  const std::vector<Metric> walls = bed_wall_metrics(bed);
  row.insert(row.end(), walls.begin(), walls.end());
  return row;
}

// Seconds as whole seconds; everything else as the other tables show it.
std::string shown_cell(const Metric& m) {
  if (m.unit == "s") return std::isfinite(m.value) ? fmt::format("{:.0f}", m.value) : "-";
  return shown_text(shown_value(m.value, m.unit, m.fraction).value);
}

std::string bed_header(const Metric& m, bool csv) {
  std::string unit = shown_value(1.0, m.unit, m.fraction).unit;
  if (unit == "%") unit = csv ? "percent" : "%";
  if (unit.empty()) return m.name;
  return csv ? fmt::format("{}_{}", m.name, unit) : fmt::format("{} [{}]", m.name, unit);
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

std::string experiments_json(const std::vector<ExperimentComparison>& experiments) {
  std::string s = "  \"experiments\": [";
  for (std::size_t e = 0; e < experiments.size(); ++e) {
    const ExperimentComparison& x = experiments[e];
    const bool strain = x.curve.axes == MeasuredAxes::stress_strain;
    s += fmt::format(
        "{}\n    {{\"file\": \"{}\", \"axes\": \"{}\", \"x_column\": \"{}\", \"y_column\": "
        "\"{}\", \"rows\": {}, \"runs\": [",
        e == 0 ? "" : ",", json_escape(x.curve.source.string()), axes_name(x.curve.axes),
        json_escape(x.curve.x_column), json_escape(x.curve.y_column), x.curve.x.size());
    for (std::size_t r = 0; r < x.runs.size(); ++r) {
      const auto& [label, m] = x.runs[r];
      s += fmt::format(
          "{}\n      {{\"label\": \"{}\", \"points\": {}, \"x_from\": {}, \"x_to\": {}, "
          "\"x_unit\": \"{}\", \"rms\": {}, \"max\": {}, \"at_x\": {}, \"unit\": \"{}\", "
          "\"rms_relative\": {}, \"max_relative\": {}}}",
          r == 0 ? "" : ",", json_escape(label), m.points, json_number(m.points > 0 ? m.from : NAN),
          json_number(m.points > 0 ? m.to : NAN), strain ? "1" : "Pa",
          json_number(m.points > 0 ? m.rms : NAN), json_number(m.points > 0 ? m.max : NAN),
          json_number(m.points > 0 ? m.at_max : NAN), strain ? "Pa" : "1",
          json_number(m.points > 0 ? m.rms_relative : NAN),
          json_number(m.points > 0 ? m.max_relative : NAN));
    }
    s += "]}";
  }
  return s + "\n  ],\n";
}

std::string experiments_html(const std::vector<ExperimentComparison>& experiments) {
  std::string s;
  for (const ExperimentComparison& x : experiments) {
    const bool strain = x.curve.axes == MeasuredAxes::stress_strain;
    s += fmt::format(
        "<h3>Against the experiment {} ({})</h3>\n<p>Each run's loading branch at the measured "
        "points ({} rows, columns {} and {}) it covers; errors in "
        "{}.</p>\n<table>\n<tr><th>run</th>"
        "<th>points</th><th>{} from</th><th>to</th><th>RMS error</th><th>largest error</th>"
        "<th>at {}</th><th>RMS relative</th><th>largest relative</th></tr>\n",
        html_escape(x.curve.source.filename().string()), axes_name(x.curve.axes), x.curve.x.size(),
        html_escape(x.curve.x_column), html_escape(x.curve.y_column),
        strain ? "stress" : "solid fraction", strain ? "strain" : "stress",
        strain ? "strain" : "stress");
    for (const auto& [label, m] : x.runs) {
      const auto x_text = [&](double v) {
        const ShownValue shown = shown_value(v, strain ? "1" : "Pa", true);
        return shown_text(m.points > 0 ? shown.value : NAN) + " " + shown.unit;
      };
      const auto y_text = [&](double v) {
        const ShownValue shown = shown_value(v, strain ? "Pa" : "1", true);
        return shown_text(m.points > 0 ? shown.value : NAN) + " " + shown.unit;
      };
      s += fmt::format(
          "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td "
          "class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td "
          "class=\"num\">{}</td><td class=\"num\">{} %</td><td class=\"num\">{} %</td></tr>\n",
          html_escape(label), m.points, x_text(m.from), x_text(m.to), y_text(m.rms), y_text(m.max),
          x_text(m.at_max), shown_text(m.points > 0 ? 100.0 * m.rms_relative : NAN),
          shown_text(m.points > 0 ? 100.0 * m.max_relative : NAN));
    }
    s += "</table>\n";
  }
  return s;
}

// "advice": one entry per advise folder: its pick, reference, tolerance, cost and every rung.
std::string advice_json(const std::vector<AdviceRecord>& advice) {
  std::string s = "  \"advice\": [";
  for (std::size_t a = 0; a < advice.size(); ++a) {
    const AdviceRecord& r = advice[a];
    s += fmt::format(
        "{}\n    {{\"folder\": \"{}\", \"pick\": \"{}\", \"reference\": \"{}\", "
        "\"tolerance\": {}, \"pick_error_vs_reference\": {}, \"cost_saved_factor\": {}, "
        "\"predicted_full_run_counted_cost\": {}, \"cpu_saved_factor\": {}, "
        "\"predicted_full_run_cpu_s\": {}, \"seed_scatter\": {}, \"rungs\": [",
        a == 0 ? "" : ",", json_escape(r.folder.string()), json_escape(r.pick.value_or("")),
        json_escape(r.reference.value_or("")), json_number(r.advice.tolerance),
        json_number(r.pick_error.value_or(NAN)), json_number(r.cost_saved_factor.value_or(NAN)),
        json_number(r.predicted_full_run_counted_cost.value_or(NAN)),
        json_number(r.cpu_saved_factor.value_or(NAN)),
        json_number(r.predicted_full_run_cpu_s.value_or(NAN)),
        json_number(r.advice.seed_scatter.value_or(NAN)));
    for (std::size_t k = 0; k < r.advice.rows.size(); ++k) {
      const AdviceRow& row = r.advice.rows[k];
      s += fmt::format(
          "{}\n      {{\"label\": \"{}\", \"status\": \"{}\", \"cause\": \"{}\", "
          "\"sub_spheres\": {}, \"time_step_fraction\": {}, \"density_scale\": {}, "
          "\"seed\": {}, \"counted_cost\": {}, \"cpu_s\": {}, \"error\": {}}}",
          k == 0 ? "" : ",", json_escape(row.rung->label), status_name(row.status),
          json_escape(row.rung->cause), row.rung->sub_spheres,
          json_number(row.rung->time_step_fraction), json_number(row.rung->density_scale),
          row.rung->seed,
          row.rung->counted_cost >= 0 ? std::to_string(row.rung->counted_cost) : "null",
          json_number(row.rung->cpu_seconds >= 0 ? row.rung->cpu_seconds : NAN),
          json_number(row.error));
    }
    s += "]}";
  }
  return s + "\n  ],\n";
}

// A percentage cell of a fraction; empty where it is not finite.
std::string percent_cell(double fraction) {
  return std::isfinite(fraction) ? fmt::format("{:.3g}", 100.0 * fraction) : std::string();
}

std::string advice_html(const AdviceRecord& r) {
  std::string s = fmt::format("<h2>Advice: {}</h2>\n<p>", html_escape(r.folder.string()));
  if (r.pick)
    s += fmt::format("Pick <b>{}</b>, {} % from the reference {} (tolerance {} %)",
                     html_escape(*r.pick), percent_cell(r.pick_error.value_or(NAN)),
                     html_escape(r.reference.value_or("?")), percent_cell(r.advice.tolerance));
  else
    s += "No pick";
  // The counted cost (what the pick goes by) and the CPU seconds measured beside it.
  const auto beside = [](std::optional<double> cpu, const char* form) {
    return cpu ? fmt::format(fmt::runtime(form), *cpu) : std::string();
  };
  if (r.cost_saved_factor)
    s += fmt::format("; {:.3g} times less counted cost{}", *r.cost_saved_factor,
                     beside(r.cpu_saved_factor, " ({:.3g} times less CPU)"));
  if (r.predicted_full_run_counted_cost && r.full_bodies > 0)
    s += fmt::format("; the full bed of {} bodies predicted at a counted cost of {:.3g}{}",
                     r.full_bodies, *r.predicted_full_run_counted_cost,
                     beside(r.predicted_full_run_cpu_s, " ({:.3g} s CPU)"));
  if (r.advice.seed_scatter)
    s += fmt::format("; the seeds' finest rungs differ by {} %",
                     percent_cell(*r.advice.seed_scatter));
  s += ".</p>\n<table>\n<tr><th>rung</th><th>status</th><th>cause</th><th>sub-spheres</th>"
       "<th>step fraction</th><th>mass scaling</th><th>seed</th><th>counted cost</th><th>CPU s</th>"
       "<th>curve RMS %</th>";
  if (r.compaction) s += "<th>peak %</th><th>recovery %</th><th>Py %</th>";
  s += "<th>error %</th><th>pick</th></tr>\n";
  for (const AdviceRow& row : r.advice.rows) {
    const Rung& rung = *row.rung;
    const bool judged = row.status == RungStatus::within || row.status == RungStatus::off;
    s += fmt::format(
        "<tr><td>{}</td><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{:g}"
        "</td><td class=\"num\">{:g}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>"
        "<td class=\"num\">{}</td><td class=\"num\">{}</td>",
        html_escape(rung.label), status_name(row.status), html_escape(rung.cause), rung.sub_spheres,
        rung.time_step_fraction, rung.density_scale, rung.seed,
        rung.counted_cost >= 0 ? std::to_string(rung.counted_cost) : std::string(),
        rung.cpu_seconds >= 0 ? fmt::format("{:.3g}", rung.cpu_seconds) : std::string(),
        judged ? percent_cell(row.versus_reference.rms_relative) : std::string());
    if (r.compaction)
      s += fmt::format(
          "<td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}"
          "</td>",
          judged ? percent_cell(row.peak_difference) : std::string(),
          judged ? percent_cell(row.recovery_difference) : std::string(),
          judged ? percent_cell(row.yield_pressure_difference) : std::string());
    const bool picked = r.advice.pick && &r.advice.rows[*r.advice.pick] == &row;
    s += fmt::format("<td class=\"num\">{}</td><td>{}</td></tr>\n",
                     judged ? percent_cell(row.error) : std::string(), picked ? "pick" : "");
  }
  return s + "</table>\n";
}

std::string beds_html(const std::vector<LoadedRun>& runs) {
  std::string s, notes;
  for (const LoadedRun& run : runs) {
    if (!run.bed || !run.compaction) continue;
    const std::vector<Metric> row = bed_table_row(*run.bed, *run.compaction);
    if (s.empty()) {
      s = "<h2>Beds</h2>\n<p>Each compaction's bed before the punch (from the run.json of the "
          "pack that made it) and its bodies (measured on the packing), beside the compaction's "
          "figures.</p>\n<table>\n<tr><th>run</th><th>particle</th>";
      for (const Metric& m : row)
        s += fmt::format("<th>{}</th>", html_escape(bed_header(m, false)));
      s += "</tr>\n";
    }
    s += fmt::format("<tr><td>{}</td><td>{}</td>", html_escape(run.label),
                     html_escape(run.bed->particle_kind));
    for (const Metric& m : row)
      s += fmt::format("<td class=\"num\">{}</td>", shown_cell(m));
    s += "</tr>\n";
    for (const std::string& note : run.bed->notes)
      notes += fmt::format("<li>{}: {}</li>\n", html_escape(run.label), html_escape(note));
  }
  if (s.empty()) return s;
  s += "</table>\n";
  if (!notes.empty()) s += fmt::format("<ul>\n{}</ul>\n", notes);
  return s;
}

}  // namespace

std::string beds_csv(const std::vector<LoadedRun>& runs) {
  std::string s;
  for (const LoadedRun& run : runs) {
    if (!run.bed || !run.compaction) continue;
    const std::vector<Metric> row = bed_table_row(*run.bed, *run.compaction);
    if (s.empty()) {
      s = "label,particle_kind";
      for (const Metric& m : row)
        s += fmt::format(",{}", bed_header(m, true));
      s += "\n";
    }
    s += fmt::format("{},{}", csv_field(run.label), csv_field(run.bed->particle_kind));
    for (const Metric& m : row) {
      const double shown = shown_value(m.value, m.unit, m.fraction).value;
      s += fmt::format(",{}", std::isfinite(shown) ? format_number(shown) : std::string());
    }
    s += "\n";
  }
  return s;
}

ShownValue shown_value(double in_si, std::string_view unit, bool fraction) {
  if (unit == "Pa") return {in_si * 1e-6, "MPa"};
  if (unit == "1/Pa") return {in_si * 1e6, "1/MPa"};
  if (unit == "m") return {in_si * 1e3, "mm"};
  if (unit == "J") return {in_si * 1e3, "mJ"};
  if (unit == "1") return fraction ? ShownValue{100.0 * in_si, "%"} : ShownValue{in_si, ""};
  return {in_si, std::string(unit)};
}

std::string shown_text(double value) {
  if (!std::isfinite(value)) return "-";
  // Four significant digits without an exponent where a reader expects none (50000 mJ, not
  // 5e+04); an exponent only far outside the ranges the units are chosen for.
  const double size = std::abs(value);
  if (size == 0.0 || (size >= 1e-3 && size < 1e4)) return fmt::format("{:.4g}", value);
  if (size >= 1e4 && size < 1e9) return fmt::format("{:.0f}", value);
  return fmt::format("{:.3e}", value);
}

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
                         const std::optional<StressSpread>& spread,
                         const std::vector<ExperimentComparison>& experiments,
                         const std::vector<AdviceRecord>& advice) {
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
  if (!experiments.empty()) s += experiments_json(experiments);
  if (!advice.empty()) s += advice_json(advice);
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
    s += "}";
    if (run.bed && run.compaction) {
      s += fmt::format(",\n     \"bed\": {{\"particle_kind\": \"{}\"",
                       json_escape(run.bed->particle_kind));
      std::vector<Metric> facts = bed_state_metrics(*run.bed);
      const std::vector<Metric> walls = bed_wall_metrics(*run.bed);
      facts.insert(facts.end(), walls.begin(), walls.end());
      for (const Metric& m : facts)
        s += fmt::format(",\n       \"{}\": {{\"value\": {}, \"unit\": \"{}\"}}", m.name,
                         json_number(m.value), m.unit);
      s += ",\n       \"notes\": [";
      for (std::size_t i = 0; i < run.bed->notes.size(); ++i)
        s += fmt::format("{}\"{}\"", i == 0 ? "" : ", ", json_escape(run.bed->notes[i]));
      s += "]}";
    }
    s += "}";
  }
  return s + "\n  ]\n}\n";
}

std::string report_html(const std::vector<LoadedRun>& runs,
                        const std::vector<std::pair<std::string, std::filesystem::path>>& charts,
                        const ReportProvenance& provenance,
                        const std::optional<StressSpread>& spread,
                        const std::vector<ExperimentComparison>& experiments,
                        const std::vector<AdviceRecord>& advice) {
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
  s += beds_html(runs);
  for (const AdviceRecord& record : advice)
    s += advice_html(record);
  s += "<h2>Metrics</h2>\n";
  for (const LoadedRun& run : runs) {
    s += fmt::format(
        "<h3>{} ({})</h3>\n<table>\n<tr><th>metric</th><th>value</th><th>unit</th>"
        "<th>meaning</th></tr>\n",
        html_escape(run.label), run.compaction ? "compaction" : "plate");
    for (const Metric& m : metrics_of(run)) {
      // Counts are whole numbers; everything else in the unit a reader expects.
      const bool count = m.name.ends_with("_points");
      const ShownValue shown = shown_value(m.value, m.unit, m.fraction);
      s += fmt::format("<tr><td>{}</td><td class=\"num\">{}</td><td>{}</td><td>{}</td></tr>\n",
                       m.name,
                       count && std::isfinite(m.value) ? fmt::format("{:.0f}", m.value)
                                                       : shown_text(shown.value),
                       html_escape(shown.unit), html_escape(m.meaning));
    }
    s += "</table>\n";
  }
  if (spread) {
    s += "<h3>Spread of the compaction runs</h3>\n<p>(max - min)/mean of the loading stress at "
         "each strain.</p>\n<table>\n<tr><th>strain</th><th>spread</th></tr>\n";
    for (std::size_t i = 0; i < spread->strain.size(); ++i)
      s +=
          fmt::format("<tr><td class=\"num\">{} %</td><td class=\"num\">{} %</td></tr>\n",
                      shown_text(100.0 * spread->strain[i]), shown_text(100.0 * spread->spread[i]));
    s += "</table>\n";
  }
  s += experiments_html(experiments);
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
