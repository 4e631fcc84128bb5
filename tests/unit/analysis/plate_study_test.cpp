// The single-particle study's numbers on synthetic plate runs with known differences.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/plate_study.hpp"

namespace shapepress::analysis {
namespace {

// A plate run F = scale · (√2/3) E* √R Δ^{3/2} at 1 % steps (R = 10 mm, E* = 22 MPa).
LoadedRun run(const std::string& label, int sub_spheres, double scale, double cpu) {
  LoadedRun r;
  r.label = label;
  PlateCurve c;
  const double radius = 0.01, e_star = 22e6;
  for (int k = 1; k <= 40; ++k) {
    const double d = k / 100.0, delta = 2 * radius * d;
    const double hertz =
        std::sqrt(2.0) / 3.0 * e_star * std::sqrt(radius) * delta * std::sqrt(delta);
    c.deformation.push_back(d);
    c.approach.push_back(delta);
    c.hertz_force.push_back(hertz);
    c.top_force.push_back(scale * hertz);
  }
  c.sub_spheres = sub_spheres;
  c.cpu_seconds = cpu;
  c.wall_seconds = cpu;
  r.plate = c;
  return r;
}

TEST(PlateStudy, ComparesEveryRunWithTheFinestAndCharts) {
  const std::vector<LoadedRun> runs = {run("coarse", 100, 1.10, 1.0), run("fine", 1322, 1.0, 30.0),
                                       run("mid", 545, 0.98, 8.0), run("hertz", 1, 1.0, 0.01)};
  const auto study = plate_study(runs, std::nullopt);
  ASSERT_TRUE(study);
  EXPECT_EQ(study->finest, "fine");
  ASSERT_EQ(study->rows.size(), 4u);
  EXPECT_NEAR(study->rows[0].versus_finest.rms_relative, 0.10, 1e-9);
  EXPECT_NEAR(study->rows[0].max_step_versus_finest, 0.10, 1e-9);
  EXPECT_NEAR(study->rows[2].max_step_versus_finest, 0.02, 1e-9);
  EXPECT_EQ(study->rows[1].versus_finest.rms_relative, 0.0);
  EXPECT_FALSE(study->rows[0].versus_tatara);
  const auto with_nu = plate_study(runs, 0.46);
  ASSERT_TRUE(with_nu && with_nu->rows[3].versus_tatara);
  // Hertz against Tatara over 5–40 %: Tatara is 16–59 % above Hertz (reference table).
  EXPECT_GT(with_nu->rows[3].versus_tatara->max_relative, 0.3);
  const std::vector<Chart> charts = plate_study_charts(*study);
  ASSERT_EQ(charts.size(), 2u);
  EXPECT_EQ(charts[0].series[0].x, (std::vector<double>{100, 545, 1322}));  // sorted by N
}

TEST(PlateStudy, NeedsTwoRunsWithSubSphereCounts) {
  const std::vector<LoadedRun> runs = {run("a", 0, 1.0, -1), run("b", 545, 1.0, 1.0)};
  EXPECT_FALSE(plate_study(runs, std::nullopt));
  // Two single spheres (a Hertz and a multi-contact plate run, N = 1 each) are no study either:
  // the demo's report has exactly those.
  const std::vector<LoadedRun> singles = {run("hertz", 1, 1.0, 0.1), run("mc", 1, 1.0, 0.1)};
  EXPECT_FALSE(plate_study(singles, std::nullopt));
  const std::vector<LoadedRun> ladder = {run("hertz", 1, 1.0, 0.1), run("n100", 100, 1.0, 1.0),
                                         run("n250", 250, 1.0, 2.0)};
  EXPECT_TRUE(plate_study(ladder, std::nullopt));
}

}  // namespace
}  // namespace shapepress::analysis
