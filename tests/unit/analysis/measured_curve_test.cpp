// Measured compaction curves: units from the column names, the axes from which columns are
// there, the loading branch, and the error at the measured points.
#include "analysis/measured_curve.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/error.hpp"
#include "tests/support/files.hpp"

namespace shapepress::analysis {
namespace {

std::filesystem::path written(const std::string& name, const std::string& text) {
  static const std::filesystem::path dir = testing::fresh_directory("measured_curve");
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

TEST(MeasuredCurve, ReadsUnitsFromTheColumnNames) {
  const MeasuredCurve c =
      read_measured_curve(written("ss.csv", "# a comment\nstrain_%,stress_MPa\n10,1\n57,30\n"));
  EXPECT_EQ(c.axes, MeasuredAxes::stress_strain);
  EXPECT_DOUBLE_EQ(c.x[1], 0.57);
  EXPECT_DOUBLE_EQ(c.y[1], 30e6);
  const MeasuredCurve d =
      read_measured_curve(written("sf.csv", "stress_kPa,solid_fraction_percent\n500,60\n"));
  EXPECT_EQ(d.axes, MeasuredAxes::solid_fraction_stress);
  EXPECT_DOUBLE_EQ(d.x[0], 5e5);
  EXPECT_DOUBLE_EQ(d.y[0], 0.6);
  // A force is not a stress; no strain or solid fraction column: both name the file.
  EXPECT_THROW(read_measured_curve(written("n.csv", "strain,stress_N\n0.1,1\n")), InputError);
  EXPECT_THROW(read_measured_curve(written("f.csv", "stress_MPa,force_N\n1,1\n")), InputError);
}

TEST(MeasuredCurve, LoadingBranchEndsAtTheLargestXAndSkipsDips) {
  MeasuredCurve c;
  c.x = {0.0, 0.1, 0.08, 0.2, 0.3, 0.25};
  c.y = {0.0, 1.0, 0.9, 2.0, 3.0, 1.0};
  const Curve l = c.loading();
  EXPECT_EQ(l.x, (std::vector<double>{0.0, 0.1, 0.2, 0.3}));
}

TEST(MeasuredCurve, ErrorsAtTheMeasuredPointsWithOneRecordOfSlack) {
  const Curve simulated{{0.0, 0.1, 0.2, 0.3}, {0.0, 1.0, 2.0, 3.0}, "sim"};
  // 10 % above the simulation at 0.15 and 0.25; 0.38 lies within one step (0.1) past its end
  // and counts against its last value; 0.45 lies beyond and is left out.
  const Curve measured{{0.15, 0.25, 0.38, 0.45}, {1.65, 2.75, 3.3, 9.0}, "m"};
  const MeasuredMismatch m = compare_with_measured(simulated, measured);
  EXPECT_EQ(m.points, 3);
  EXPECT_NEAR(m.max, 0.3, 1e-12);
  EXPECT_DOUBLE_EQ(m.at_max, 0.38);
  EXPECT_NEAR(m.rms_relative, 0.1 / 1.1, 1e-12);
  EXPECT_NEAR(m.max_relative, 0.1 / 1.1, 1e-12);
  EXPECT_EQ(compare_with_measured(simulated, measured, 0.2, 0.3).points, 1);
  // Near zero a relative error is noise: points below 5 % of the largest are not in it.
  const Curve tiny{{0.05, 0.3}, {1e-6, 3.3}, "m"};
  EXPECT_NEAR(compare_with_measured(simulated, tiny).max_relative, 0.1 / 1.1, 1e-12);
}

}  // namespace
}  // namespace shapepress::analysis
