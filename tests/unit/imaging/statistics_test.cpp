// Distributions: quantiles, Q3 weighting, correlation, and the Fourier fit on spectra with
// known parameters.
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.hpp"
#include "imaging/statistics.hpp"

namespace shapepress::imaging {
namespace {

TEST(Statistics, WeightedQuantileInterpolatesBetweenClassMidpoints) {
  // Values 1..4 with equal weights: mid-points at 1/8, 3/8, 5/8, 7/8.
  std::vector<double> v = {4, 1, 3, 2}, w(4, 1.0);
  EXPECT_DOUBLE_EQ(weighted_quantile(v, w, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(weighted_quantile(v, w, 0.125), 1.0);
  EXPECT_DOUBLE_EQ(weighted_quantile(v, w, 0.05), 1.0);
  EXPECT_DOUBLE_EQ(weighted_quantile(v, w, 0.99), 4.0);
}

ParticleSample sample(double d_m, double asr) {
  ParticleSample s;
  s.equivalent_diameter_m = d_m;
  s.equivalent_diameter_px = d_m / 1e-6;
  s.aspect_ratio = asr;
  s.fourier_mean_radius_px = s.equivalent_diameter_px / 2;
  return s;
}

TEST(Statistics, VolumeWeightingFavoursLargeParticles) {
  // 9 particles of 10 µm and 1 of 20 µm: by number x50 = 10 µm; by volume the large one
  // holds 8/17 of the volume, so x90 (Q3) is 20 µm.
  std::vector<ParticleSample> p(9, sample(10e-6, 0.8));
  p.push_back(sample(20e-6, 0.5));
  ShapeSummary s = summarize(p);
  EXPECT_DOUBLE_EQ(s.size.number.x50, 10e-6);
  EXPECT_DOUBLE_EQ(s.size.volume.x90, 20e-6);
  EXPECT_DOUBLE_EQ(s.size.volume.x10, 10e-6);
  EXPECT_NEAR(s.size.volume.mean,
              (9 * 1e-15 + 8e-15) / 17e-15 * 0 + (9 * 1e-20 + 20e-6 * 8e-15) / 17e-15,
              1e-18);  // Σ d·d³ / Σ d³
  EXPECT_NEAR(s.size.Q3.back(), 1.0, 1e-12);
  EXPECT_NEAR(s.size.Q0.front(), 0.0, 1e-12);
  // Large particle is the elongated one: ASR falls with size.
  EXPECT_LT(s.asr.pearson_with_size, -0.9);
  EXPECT_DOUBLE_EQ(s.asr.s50, 0.8);
  EXPECT_NEAR(s.asr.mean, (9 * 0.8 + 0.5) / 10, 1e-12);
}

TEST(Statistics, FourierFitRecoversAKnownSpectrum) {
  // Spectrum of the Mollon & Zhao form: D2 = 0.15, log-linear from D3 = 0.06 to D8 = 0.01,
  // then D8 (n/8)^-2.
  FourierSpectrum d{};
  d[0] = 1;
  d[2] = 0.15;
  for (int n = 3; n <= 8; ++n)
    d[n] = 0.06 * std::pow(n / 3.0, std::log(0.01 / 0.06) / std::log(8.0 / 3.0));
  for (int n = 9; n <= fourier_max_order; ++n)
    d[n] = 0.01 * std::pow(n / 8.0, -2.0);
  std::vector<ParticleSample> p(5, sample(100e-6, 0.7));  // 100 px: resolves n up to 32
  for (auto& s : p)
    s.fourier = d;
  ShapeSummary s = summarize(p);
  EXPECT_EQ(s.fourier.particles_used, 5);
  EXPECT_NEAR(s.fourier.D2, 0.15, 1e-12);
  EXPECT_NEAR(s.fourier.D3, 0.06, 1e-9);
  EXPECT_NEAR(s.fourier.D8, 0.01, 1e-9);
  EXPECT_NEAR(s.fourier.decay_exponent, 2.0, 1e-9);
  EXPECT_EQ(s.fourier.last_order, 32);
}

TEST(Statistics, SmallParticlesAreLeftOutOfTheSpectrum) {
  std::vector<ParticleSample> p = {sample(100e-6, 0.7), sample(5e-6, 0.7)};
  p[0].fourier[2] = 0.1;
  p[1].fourier[2] = 0.9;  // a 5 px outline: pixel noise, not shape
  ShapeSummary s = summarize(p, 20.0);
  EXPECT_EQ(s.fourier.particles_used, 1);
  EXPECT_DOUBLE_EQ(s.fourier.D2, 0.1);
}

TEST(Statistics, NoParticleIsAnInputError) {
  EXPECT_THROW(summarize({}), InputError);
}

}  // namespace
}  // namespace shapepress::imaging
