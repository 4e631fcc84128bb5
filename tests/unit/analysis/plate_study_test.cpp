// The single-particle study's numbers on synthetic plate runs with known differences.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/plate_study.hpp"
#include "common/error.hpp"

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
  ASSERT_EQ(charts.size(), 3u);
  EXPECT_EQ(charts[0].series[0].x, (std::vector<double>{100, 545, 1322}));  // sorted by N
  // (d): N = 100 and 545 against the finest at the 36 steps, then the ±2 % lines (one fill
  // each: no band of standard errors).
  ASSERT_EQ(charts[2].series.size(), 4u);
  EXPECT_EQ(charts[2].series[0].x.size(), 36u);
  EXPECT_NEAR(charts[2].series[1].y.front(), -2.0, 1e-9);
}

// FEM runs (fem-plate) join the study as the other half of Fig. 2b: by elements, each against
// the finest FEM run, and every BMS run against that run too; they are not BMS rows.
TEST(PlateStudy, FemRunsAreChartedByElementsAgainstTheFinestFem) {
  const auto fem = [](const std::string& label, int elements, double scale, double cpu) {
    LoadedRun r = run(label, 1, scale, cpu);
    r.plate->particle = "fem";
    r.plate->elements = elements;
    return r;
  };
  const std::vector<LoadedRun> runs = {run("coarse", 100, 1.10, 1.0), run("fine", 1322, 1.0, 30.0),
                                       fem("fem-48", 5088, 1.05, 80.0),
                                       fem("fem-12", 336, 1.05 * 1.01, 4.0)};
  const auto study = plate_study(runs, std::nullopt);
  ASSERT_TRUE(study);
  EXPECT_EQ(study->finest, "fine");
  ASSERT_EQ(study->rows.size(), 2u);  // the BMS runs only
  ASSERT_EQ(study->fem.size(), 2u);
  EXPECT_EQ(study->fem[0].label, "fem-12");  // by elements
  EXPECT_NEAR(study->fem[0].versus_finest_fem.rms_relative, 0.01, 1e-9);
  EXPECT_EQ(study->fem[1].versus_finest_fem.rms_relative, 0.0);
  ASSERT_TRUE(study->rows[1].versus_fem);
  EXPECT_NEAR(study->rows[1].versus_fem->rms_relative, 1.0 - 1.0 / 1.05, 1e-9);
  const std::vector<Chart> charts = plate_study_charts(*study);
  ASSERT_EQ(charts[0].series.size(), 3u);
  EXPECT_EQ(charts[0].series[2].x, (std::vector<double>{336, 5088}));
  EXPECT_EQ(charts[0].series[2].y, (std::vector<double>{4.0, 80.0}));
  const auto& accuracy = charts[1].series;
  ASSERT_EQ(accuracy.back().title, "FEM vs the finest FEM");
  EXPECT_EQ(accuracy.back().x, (std::vector<double>{4.0}));  // the finest is not charted
  EXPECT_NEAR(accuracy.back().y[0], 1.0, 1e-7);              // percent
}

TEST(PlateStudy, MeansOfFillsCarryTheStandardErrorOfTheirDifference) {
  // 819 at 1.03 × the finest, both means of 16 fills whose top force spreads by 8 % (sd): each
  // mean's standard error is 2 % of it, so that of the ratio 1.03 is 1.03 · √2 · 0.02.
  LoadedRun a = run("n819", 819, 1.03, 5.0), b = run("n1322", 1322, 1.0, 11.0);
  for (LoadedRun* r : {&a, &b}) {
    r->plate->fills = 16;
    for (double f : r->plate->top_force)
      r->plate->top_force_sd.push_back(0.08 * f);
  }
  const auto study = plate_study({a, b}, std::nullopt);
  ASSERT_TRUE(study);
  const PlateStudyRow& row = study->rows[0];
  EXPECT_EQ(row.fills, 16);
  ASSERT_EQ(row.steps.size(), 36u);
  for (const PlateStep& step : row.steps) {
    EXPECT_NEAR(step.versus_finest, 0.03, 1e-9);
    EXPECT_NEAR(step.force_error / step.force, 0.02, 1e-9);
    EXPECT_NEAR(step.versus_finest_error, std::sqrt(2.0) * 1.03 * 0.02, 1e-9);
  }
  EXPECT_TRUE(study->rows[1].steps.front().versus_finest_error == 0.0);  // the finest itself
  // The chart's band: 3 % ± two standard errors.
  const Chart chart = plate_study_charts(*study)[2];
  ASSERT_EQ(chart.series.size(), 5u);  // N = 819, its band (two lines), ±2 %
  EXPECT_NEAR(chart.series[1].y.front(), 3.0 - 200 * std::sqrt(2.0) * 1.03 * 0.02, 1e-9);
  EXPECT_NEAR(chart.series[2].y.front(), 3.0 + 200 * std::sqrt(2.0) * 1.03 * 0.02, 1e-9);
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

// A run of one method (particle kind) whose force is scale · Hertz, with a dropout row.
LoadedRun method_run(const std::string& label, const std::string& particle, int sub_spheres,
                     double scale) {
  LoadedRun r = run(label, sub_spheres, scale, 1.0);
  r.plate->particle = particle;
  for (std::size_t i = 0; i < r.plate->deformation.size(); ++i)
    r.plate->contacts.push_back(static_cast<double>(10 + i));
  return r;
}

TEST(ConvergenceStudy, SpreadPerMethodOverTheGivenCountsAndDropouts) {
  std::vector<LoadedRun> runs = {
      method_run("cms-50", "cms", 50, 3.0),     method_run("cms-150", "cms", 150, 1.2),
      method_run("cms-750", "cms", 750, 1.5),   method_run("cms-3000", "cms", 3000, 1.0),
      method_run("bms-545", "bms", 545, 0.9),   method_run("bms-819", "bms", 819, 1.02),
      method_run("bms-1322", "bms", 1322, 1.0), method_run("hertz", "sphere", 1, 1.0)};
  // One dropout in cms-150: the force falls by 5 % and two contacts are lost at row 20.
  runs[1].plate->top_force[20] = 0.95 * runs[1].plate->top_force[19];
  runs[1].plate->contacts[20] = runs[1].plate->contacts[19] - 2;
  const auto study = convergence_study(runs, {{"cms", 150}});
  ASSERT_TRUE(study);
  ASSERT_EQ(study->methods.size(), 2u);  // bms, cms; the single sphere is no method ladder
  const MethodConvergence& bms = study->methods[0];
  const MethodConvergence& cms = study->methods[1];
  EXPECT_EQ(bms.method, "bms");
  EXPECT_EQ(cms.method, "cms");
  // Default: the two finest BMS runs (819, 1322): (1.02 − 1)/1.01 at every deformation.
  EXPECT_EQ(bms.spread_from, 819);
  EXPECT_EQ(bms.spread_to, 1322);
  EXPECT_EQ(bms.spread_runs, 2);
  for (double s : bms.spread)
    EXPECT_NEAR(s, 0.02 / 1.01, 1e-9);
  // CMS from 150: scales 1.2, 1.5, 1.0 → (1.5 − 1.0)/(3.7/3).
  EXPECT_EQ(cms.spread_from, 150);
  EXPECT_EQ(cms.spread_runs, 3);
  ASSERT_EQ(cms.spread.size(), 3u);
  EXPECT_NEAR(cms.spread[0], 0.5 / (3.7 / 3.0), 1e-9);
  // Ascending N; the change from the next coarser N: 50 → 150 is (3 − 1.2)/2.1.
  EXPECT_EQ(cms.runs[0].sub_spheres, 50);
  EXPECT_TRUE(std::isnan(cms.runs[0].change[0]));
  EXPECT_NEAR(cms.runs[1].change[1], 1.8 / 2.1, 1e-9);
  EXPECT_EQ(cms.runs[1].force_drops, 1);
  EXPECT_EQ(cms.runs[1].contact_drops, 1);
  EXPECT_EQ(cms.runs[0].force_drops, 0);
  EXPECT_TRUE(cms.runs[1].finite);
  const std::vector<Chart> charts = convergence_charts(*study, runs, 0.46);
  ASSERT_EQ(charts.size(), 4u);
  // (a) four CMS curves, the finest BMS, Hertz and Tatara.
  EXPECT_EQ(charts[0].series.size(), 4u + 1u + 2u);
  EXPECT_EQ(charts[1].series.size(), 4u);  // contacts of the CMS runs
  EXPECT_EQ(charts[2].series.size(), 6u);  // 3 deformations x 2 methods
  EXPECT_EQ(charts[3].series[1].x, (std::vector<double>{20, 30, 40}));
}

TEST(ConvergenceStudy, NeedsTwoCmsRunsAndRejectsASpreadItCannotTake) {
  const std::vector<LoadedRun> bms_only = {method_run("a", "bms", 100, 1.0),
                                           method_run("b", "bms", 250, 1.0)};
  EXPECT_FALSE(convergence_study(bms_only, {}));
  const std::vector<LoadedRun> runs = {method_run("a", "cms", 50, 1.0),
                                       method_run("b", "cms", 89, 1.0)};
  EXPECT_TRUE(convergence_study(runs, {}));
  EXPECT_THROW(convergence_study(runs, {{"cms", 150}}), InputError);  // one run or none above
  EXPECT_THROW(convergence_study(runs, {{"bms", 819}}), InputError);  // no BMS runs at all
  // A run short of 40 %: no force there, and the spread at 40 % is over the others.
  std::vector<LoadedRun> short_run = {method_run("a", "cms", 50, 1.0),
                                      method_run("b", "cms", 89, 1.1),
                                      method_run("c", "cms", 150, 1.2)};
  for (auto* column : {&short_run[2].plate->deformation, &short_run[2].plate->top_force,
                       &short_run[2].plate->contacts})
    column->resize(30);
  const auto study = convergence_study(short_run, {{"cms", 50}});
  ASSERT_TRUE(study);
  EXPECT_TRUE(std::isnan(study->methods[0].runs[2].force[2]));
  EXPECT_NEAR(study->methods[0].spread[2], 0.1 / 1.05, 1e-9);
}

TEST(PlateStudy, LeavesTheCmsRunsToTheConvergenceStudy) {
  const std::vector<LoadedRun> runs = {method_run("bms-100", "bms", 100, 1.1),
                                       method_run("bms-250", "bms", 250, 1.0),
                                       method_run("cms-3000", "cms", 3000, 2.0)};
  const auto study = plate_study(runs, std::nullopt);
  ASSERT_TRUE(study);
  EXPECT_EQ(study->finest, "bms-250");
  EXPECT_EQ(study->rows.size(), 2u);
}

}  // namespace
}  // namespace shapepress::analysis
