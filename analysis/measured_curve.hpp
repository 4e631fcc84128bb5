#pragma once
// A measured compaction curve (an experiment, or a reference a calibration is fitted to) and how
// far a simulated compaction is from it. Two kinds, as tableting papers report them: stress
// against strain, or solid fraction against stress. The CSV carries the unit in each column name
// (`strain`, `strain_%`, `stress_MPa`, `solid_fraction`), so a curve digitised in MPa and
// percent reads the same as one shapepress wrote in Pa and fractions.
#include <cmath>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/compaction.hpp"
#include "analysis/curves.hpp"

namespace shapepress::analysis {

enum class MeasuredAxes {
  stress_strain,          // x strain (H0 − H)/H0, y punch stress [Pa]
  solid_fraction_stress,  // x punch stress [Pa], y solid fraction D
};

// "stress–strain" or "solid fraction–stress".
std::string axes_name(MeasuredAxes axes);

struct MeasuredCurve {
  MeasuredAxes axes = MeasuredAxes::stress_strain;
  std::vector<double> x, y;  // SI: strain and Pa, or Pa and solid fraction; the file's order
  std::string x_column, y_column;
  std::filesystem::path source;
  // Its loading branch: the points before x first falls, each above the last kept x (a
  // load–unload record keeps its load; a dip in noisy data is skipped, not a cut).
  Curve loading() const;
};

// The factor that turns a column's numbers into SI: `quantity` alone (a fraction, or Pa for
// stress), `quantity_UNIT` with UNIT a unit of `dimension` ("MPa", "kPa", "psi" is not one), or
// `quantity_%` / `quantity_percent` for a dimensionless one. InputError naming the file and
// the column otherwise.
double column_factor(std::string_view column, std::string_view quantity, bool pressure,
                     const std::filesystem::path& source);

// Reads a measured curve. With both columns empty the axes come from the names: a `strain…`
// and a `stress…` column make a stress–strain curve, a `solid_fraction…` and a `stress…` column
// a solid fraction–stress curve. InputError naming the file when it has neither pair, a unit is
// not one, or fewer than two rows.
MeasuredCurve read_measured_curve(const std::filesystem::path& path, std::string x_column = {},
                                  std::string y_column = {});

// A simulated compaction on the measured curve's axes, its loading branch (rows before the
// unloading starts, rising in x as MeasuredCurve::loading takes them).
Curve simulated_loading(const PunchCurve& run, MeasuredAxes axes);

// How far a simulated curve is from a measured one, at the measured points (no resampling:
// each measured point counts once) whose x lies in [from, to] and within the simulated curve's
// x range; a measured point up to one record step (the last x step of the simulated curve)
// beyond its end counts against its last value (a run stopped one record short of the measured
// 57 %). Relative errors are taken where |y_meas| is at least `relative_floor` of the largest
// |y_meas| compared.
inline constexpr double relative_floor = 0.05;
struct MeasuredMismatch {
  int points = 0;               // measured points compared
  double rms = 0.0;             // √(mean (y_sim − y_meas)²), in y's SI unit
  double max = 0.0;             // largest |y_sim − y_meas|
  double at_max = 0.0;          // x of that point
  double rms_relative = 0.0;    // √(mean ((y_sim − y_meas)/y_meas)²) (above the floor)
  double max_relative = 0.0;    // largest |y_sim − y_meas|/|y_meas| (above the floor)
  double from = 0.0, to = 0.0;  // x of the first and last point compared
};
MeasuredMismatch compare_with_measured(const Curve& simulated, const Curve& measured,
                                       double from = -HUGE_VAL, double to = HUGE_VAL);

}  // namespace shapepress::analysis
