#include "analysis/measured_curve.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/units.hpp"

namespace shapepress::analysis {
namespace {

constexpr std::string_view strain = "strain";
constexpr std::string_view stress = "stress";
constexpr std::string_view solid_fraction = "solid_fraction";

bool names_quantity(std::string_view column, std::string_view quantity) {
  return column == quantity ||
         (column.size() > quantity.size() + 1 && column.substr(0, quantity.size()) == quantity &&
          column[quantity.size()] == '_');
}

// The one column of the table that names `quantity`; empty when none, InputError when several.
std::string column_of(const CsvTable& table, std::string_view quantity) {
  std::string found;
  for (const std::string& c : table.columns) {
    if (!names_quantity(c, quantity)) continue;
    // solid_fraction_spheres and solid_fraction_shape (punch.csv) are the sub-spheres' and the
    // meshes' fractions, not the bed's.
    if (quantity == solid_fraction &&
        (c == "solid_fraction_spheres" || c == "solid_fraction_shape"))
      continue;
    if (!found.empty())
      throw InputError(fmt::format("{}: columns '{}' and '{}' both name {}; give the columns",
                                   table.source, found, c, quantity));
    found = c;
  }
  return found;
}

std::vector<double> column_in_si(const CsvTable& table, const std::string& column,
                                 std::string_view quantity) {
  const double factor = column_factor(column, quantity, quantity == stress, table.source);
  std::vector<double> values = table.column(column);
  for (double& v : values) {
    if (!std::isfinite(v))
      throw InputError(fmt::format("{}: column '{}' holds {}", table.source, column, v));
    v *= factor;
  }
  return values;
}

Curve rising(const std::vector<double>& x, const std::vector<double>& y, std::size_t end,
             std::string label) {
  Curve c{{}, {}, std::move(label)};
  for (std::size_t i = 0; i < end; ++i) {
    if (!c.x.empty() && !(x[i] > c.x.back())) continue;
    c.x.push_back(x[i]);
    c.y.push_back(y[i]);
  }
  return c;
}

}  // namespace

std::string axes_name(MeasuredAxes axes) {
  return axes == MeasuredAxes::stress_strain ? "stress-strain" : "solid fraction-stress";
}

double column_factor(std::string_view column, std::string_view quantity, bool pressure,
                     const std::filesystem::path& source) {
  if (column == quantity) return 1.0;  // SI: a fraction, or Pa
  const std::string_view given = column.substr(quantity.size() + 1);
  const std::string_view unit = given == "percent" || given == "pct" ? "%" : given;
  const std::string key = fmt::format("{}: column '{}'", source.string(), column);
  return parse_quantity(fmt::format("1 {}", unit), pressure ? dim::pressure : dim::dimensionless,
                        key);
}

Curve MeasuredCurve::loading() const {
  // Up to the largest x of the stress–strain record; the solid fraction–stress record rises in
  // stress until the unloading, which lowers the stress while D stays: cut at the peak stress.
  const std::size_t peak =
      static_cast<std::size_t>(std::max_element(x.begin(), x.end()) - x.begin());
  return rising(x, y, peak + 1, source.filename().string());
}

MeasuredCurve read_measured_curve(const std::filesystem::path& path, std::string x_column,
                                  std::string y_column) {
  const CsvTable table = read_csv(path);
  MeasuredCurve m;
  m.source = path;
  if (x_column.empty() != y_column.empty())
    throw InputError(fmt::format("{}: give both columns of the curve or neither", path.string()));
  if (x_column.empty()) {
    const std::string e = column_of(table, strain), s = column_of(table, stress),
                      d = column_of(table, solid_fraction);
    if (s.empty() || (e.empty() && d.empty()))
      throw InputError(fmt::format(
          "{}: a measured compaction curve needs a 'stress_<unit>' column and a 'strain' or "
          "'solid_fraction' column (unit in the name: strain_%, stress_MPa); it has {}",
          path.string(), fmt::join(table.columns, ", ")));
    // punch.csv has both: its stress–strain.
    x_column = e.empty() ? s : e;
    y_column = e.empty() ? d : s;
  }
  const bool x_stress = names_quantity(x_column, stress);
  if (x_stress && names_quantity(y_column, solid_fraction)) {
    m.axes = MeasuredAxes::solid_fraction_stress;
  } else if (names_quantity(x_column, strain) && names_quantity(y_column, stress)) {
    m.axes = MeasuredAxes::stress_strain;
  } else {
    throw InputError(fmt::format(
        "{}: columns '{}' and '{}' are neither strain and stress nor stress and solid_fraction",
        path.string(), x_column, y_column));
  }
  m.x_column = x_column;
  m.y_column = y_column;
  m.x = column_in_si(table, x_column, x_stress ? stress : strain);
  m.y = column_in_si(table, y_column, x_stress ? solid_fraction : stress);
  if (m.x.empty())
    throw InputError(fmt::format("{}: the measured curve has no rows", path.string()));
  return m;
}

Curve simulated_loading(const PunchCurve& run, MeasuredAxes axes) {
  std::vector<double> e, x, y;
  for (std::size_t i = 0; i < run.gap.size(); ++i)
    e.push_back((run.reference_gap - run.gap[i]) / run.reference_gap);
  std::size_t end = 0;
  while (end < run.phase.size() && run.phase[end] < static_cast<int>(PunchPhase::unload))
    ++end;
  if (axes == MeasuredAxes::stress_strain) return rising(e, run.stress, end, "simulated");
  return rising(run.stress, run.solid_fraction, end, "simulated");
}

MeasuredMismatch compare_with_measured(const Curve& simulated, const Curve& measured, double from,
                                       double to) {
  MeasuredMismatch d;
  if (simulated.x.size() < 2) return d;
  // A measured point up to one record step past the run's last loading record counts against
  // that record: a run stopped at its target strain records it at most a step short.
  const std::size_t n = simulated.x.size();
  const double end = simulated.x[n - 1] + (simulated.x[n - 1] - simulated.x[n - 2]);
  std::vector<std::size_t> compared;
  double largest = 0.0;
  for (std::size_t i = 0; i < measured.x.size(); ++i) {
    const double x = measured.x[i];
    if (x < from || x > to || x < simulated.x.front() || x > end) continue;
    compared.push_back(i);
    largest = std::max(largest, std::abs(measured.y[i]));
  }
  if (compared.empty()) return d;
  double sum = 0.0, sum_relative = 0.0;
  int relative_points = 0;
  d.from = measured.x[compared.front()];
  d.to = measured.x[compared.back()];
  for (std::size_t i : compared) {
    const double error = interpolate(simulated, measured.x[i]) - measured.y[i];
    ++d.points;
    sum += error * error;
    if (std::abs(error) >= d.max) d.max = std::abs(error), d.at_max = measured.x[i];
    // Relative errors where the measured value is at least a twentieth of its largest: near
    // zero (a loose bed's first contacts) a relative error measures noise, not the fit.
    if (std::abs(measured.y[i]) < relative_floor * largest) continue;
    const double relative = std::abs(error / measured.y[i]);
    sum_relative += relative * relative;
    ++relative_points;
    d.max_relative = std::max(d.max_relative, relative);
  }
  d.rms = std::sqrt(sum / d.points);
  if (relative_points > 0) d.rms_relative = std::sqrt(sum_relative / relative_points);
  return d;
}

}  // namespace shapepress::analysis
