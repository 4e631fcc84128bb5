#include "geometry/generate.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "common/error.hpp"
#include "geometry/descriptors.hpp"
#include "geometry/icosphere.hpp"
#include "geometry/mesh_checks.hpp"
#include "geometry/spherical_harmonics.hpp"
#include "tests/support/files.hpp"

namespace shapepress::geometry {
namespace {

const std::string data = std::string(SHAPEPRESS_TEST_DATA) + "/geometry/";

TEST(SphericalHarmonics, AreOrthonormalOnTheSphere) {
  // Equal-weight quadrature on a Fibonacci lattice (equal-area cells, weight 4π/N).
  const int N = 40000, L = 8, count = (L + 1) * (L + 1);
  std::vector<Vec3> points;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < N; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / N, s = std::sqrt(1.0 - z * z);
    points.emplace_back(s * std::cos(golden * i), s * std::sin(golden * i), z);
  }
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(count, count);
  for (const Vec3& v : points) {
    const auto Y = real_spherical_harmonics(v, L);
    const Eigen::Map<const Eigen::VectorXd> y(Y.data(), count);
    gram += y * y.transpose();
  }
  gram *= 4.0 * std::numbers::pi / N;
  // 40000 Fibonacci points integrate products of degree <= 16 to well below 1 %.
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(count, count)).cwiseAbs().maxCoeff(), 5e-3);
}

TEST(Generate, SpectrumFollowsTheDescriptors) {
  ShapeTargets t;
  t.D3 = 0.04;
  t.D8 = 0.01;
  t.decay_exponent = 2.0;
  const auto D = roughness_spectrum(t, 16);
  EXPECT_EQ(D[2], 0.0);  // elongation comes from the stretch
  EXPECT_DOUBLE_EQ(D[3], 0.04);
  EXPECT_NEAR(D[8], 0.01, 1e-15);
  EXPECT_NEAR(D[16], 0.01 * 0.25, 1e-15);  // (16/8)^-2
}

TEST(Generate, RoughSphereHasTheRequestedRoughnessAndIsValid) {
  ShapeTargets t;
  t.D3 = 0.03;
  t.D8 = 0.008;
  const TriangleMesh m = rough_sphere(roughness_spectrum(t, 15), 11);
  EXPECT_TRUE(check_mesh(m).valid());
  double sum_sq = 0.0;
  for (const Vec3& v : m.vertices)
    sum_sq += (v.norm() - 1.0) * (v.norm() - 1.0);
  const double rms = std::sqrt(sum_sq / m.vertices.size());
  // Expected rms of the field: sqrt(Σ D_l²/2) = 0.045 for this spectrum; one draw of 250
  // Gaussian coefficients is within ±40 % of it.
  double expected = 0.0;
  for (double d : roughness_spectrum(t, 15))
    expected += d * d / 2.0;
  expected = std::sqrt(expected);
  EXPECT_NEAR(rms / expected, 1.0, 0.4);
}

TEST(Generate, StretchReachesTheBoxRatios) {
  TriangleMesh m = ellipsoid_mesh(Vec3(1.0, 0.95, 0.9), 3);
  stretch_to_box_ratios(m, 0.7, 0.8);
  const OrientedBox box = minimum_oriented_box(m.vertices);
  EXPECT_NEAR(box.lengths[1] / box.lengths[0], 0.7, 2e-3);  // the function's tolerance
  EXPECT_NEAR(box.lengths[2] / box.lengths[1], 0.8, 2e-3);
}

std::string bytes_of(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Generate, SameSeedGivesByteIdenticalMeshes) {
  const ShapeTargets targets = read_shape_targets(data + "paper_box_targets.toml");
  GenerateOptions options;
  options.count = 3;
  options.seed = 5;
  const auto a = generate_population(targets, options);
  const auto b = generate_population(targets, options);
  const auto dir = testing::fresh_directory("generate_meshes");
  for (std::size_t i = 0; i < a.size(); ++i) {
    write_mesh(a[i].mesh, dir / "shapepress_gen_a.stl");
    write_mesh(b[i].mesh, dir / "shapepress_gen_b.stl");
    EXPECT_EQ(bytes_of(dir / "shapepress_gen_a.stl"), bytes_of(dir / "shapepress_gen_b.stl"));
  }
  options.seed = 6;
  const auto c = generate_population(targets, options);
  EXPECT_NE(c[0].mesh.vertices[0], a[0].mesh.vertices[0]);
  // Sizes: sqrt(A/π) is the drawn equivalent-circle diameter.
  for (const auto& p : a)
    EXPECT_NEAR(std::sqrt(surface_area(p.mesh) / std::numbers::pi) / p.size_m, 1.0, 1e-9);
}

TEST(ShapeTargets, ReadsTheImagingSummaryJson) {
  const auto path = testing::fresh_directory("targets") / "shapepress_summary.json";
  std::ofstream(path) << R"({"format": "shapepress shape-stats summary 1",
    "size": {"x10_m": 5e-5, "x50_m": 1e-4, "x90_m": 2e-4},
    "asr": {"mean": 0.7, "quantile_levels": [0.1, 0.5, 0.9], "quantiles": [0.5, 0.7, 0.85]},
    "fourier": {"D2": 0.1, "D3": 0.03, "D8": 0.01, "decay_exponent": 1.5}})";
  const ShapeTargets t = read_shape_targets(path);
  EXPECT_TRUE(t.projected_distribution());
  EXPECT_DOUBLE_EQ(t.asr_quantile(0.5), 0.7);
  EXPECT_DOUBLE_EQ(t.asr_cdf(0.7), 0.5);
  EXPECT_NEAR(t.size_quantile(0.5), 1e-4, 1e-16);  // exp(log x) round trip
  EXPECT_NEAR(t.size_quantile(0.9), 2e-4, 1e-18);
  EXPECT_DOUBLE_EQ(t.decay_exponent, 1.5);
  std::ofstream(path) << R"({"size": {"x10_m": 5e-5, "x50_m": 1e-4, "x90_m": 2e-4},
    "fourier": {"D3": 0.03}})";
  try {
    read_shape_targets(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fourier.D8"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(ShapeTargets, TomlUnknownKeysAreErrors) {
  const auto path = testing::fresh_directory("targets") / "shapepress_targets.toml";
  std::ofstream(path) << "[fourier]\nD3 = 0.03\nD8 = 0.01\n[asr]\nmean = 0.8\nelongaton = 0.8\n"
                         "[size]\nx10_m = 5e-5\nx50_m = 1e-4\nx90_m = 2e-4\n";
  EXPECT_THROW(read_shape_targets(path), InputError);
  std::filesystem::remove(path);
}

TEST(ShapeTargets, EffectiveTomlReadsBackToTheSameTargets) {
  const auto path = testing::fresh_directory("targets") / "shapepress_targets_effective.toml";
  for (const std::string& text :
       {std::string("[fourier]\nD2 = 0.07\nD3 = 0.03\nD8 = 0.01\ndecay_exponent = 2.5\n[asr]\n"
                    "quantiles = [0.5, 0.7, 0.9]\nquantile_levels = [0.1, 0.5, 0.9]\n"
                    "[size]\nx10_m = 5e-5\nx50_m = 1e-4\nx90_m = 2e-4\n"),
        bytes_of(data + "paper_box_targets.toml")}) {
    std::ofstream(path) << text;
    const ShapeTargets a = read_shape_targets(path);
    std::ofstream(path) << shape_targets_toml(a);
    const ShapeTargets b = read_shape_targets(path);
    EXPECT_EQ(b.D2, a.D2);
    EXPECT_EQ(b.D3, a.D3);
    EXPECT_EQ(b.D8, a.D8);
    EXPECT_EQ(b.decay_exponent, a.decay_exponent);
    EXPECT_EQ(b.asr_quantiles, a.asr_quantiles);
    EXPECT_EQ(b.asr_levels, a.asr_levels);
    EXPECT_EQ(b.asr_mean, a.asr_mean);
    EXPECT_EQ(b.elongation, a.elongation);
    EXPECT_EQ(b.flatness, a.flatness);
    EXPECT_EQ(b.x10_m, a.x10_m);
    EXPECT_EQ(b.x50_m, a.x50_m);
    EXPECT_EQ(b.x90_m, a.x90_m);
  }
  // Levels are the quantiles' levels: given alone they would be ignored, so they are refused.
  std::ofstream(path) << "[fourier]\nD3 = 0.03\nD8 = 0.01\n[asr]\nmean = 0.8\n"
                         "quantile_levels = [0.1, 0.9]\n[size]\nx10_m = 5e-5\nx50_m = 1e-4\n"
                         "x90_m = 2e-4\n";
  EXPECT_THROW(read_shape_targets(path), InputError);
  std::filesystem::remove(path);
}

// A mixture whose upper half is round (projected ASR 0.99, discs in the images) beside elongated
// particles: the rough spheres of the measured spectrum show Feret ratios near 0.95 only, so the
// fit must make the round ones smoother, and the others rougher to keep the mean amplitude.
TEST(Generate, RoundMassOfAMixtureIsMadeOfSmootherParticles) {
  ShapeTargets t;
  t.D3 = 0.03;
  t.D8 = 0.008;
  t.x10_m = t.x50_m = t.x90_m = 1e-4;
  t.asr_levels = {0.05, 0.25, 0.45, 0.55, 0.75, 0.95};
  t.asr_quantiles = {0.55, 0.68, 0.78, 0.985, 0.99, 0.995};
  GenerateOptions options;
  options.count = 16;
  options.seed = 3;
  options.subdivisions = 3;
  const auto particles = generate_population(t, options);
  std::vector<double> projected;
  int smoother = 0;
  double mean_roughness = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const ShapeDescriptors d = describe(particles[i].mesh, {32, 100 + i});
    projected.insert(projected.end(), d.projected_asr.begin(), d.projected_asr.end());
    smoother += particles[i].roughness < 0.5 ? 1 : 0;
    mean_roughness += particles[i].roughness / particles.size();
    EXPECT_GE(particles[i].elongation_target, 0.3);  // no needles
  }
  EXPECT_GE(smoother, 4);
  EXPECT_NEAR(mean_roughness, 1.0, 0.1);
  std::sort(projected.begin(), projected.end());
  EXPECT_GT(projected[projected.size() * 3 / 4], 0.98);  // the round mass is there
  EXPECT_LT(ks_distance(projected, t), 0.15);            // 16 particles, 32 views each
}

TEST(ShapeTargets, KsDistanceOfTheTargetItselfIsSmall) {
  ShapeTargets t;
  t.asr_levels = {0.0, 1.0};
  t.asr_quantiles = {0.4, 0.9};  // uniform on [0.4, 0.9]
  std::vector<double> sample;
  for (int i = 0; i < 1000; ++i)
    sample.push_back(0.4 + 0.5 * (i + 0.5) / 1000.0);
  EXPECT_LT(ks_distance(sample, t), 1e-3);
  std::vector<double> shifted = sample;
  for (double& a : shifted)
    a = std::min(1.0, a + 0.1);
  EXPECT_NEAR(ks_distance(shifted, t), 0.2, 1e-3);  // a shift of 0.1 on a width of 0.5
}

}  // namespace
}  // namespace shapepress::geometry
