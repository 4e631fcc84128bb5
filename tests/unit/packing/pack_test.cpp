// The pack stage's pieces without the dynamics: sizes and orientations drawn from their targets
// within sampling error, scaled templates keeping mass and inertia, bonds within bodies, the
// packed.h5 round trip, the BMS template check, the measures.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "common/error.hpp"
#include "packing/body_packing.hpp"
#include "packing/clump_packing.hpp"
#include "packing/pack.hpp"
#include "tests/support/files.hpp"

namespace shapepress::packing {
namespace {

// Four touching spheres of unequal radii, not symmetric, bonded in a chain: its mass properties
// as a BMS template's (Σ sub-spheres with the parallel-axis terms) in its principal frame.
BodyTemplate bms_chain() {
  BodyTemplate t;
  t.name = "bms/chain";
  t.source = "test";
  t.kind = BodyKind::bms;
  const std::vector<double> r = {1.0, 0.8, 0.6, 0.7};
  std::vector<Eigen::Vector3d> c = {{0, 0, 0}, {1.8, 0, 0}, {1.8 + 1.4 * 0.6, 1.4 * 0.8, 0}, {}};
  c[3] = c[2] + 1.3 * Eigen::Vector3d(0.0, 0.6, 0.8);
  double volume = 0.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double v = 4.0 / 3.0 * std::numbers::pi * std::pow(r[i], 3);
    volume += v, centre += v * c[i];
  }
  centre /= volume;
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double v = 4.0 / 3.0 * std::numbers::pi * std::pow(r[i], 3);
    const Eigen::Vector3d d = c[i] - centre;
    inertia += 0.4 * v * r[i] * r[i] * Eigen::Matrix3d::Identity() +
               v * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(inertia);
  const Eigen::Matrix3d axes = eigen.eigenvectors();
  for (std::size_t i = 0; i < r.size(); ++i) {
    const Eigen::Vector3d body = axes.transpose() * (c[i] - centre);
    t.centres.push_back({body.x(), body.y(), body.z()});
    t.radii.push_back(r[i] * 1e-5);
    for (auto& x : t.centres.back())
      x *= 1e-5;
  }
  t.bonds = {{0, 1}, {1, 2}, {2, 3}};
  t.sphere_volume = volume * 1e-15;
  t.shape_volume = 1.3 * t.sphere_volume;  // a shape a little larger than its sub-spheres
  for (int k = 0; k < 3; ++k)
    t.principal_inertia[k] = eigen.eigenvalues()[k] * 1e-25;
  set_body_volume(t);
  return t;
}

BodyTemplate sphere_template() {
  BodyTemplate t;
  t.name = "sphere";
  t.centres = {{0.0, 0.0, 0.0}};
  t.radii = {0.5};
  t.shape_volume = t.sphere_volume = std::numbers::pi / 6.0;
  set_body_volume(t);
  return t;
}

// Table 2 of Giannis et al. 2023 (Avicel PH 200, Q3): x10 = 82.9, x50 = 224.6, x90 = 379.3 um.
PackRequest avicel_request(std::int64_t count) {
  PackRequest r;
  r.templates = {{"sphere", 1.0}, {"bms/chain", 1.0}};
  r.count = count;
  r.sizes.diameters = {82.9e-6, 224.6e-6, 379.3e-6};
  r.sizes.levels = {0.1, 0.5, 0.9};
  r.sizes.volume_weighted = true;
  r.diameter_min = 180e-6;
  r.diameter_max = 500e-6;
  return r;
}

// The fraction of the sample's weight below x, and the effective sample size of the weights.
std::pair<double, double> weight_below(const std::vector<double>& d, double x, bool volume) {
  double below = 0.0, total = 0.0, squares = 0.0;
  for (double v : d) {
    const double w = volume ? v * v * v : 1.0;
    total += w, squares += w * w;
    if (v < x) below += w;
  }
  return {below / total, total * total / squares};
}

TEST(Pack, SizesOf500BodiesMatchTheirTargetsWithinSamplingError) {
  const std::vector<BodyTemplate> templates = {sphere_template(), bms_chain()};
  for (const bool volume : {true, false}) {
    PackRequest r = avicel_request(500);
    r.sizes.volume_weighted = volume;
    const std::vector<PackedBody> bodies = draw_bodies(r, templates);
    ASSERT_EQ(bodies.size(), 500u);
    std::vector<double> d;
    for (const PackedBody& b : bodies) {
      d.push_back(std::cbrt(6.0 * b.shape_volume / std::numbers::pi));
      EXPECT_GE(d.back(), r.diameter_min * (1 - 1e-12));
      EXPECT_LE(d.back(), r.diameter_max * (1 + 1e-12));
    }
    const SizeTable table = size_table(r.sizes, r.diameter_min, r.diameter_max);
    for (const double level : {0.1, 0.5, 0.9}) {
      const double x = size_quantile(table, level, volume);
      const auto [fraction, n] = weight_below(d, x, volume);
      // The weighted empirical CDF at the true quantile: standard error √(p (1 - p) / n_eff).
      EXPECT_NEAR(fraction, level, 4.0 * std::sqrt(level * (1 - level) / n))
          << "level " << level << (volume ? " (Q3)" : " (Q0)");
    }
  }
}

TEST(Pack, TruncationMovesTheTargetQuantilesAndACutoffOfNothingIsRefused) {
  PackRequest r = avicel_request(10);
  const SizeTable table = size_table(r.sizes, r.diameter_min, r.diameter_max);
  EXPECT_GT(size_quantile(table, 0.1, true), r.diameter_min);  // not Table 2's 82.9 um any more
  EXPECT_LT(size_quantile(table, 0.9, true), r.diameter_max);
  r.diameter_min = 5e-3, r.diameter_max = 6e-3;  // 14 x90 away: no particle that size
  try {
    draw_bodies(r, {sphere_template(), bms_chain()});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("size cutoff"), std::string::npos) << e.what();
  }
}

TEST(Pack, OrientationsAreIsotropicWithinSamplingError) {
  const std::vector<BodyTemplate> templates = {sphere_template(), bms_chain()};
  const std::vector<PackedBody> bodies = draw_bodies(avicel_request(500), templates);
  const double n = static_cast<double>(bodies.size());
  for (int k = 0; k < 3; ++k) {
    double mean_c = 0.0, p2 = 0.0;
    for (const PackedBody& b : bodies) {
      Vector3 axis = {0.0, 0.0, 0.0};
      axis[k] = 1.0;
      const Vector3 w = rotate_to_world(b.orientation, axis);
      mean_c += w[2] / n;
      p2 += 0.5 * (3 * w[2] * w[2] - 1) / n;
    }
    // Uniform on the sphere: cos θ uniform on [-1, 1] (sd 1/√3), P2 of mean 0 and sd 1/√5.
    EXPECT_NEAR(mean_c, 0.0, 4.0 / std::sqrt(3.0 * n)) << "axis " << k;
    EXPECT_NEAR(p2, 0.0, 4.0 / std::sqrt(5.0 * n)) << "axis " << k;
  }
}

TEST(Pack, VolumeWeightingSharesTheVolumeByTheWeights) {
  const std::vector<BodyTemplate> templates = {sphere_template(), bms_chain()};
  PackRequest r = avicel_request(300);
  r.templates = {{"sphere", 1.0}, {"bms/chain", 3.0}};
  r.weighting = TemplateWeighting::volume;
  double v[2] = {0.0, 0.0};
  for (const PackedBody& b : draw_bodies(r, templates))
    v[b.template_index] += b.shape_volume;
  // Each body goes where the share lags most: off by at most one body's volume.
  const double largest = std::numbers::pi / 6.0 * std::pow(r.diameter_max, 3);
  EXPECT_NEAR(v[1] / (v[0] + v[1]), 0.75, largest / (v[0] + v[1]));
}

TEST(Pack, AScaledTemplateKeepsItsMassAndInertiaTimesS3AndS5) {
  const BodyTemplate t = bms_chain();
  PackedBody body;
  body.scale = 7.5;
  std::mt19937_64 random(3);
  body.orientation = random_rotation(random);
  body.centre = {1e-3, 2e-3, 3e-3};
  std::vector<Vector3> centres;
  std::vector<double> radii;
  place_body(t, body, centres, radii);
  // Volume and inertia tensor of the placed sub-spheres about their centre of mass.
  double volume = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < radii.size(); ++i) {
    const double v = 4.0 / 3.0 * std::numbers::pi * std::pow(radii[i], 3);
    volume += v, com += v * Eigen::Vector3d(centres[i][0], centres[i][1], centres[i][2]);
  }
  com /= volume;
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < radii.size(); ++i) {
    const double v = 4.0 / 3.0 * std::numbers::pi * std::pow(radii[i], 3);
    const Eigen::Vector3d d = Eigen::Vector3d(centres[i][0], centres[i][1], centres[i][2]) - com;
    inertia += 0.4 * v * radii[i] * radii[i] * Eigen::Matrix3d::Identity() +
               v * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  const double s = body.scale;
  EXPECT_NEAR(volume, t.sphere_volume * s * s * s, 1e-12 * volume);
  EXPECT_NEAR((com - Eigen::Vector3d(1e-3, 2e-3, 3e-3)).norm(), 0.0, 1e-12);
  // In the body frame the tensor is diagonal with the template's moments × s⁵.
  for (int k = 0; k < 3; ++k) {
    Vector3 e = {0.0, 0.0, 0.0};
    e[k] = 1.0;
    const Vector3 w = rotate_to_world(body.orientation, e);
    const Eigen::Vector3d a(w[0], w[1], w[2]);
    EXPECT_NEAR(a.dot(inertia * a), t.principal_inertia[k] * std::pow(s, 5),
                1e-9 * t.principal_inertia[k] * std::pow(s, 5));
  }
}

BodyPacking two_body_packing() {
  BodyPacking p;
  p.templates = {sphere_template(), bms_chain()};
  p.box = Box{1e-3, 1e-3};
  PackedBody a;
  a.template_index = 1;
  a.scale = 2.0;
  a.centre = {2e-4, 2e-4, 1e-4};
  a.shape_volume = p.templates[1].shape_volume * 8;
  a.sphere_volume = p.templates[1].sphere_volume * 8;
  PackedBody b = a;
  b.centre = {6e-4, 6e-4, 1e-4};
  std::mt19937_64 random(9);
  b.orientation = random_rotation(random);
  PackedBody c;
  c.template_index = 0;
  c.scale = 5e-5;
  c.centre = {5e-4, 1e-4, 4e-4};
  c.shape_volume = c.sphere_volume = std::numbers::pi / 6 * std::pow(5e-5, 3);
  p.bodies = {a, b, c};
  p.top = 6e-4;
  place_bodies(p);
  return p;
}

TEST(Pack, NoBondJoinsTwoBodiesAndBondsRestAtTheirPlacedLength) {
  const BodyPacking p = two_body_packing();
  ASSERT_EQ(p.bonds.size(), 6u);
  for (std::size_t k = 0; k < p.bonds.size(); ++k) {
    const auto [i, j] = p.bonds[k];
    EXPECT_EQ(p.particle_body[i], p.particle_body[j]);
    const double d =
        std::hypot(p.particles.x[i] - p.particles.x[j], p.particles.y[i] - p.particles.y[j],
                   p.particles.z[i] - p.particles.z[j]);
    EXPECT_DOUBLE_EQ(p.bond_rest_length[k], d);
  }
}

TEST(Pack, PackedFileRoundTripsAndABondAcrossBodiesIsRefused) {
  const std::filesystem::path dir = shapepress::testing::fresh_directory("pack_unit_roundtrip");
  BodyPacking p = two_body_packing();
  p.measures.solid_fraction_shape = 0.55;
  p.measures.orientation_order = -0.1;
  write_packing(dir / "packed.h5", p, Provenance{"test", "", 7});
  EXPECT_TRUE(std::filesystem::exists(dir / "packed.xmf"));
  const BodyPacking q = read_packing(dir / "packed.h5");
  ASSERT_EQ(q.size(), p.size());
  EXPECT_EQ(q.particles.x, p.particles.x);
  EXPECT_EQ(q.particles.radius, p.particles.radius);
  EXPECT_EQ(q.particle_body, p.particle_body);
  EXPECT_EQ(q.bonds, p.bonds);
  EXPECT_EQ(q.bond_rest_length, p.bond_rest_length);
  EXPECT_EQ(q.templates[1].centres, p.templates[1].centres);
  EXPECT_EQ(q.bodies[1].orientation.x, p.bodies[1].orientation.x);
  EXPECT_EQ(q.measures.solid_fraction_shape, 0.55);
  EXPECT_EQ(q.measures.orientation_order, -0.1);
  p.bonds[0] = {0, 4};  // particle 4 is body 1's
  write_packing(dir / "bad.h5", p, Provenance{"test", "", 7});
  EXPECT_THROW(read_packing(dir / "bad.h5"), InputError);
}

TEST(Pack, ABmsTemplateWhoseSubSpheresOverlapIsRefused) {
  BodyTemplate t = bms_chain();
  EXPECT_NO_THROW(check_bms_template(t));  // touching
  t.centres[1][0] -= 0.2 * t.radii[1];
  EXPECT_THROW(check_bms_template(t), InputError);
}

TEST(Pack, MeasuresCountContactsOverlapsAndSolidFraction) {
  BodyPacking p;
  p.templates = {sphere_template()};
  p.box = Box{1e-3, 1e-3};
  const double r = 1e-4;
  for (const double x : {1e-4, 2.9e-4, 9.5e-4}) {  // 0-1 overlap 0.1 r; 2 with 0 across x = 0
    PackedBody b;
    b.scale = 2 * r;
    b.centre = {x, 5e-4, r};
    b.shape_volume = b.sphere_volume = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    p.bodies.push_back(b);
  }
  place_bodies(p);
  SizeQuantiles q{{1e-4, 2e-4}, {0.1, 0.9}, true};
  const PackMeasures m = measure_packing(p, size_table(q, 1.5e-4, 2.5e-4), true);
  EXPECT_NEAR(m.bed_height, 2 * r, 1e-15);
  EXPECT_NEAR(m.largest_overlap, 0.5 * r, 1e-12);  // bodies 2 and 0 across x = 0
  EXPECT_NEAR(m.coordination, 2.0 * 2 / 3, 1e-12);
  EXPECT_NEAR(m.solid_fraction_shape, 3 * p.bodies[0].shape_volume / (1e-6 * 2 * r), 1e-12);
  EXPECT_NEAR(m.x50, 2 * r, 1e-12);
}

// compact's pour settles in pack's phase loop for exactly ceil(settle_time / step) steps (the
// config's settle time is part of the bed's recipe, not a rest test), then leaves the bed at
// rest; a stop asked for after a step ends the settle there with no bed.
TEST(TimedSettle, TakesTheSettleTimeInWholeStepsAndLeavesTheBedAtRest) {
  SphereList one;
  one.x = {0.5e-3}, one.y = {0.5e-3}, one.z = {2e-3}, one.radius = {0.1e-3};
  const SphereState state = make_state(one, 1500.0, 0);
  Material powder;
  powder.name = "powder", powder.youngs_modulus = 1e8, powder.poisson_ratio = 0.3;
  powder.density = 1500.0;
  Interaction self;
  self.first = self.second = "powder";
  TimedSettle request;
  request.box = Box{1e-3, 1e-3};
  request.walls = {PlaneWall{0.0, 1, 0.0, 0}};
  request.settings.time_step = 1e-5;
  request.settings.skin = 1e-5;
  request.settle_time = 10.5e-5;  // 10.5 steps: 11 whole ones
  int steps = 0;
  ClumpSet clumps;
  const std::optional<SphereState> settled =
      settle_for_time(state, clumps, {powder}, {self}, request,
                      {[&](const Engine&) { return ++steps > 0; }, std::nullopt});
  ASSERT_TRUE(settled);
  EXPECT_EQ(steps, 11);
  // It fell (gravity unset is 9.81 m/s² down) and is left with no velocity.
  EXPECT_LT(settled->position.z[0], 2e-3);
  EXPECT_EQ(settled->velocity.z[0], 0.0);
  int taken = 0;
  ClumpSet none;
  EXPECT_FALSE(settle_for_time(state, none, {powder}, {self}, request,
                               {[&](const Engine&) { return ++taken < 4; }, std::nullopt}));
  EXPECT_EQ(taken, 4);
}

}  // namespace
}  // namespace shapepress::packing
