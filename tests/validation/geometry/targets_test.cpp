// Generated populations match their targets (issue 8 acceptance): 150 particles, fixed seed.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <string>

#include <fmt/format.h>

#include "geometry/descriptors.hpp"
#include "geometry/generate.hpp"

namespace shapepress::geometry {
namespace {

const std::string data = std::string(SHAPEPRESS_TEST_DATA) + "/geometry/";

// The criteria are for 150-particle populations (SHAPEPRESS_FULL_VALIDATION=1, a few
// minutes); CI runs 40, whose sampling error (mean of 40 ratios with a 5 % spread: ±0.007)
// still leaves the 0.02 criterion meaningful.
int population_size() {
  const char* full = std::getenv("SHAPEPRESS_FULL_VALIDATION");
  return full != nullptr && std::string(full) == "1" ? 150 : 40;
}

struct Means {
  double asr = 0, elongation = 0, flatness = 0;
  std::vector<double> projected;
};

Means measure(const std::vector<GeneratedParticle>& particles, int directions) {
  Means m;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    // Viewing directions independent of the ones the calibration used.
    const ShapeDescriptors d = describe(particles[i].mesh, {directions, 1000 + i});
    m.asr += d.asr / particles.size();
    m.elongation += d.elongation / particles.size();
    m.flatness += d.flatness / particles.size();
    m.projected.insert(m.projected.end(), d.projected_asr.begin(), d.projected_asr.end());
  }
  return m;
}

TEST(Targets, ProjectedAsrOfAvicelLikePopulationMatchesTheImageDistribution) {
  const ShapeTargets targets = read_shape_targets(data + "avicel_ph200_projected.toml");
  GenerateOptions options;
  options.count = population_size();
  options.seed = 42;
  const auto particles = generate_population(targets, options);
  const Means m = measure(particles, 8);
  const double ks = ks_distance(m.projected, targets);
  std::printf("avicel projected: KS = %.4f, mean projected ASR = %.4f, 3D ASR %.3f e %.3f f %.3f\n",
              ks, std::accumulate(m.projected.begin(), m.projected.end(), 0.0) / m.projected.size(),
              m.asr, m.elongation, m.flatness);
  EXPECT_LT(ks, 0.1);  // the criterion
}

void expect_box_means(const ShapeTargets& targets, const char* label) {
  GenerateOptions options;
  options.count = population_size();
  options.seed = 7;
  const Means m = measure(generate_population(targets, options), 4);
  std::printf("%s: ASR %.4f (target %.4f) elongation %.4f (%.4f) flatness %.4f (%.4f)\n", label,
              m.asr, targets.target_elongation() * targets.target_flatness(), m.elongation,
              targets.target_elongation(), m.flatness, targets.target_flatness());
  // The criterion: population means within 0.02 of the targets.
  EXPECT_NEAR(m.asr, targets.target_elongation() * targets.target_flatness(), 0.02);
  EXPECT_NEAR(m.elongation, targets.target_elongation(), 0.02);
  EXPECT_NEAR(m.flatness, targets.target_flatness(), 0.02);
}

TEST(Targets, BoxRatiosOfThePapersParticles) {
  expect_box_means(read_shape_targets(data + "paper_box_targets.toml"), "paper 0.8/0.84/0.95");
}

TEST(Targets, BoxRatiosOfTheThreeAvicelShapes) {
  ShapeTargets targets = read_shape_targets(data + "paper_box_targets.toml");
  targets.elongation.reset();
  targets.flatness.reset();
  for (double asr : {0.84, 0.71, 0.53}) {  // Giannis et al. 2023, Figure 7
    targets.asr_mean = asr;
    expect_box_means(targets, fmt::format("avicel ASR {}", asr).c_str());
  }
}

}  // namespace
}  // namespace shapepress::geometry
