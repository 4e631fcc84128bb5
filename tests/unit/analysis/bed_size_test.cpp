#include "analysis/bed_size.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "tests/support/files.hpp"

namespace shapepress::analysis {
namespace {

// A synthetic ladder whose answer is known. Every figure of a bed of b bodies and N sub-spheres is
// its true value × (1 + 4/b) (a boundary layer that fades with size) × 0.85 at N = 40 (too coarse
// a body), and its three seeds sit at −d, 0 and +d of it (sample standard deviation d of the
// mean) with d = 0.2 √(50/b): the scatter of a packing halves as the bed grows four times. A run
// costs b^1.5 N (more bodies, and a deeper bed to press).
std::vector<BedRun> synthetic_ladder() {
  std::vector<BedRun> ladder;
  for (int bodies : {50, 100, 200, 400})
    for (int count : {40, 80}) {
      const double factor = (1.0 + 4.0 / bodies) * (count == 40 ? 0.85 : 1.0);
      const double d = 0.2 * std::sqrt(50.0 / bodies);
      int seed = 1;
      for (double offset : {-d, 0.0, d}) {
        BedRun run;
        run.label = fmt::format("b{}-n{}-s{}", bodies, count, seed);
        run.bodies = bodies;
        run.sub_spheres = count;
        run.seed = static_cast<std::uint64_t>(seed++);
        run.bed_height_diameters = 0.08 * bodies;
        run.peak_stress = 30e6 * factor * (1.0 + offset);
        run.elastic_recovery = 0.08 * factor * (1.0 + offset);
        run.yield_pressure = 70e6 * factor * (1.0 + offset);
        run.counted_cost = std::llround(std::pow(bodies, 1.5) * count);
        ladder.push_back(run);
      }
    }
  return ladder;
}

const BedSetting& setting(const BedSizeAdvice& advice, int bodies, int count) {
  for (const BedSetting& s : advice.settings)
    if (s.bodies == bodies && s.sub_spheres == count) return s;
  throw std::runtime_error("no such setting");
}

TEST(BedSize, PicksTheCheapestBedWithinTheToleranceAndTheSeedsItNeeds) {
  const BedSizeAdvice advice = advise_bed_size(synthetic_ladder(), 0.05);
  ASSERT_EQ(advice.settings.size(), 8u);
  const BedSetting& reference = advice.settings[advice.reference];
  EXPECT_EQ(reference.bodies, 400);
  EXPECT_EQ(reference.sub_spheres, 80);
  // Biases of (1 + 4/b)/(1 + 4/400) − 1 at N = 80: 6.9 %, 3.0 %, 1.0 %; every N = 40 is ≥ 9 % off.
  EXPECT_NEAR(setting(advice, 50, 80).bias, 1.08 / 1.01 - 1.0, 1e-12);
  EXPECT_NEAR(setting(advice, 100, 80).bias, 1.04 / 1.01 - 1.0, 1e-12);
  EXPECT_FALSE(setting(advice, 50, 80).holds);
  EXPECT_TRUE(setting(advice, 100, 80).holds);
  for (int bodies : {50, 100, 200, 400})
    EXPECT_FALSE(setting(advice, bodies, 40).holds) << bodies;
  // The scatter is d, and the seeds that bring its standard error under 5 %: (d/0.05)².
  EXPECT_NEAR(setting(advice, 100, 80).scatter, 0.2 * std::sqrt(0.5), 1e-12);
  EXPECT_EQ(setting(advice, 100, 80).seeds_needed, 8);
  EXPECT_EQ(setting(advice, 200, 80).seeds_needed, 4);
  EXPECT_EQ(setting(advice, 400, 80).seeds_needed, 2);
  // 100^1.5 × 80 × 8 = 640,000 against 200's 904,966 and 400's 1,280,000.
  ASSERT_TRUE(advice.pick);
  const BedSetting& pick = advice.settings[*advice.pick];
  EXPECT_EQ(pick.bodies, 100);
  EXPECT_EQ(pick.sub_spheres, 80);
  EXPECT_DOUBLE_EQ(pick.predicted_cost, 1000.0 * 80 * 8);
  // Three seeds do not resolve a 3 % bias under a 14 % scatter: said, not hidden.
  EXPECT_FALSE(pick.resolved);
  EXPECT_GT(pick.bias_standard_error, 0.05);
}

TEST(BedSize, ATighterToleranceNeedsALargerBedAndMoreSeeds) {
  const BedSizeAdvice advice = advise_bed_size(synthetic_ladder(), 0.02);
  EXPECT_FALSE(setting(advice, 100, 80).holds);  // 3.0 % off
  ASSERT_TRUE(advice.pick);
  const BedSetting& pick = advice.settings[*advice.pick];
  // 200 bodies: (0.1/0.02)² = 25 seeds at 226,274 each; 400: ⌈12.5⌉ = 13 at 640,000.
  EXPECT_EQ(pick.bodies, 200);
  EXPECT_EQ(pick.seeds_needed, 25);
  EXPECT_EQ(setting(advice, 400, 80).seeds_needed, 13);
}

TEST(BedSize, OneSeedLeavesTheScatterUnknownAndNothingIsResolvedButTheReference) {
  std::vector<BedRun> ladder;
  for (const BedRun& run : synthetic_ladder())
    if (run.seed == 2) ladder.push_back(run);
  const BedSizeAdvice advice = advise_bed_size(ladder, 0.05);
  for (const BedSetting& s : advice.settings) {
    EXPECT_TRUE(std::isnan(s.scatter));
    EXPECT_EQ(s.seeds_needed, 1);
    EXPECT_EQ(s.resolved, s.reference);
  }
  ASSERT_TRUE(advice.pick);
  EXPECT_EQ(advice.settings[*advice.pick].bodies, 100);
}

TEST(BedSize, ABadRunIsAnInputErrorNamingIt) {
  std::vector<BedRun> ladder = synthetic_ladder();
  ladder[3].peak_stress = 0.0;
  try {
    advise_bed_size(ladder, 0.05);
    FAIL() << "a zero peak was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(ladder[3].label), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("peak_stress"), std::string::npos) << e.what();
  }
  EXPECT_THROW(advise_bed_size({}, 0.05), InputError);
  // A bed that never yields has an infinite Py: judged on its other figures.
  ladder = synthetic_ladder();
  for (BedRun& run : ladder)
    run.yield_pressure = INFINITY;
  EXPECT_TRUE(advise_bed_size(ladder, 0.05).pick);
}

TEST(BedSize, TheTableAndChartsHoldEverySetting) {
  const BedSizeAdvice advice = advise_bed_size(synthetic_ladder(), 0.05);
  const std::filesystem::path dir = shapepress::testing::fresh_directory("bed_size_csv");
  write_bed_size_csv(dir / "bed_size.csv", advice);
  const CsvTable table = read_csv(dir / "bed_size.csv");
  ASSERT_EQ(table.rows.size(), 8u);
  const std::vector<double> picked = table.column("picked");
  EXPECT_EQ(std::count(picked.begin(), picked.end(), 1.0), 1);
  EXPECT_EQ(table.column("seeds_needed")[3], 8.0);  // 100 bodies at N = 80, the fourth row
  const Chart peak = bed_size_chart(advice, BedFigure::peak_stress);
  ASSERT_EQ(peak.series.size(), 2u);  // N = 40 and 80
  EXPECT_EQ(peak.series[1].x.size(), 4u);
  EXPECT_NEAR(peak.series[1].y_error[0], 30.0 * 1.08 * 0.2, 1e-9);  // MPa at 50 bodies
  const Chart cost = bed_speed_accuracy_chart(advice);
  ASSERT_EQ(cost.series.size(), 3u);  // bodies, sub-spheres, the tolerance
  EXPECT_EQ(cost.series[0].x.size(), 4u);
  EXPECT_EQ(cost.series[1].x.size(), 2u);
}

}  // namespace
}  // namespace shapepress::analysis
