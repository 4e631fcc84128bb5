// The projected aspect ratio of a body of sub-spheres (analysis/beds.hpp) against silhouettes
// worked out by hand: a sphere is round from every side; two touching spheres seen across their
// axis are twice as long as wide; averaged over random views they measure π/2 − 1.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "analysis/beds.hpp"
#include "analysis/report.hpp"
#include "common/run_metadata.hpp"
#include "tests/support/files.hpp"

namespace shapepress::analysis {
namespace {

SphereUnion dumbbell(double r) {
  return {{{-r, 0.0, 0.0}, {r, 0.0, 0.0}}, {r, r}};
}

TEST(Beds, ASphereIsRoundFromEverySide) {
  const SphereUnion sphere{{{1e-4, -2e-4, 3e-4}}, {1e-4}};
  for (const auto& d : viewing_directions(16))
    EXPECT_NEAR(projected_aspect_ratio(sphere, d), 1.0, 1e-9);
}

TEST(Beds, TwoTouchingSpheresAreHalfAsWideAsLongAcrossTheirAxisAndRoundAlongIt) {
  EXPECT_NEAR(projected_aspect_ratio(dumbbell(1e-4), {0.0, 0.0, 1.0}), 0.5, 1e-9);
  EXPECT_NEAR(projected_aspect_ratio(dumbbell(1e-4), {1.0, 0.0, 0.0}), 1.0, 1e-9);
  // At θ from the axis the two discs are 2r sin θ apart: Feret min 2r, max 2r (1 + sin θ).
  const double theta = 0.6;
  EXPECT_NEAR(projected_aspect_ratio(dumbbell(1e-4), {std::cos(theta), std::sin(theta), 0.0}),
              1.0 / (1.0 + std::sin(theta)), 1e-9);
}

// ∫ sin θ / (1 + sin θ) dθ over [0, π/2] = π/2 − 1: the mean over views uniform on the sphere.
TEST(Beds, TheMeanOverRandomViewsOfTwoTouchingSpheresIsHalfPiMinusOne) {
  const auto views = viewing_directions(4000, 3);
  EXPECT_NEAR(mean_projected_aspect_ratio(dumbbell(2e-4), views), std::numbers::pi / 2 - 1, 0.005);
}

TEST(Beds, ViewingDirectionsAreUnitVectorsSpreadOverTheSphere) {
  const auto views = viewing_directions(4000, 5);
  double mean_z = 0.0, mean_z2 = 0.0;
  for (const auto& d : views) {
    EXPECT_NEAR(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0, 1e-12);
    mean_z += d[2] / 4000.0, mean_z2 += d[2] * d[2] / 4000.0;
  }
  EXPECT_NEAR(mean_z, 0.0, 0.03);
  EXPECT_NEAR(mean_z2, 1.0 / 3.0, 0.02);  // <z²> of a uniform direction
  EXPECT_EQ(viewing_directions(8, 1), viewing_directions(8, 1));
}

// A bed of `bodies` bodies of one particle and its figures, as the report loads it.
LoadedRun bed_run(const std::string& label, std::int64_t bodies, double per_body, double peak) {
  LoadedRun run;
  run.label = label;
  run.bed = BedFacts{};
  run.bed->particle_kind = "bms";
  run.bed->bodies = bodies;
  run.bed->sub_spheres_per_body = per_body;
  run.compaction = CompactionMetrics{};
  run.compaction->peak_stress = peak;
  run.compaction->unloaded = true;
  run.compaction->elastic_recovery = 0.2;
  run.compaction->heckel.yield_pressure = 8e6;
  return run;
}

// Beds of one particle in several sizes are charted against their bodies; a particle in one
// size is not, and with no particle in two sizes there is no chart.
TEST(Beds, BedSizeChartsOnlyAParticleInSeveralSizes) {
  std::vector<LoadedRun> runs = {bed_run("40", 40, 80, 1e6), bed_run("150", 150, 80, 2e6),
                                 bed_run("150-seed2", 150, 80, 2.2e6),
                                 bed_run("350", 150, 350, 3e6)};
  const std::vector<Chart> charts = bed_size_charts(runs);
  ASSERT_EQ(charts.size(), 3u);
  const Chart& peak = charts[0];
  ASSERT_EQ(peak.series.size(), 3u);  // not the N = 350 bed, of one size
  EXPECT_EQ(peak.series[0].x, std::vector<double>{40.0});
  EXPECT_EQ(peak.series[2].y, std::vector<double>{2.2});
  runs.resize(1);
  runs.push_back(bed_run("350", 150, 350, 3e6));
  EXPECT_TRUE(bed_size_charts(runs).empty());
}

// A bed of rigid clumps counts its clumps as bodies, its sub-spheres per clump, whatever is
// known of its packing.
TEST(Beds, ABedOfClumpsCountsItsClumps) {
  const std::filesystem::path dir = shapepress::testing::fresh_directory("beds_clumps");
  RunMetadata meta("compact", "shapepress compact ...");
  meta.fact("particle_kind", "cms").fact("spheres", 890).fact("clumps", 10);
  meta.write(dir / run_metadata_name);
  PunchCurve curve;
  curve.solid_fraction = {0.6, 0.7};
  const BedFacts bed = bed_facts(dir / run_metadata_name, curve);
  EXPECT_EQ(bed.particle_kind, "cms");
  EXPECT_EQ(bed.bodies, 10);
  EXPECT_DOUBLE_EQ(bed.sub_spheres_per_body, 89.0);
}

}  // namespace
}  // namespace shapepress::analysis
