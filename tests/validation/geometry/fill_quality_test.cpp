// Fill quality on an analytic sphere and ellipsoid and on an ellipsoid mesh (issue 8
// acceptance): the CMS union's volume error at 150 spheres, the BMS volume fraction, and the
// trend of every metric with the sphere count. The tables printed here are the ones charted in
// the stage's closing note.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "geometry/icosphere.hpp"
#include "geometry/mesh_distance.hpp"
#include "geometry/sphere_fill.hpp"
#include "geometry/template_quality.hpp"

namespace shapepress::geometry {
namespace {

// ASR 0.8, elongation 0.84, flatness 0.95: the paper's generated particles (§3.2).
const Vec3 paper_ellipsoid(1.0e-4, 0.84e-4, 0.8e-4);

void print(const std::string& label, int n, const FillQuality& q) {
  std::printf(
      "%-16s N=%5d Vfrac=%.4f Verr=%.4f rms/d=%.4f haus/d=%.4f inertia=%.4f extent=%.4f "
      "bonds=%d\n",
      label.c_str(), n, q.volume_fraction, q.volume_error, q.surface_rms_relative,
      q.hausdorff_relative, q.inertia_error, q.extent_error, q.bond_count);
}

std::vector<FillQuality> rigid_series(const SignedDistance& shape, const MassProperties& exact,
                                      const std::vector<int>& counts, bool match_volume,
                                      const std::string& label) {
  std::vector<FillQuality> series;
  for (int n : counts) {
    RigidFillOptions options;
    options.sphere_count = n;
    options.match_volume = match_volume;
    series.push_back(assess_fill(fill_rigid(shape, options), shape, exact));
    print(label, n, series.back());
  }
  return series;
}

std::vector<FillQuality> bonded_series(const SignedDistance& shape, const MassProperties& exact,
                                       const std::vector<int>& counts, const std::string& label) {
  std::vector<FillQuality> series;
  for (int n : counts) {
    BondedFillOptions options;
    options.target_count = n;
    series.push_back(assess_fill(fill_bonded(shape, options), shape, exact));
    print(label, n, series.back());
    EXPECT_EQ(series.back().sphere_count, n);
    EXPECT_TRUE(series.back().connected);
  }
  return series;
}

// Each metric may wobble by `slack` (relative) between neighbouring counts (lattice and greedy
// choices are discrete) but must fall overall by at least `overall`.
void expect_decreasing(const std::vector<FillQuality>& s, double FillQuality::*metric,
                       const char* name, double slack = 0.15, double overall = 0.7) {
  for (std::size_t i = 1; i < s.size(); ++i)
    EXPECT_LE(s[i].*metric, s[i - 1].*metric * (1.0 + slack)) << name << " at step " << i;
  EXPECT_LT(s.back().*metric, s.front().*metric * overall) << name;
}

TEST(FillQuality, RigidEllipsoidUnionVolumeWithin3PercentAt150AndImprovesWithCount) {
  const SignedDistance shape = ellipsoid_distance(paper_ellipsoid);
  const MassProperties exact = ellipsoid_mass_properties(paper_ellipsoid);
  // Up to 150 the medial-axis cover is still incomplete (it completes at about 130 balls on the
  // 64-cell grid) and every added ball refines it.
  const auto matched = rigid_series(shape, exact, {25, 50, 150}, true, "cms ellipsoid");
  EXPECT_LT(matched[2].volume_error, 0.03);  // the acceptance: < 3 % at 150 spheres
  expect_decreasing(matched, &FillQuality::surface_rms_relative, "rms");
  expect_decreasing(matched, &FillQuality::hausdorff_relative, "hausdorff");
  expect_decreasing(matched, &FillQuality::inertia_error, "inertia");
  expect_decreasing(matched, &FillQuality::extent_error, "extent");
  // Past that count the cap takes over (400 balls, smaller ones at the surface): the grid
  // resolves nothing finer, so the template stays as good as at 150, within a grid cell's worth
  // (cell / d_eq = 0.018 for distances; 1 % for volume and inertia).
  const FillQuality more = rigid_series(shape, exact, {400}, true, "cms ellipsoid").front();
  EXPECT_EQ(more.sphere_count, 400);
  EXPECT_LT(more.volume_error, 0.03);
  EXPECT_LT(more.surface_rms_relative, matched[2].surface_rms_relative + 0.018);
  EXPECT_LT(more.hausdorff_relative, matched[2].hausdorff_relative + 0.018);
  EXPECT_LT(more.inertia_error, matched[2].inertia_error + 0.01);
  EXPECT_LT(more.extent_error, matched[2].extent_error + 0.018);
  // Without the common radius growth the inscribed balls' deficit is the volume error, and it
  // shrinks as the count grows to the complete cover.
  const auto inscribed = rigid_series(shape, exact, {25, 50, 150, 400}, false, "cms inscribed");
  expect_decreasing({inscribed.begin(), inscribed.begin() + 3}, &FillQuality::volume_error,
                    "volume error (inscribed)", 0.0);
  EXPECT_LT(inscribed[3].volume_error, inscribed[2].volume_error + 0.01);
  for (const FillQuality& q : inscribed)
    EXPECT_LT(q.volume_fraction, 1.0);
}

// The paper's Fig. 3 representations of a sphere (issue 6): one ball would cover it, so the cap
// on the surface balls makes the cover take exactly N. CI fills 50, 89 and 150;
// SHAPEPRESS_FULL_VALIDATION=1 adds 750, 1500 and 3000.
TEST(FillQuality, RigidSphereTakesThePapersCounts) {
  const double radius = 0.01;
  const SignedDistance shape = sphere_distance(radius);
  const MassProperties exact = ellipsoid_mass_properties(Vec3::Constant(radius));
  std::vector<int> counts = {50, 89, 150};
  const char* full = std::getenv("SHAPEPRESS_FULL_VALIDATION");
  if (full != nullptr && std::string(full) == "1") counts.insert(counts.end(), {750, 1500, 3000});
  double previous_cap = HUGE_VAL;
  for (int n : counts) {
    RigidFillOptions options;
    options.sphere_count = n;
    RigidFillInfo info;
    const SphereTemplate t = fill_rigid(shape, options, &info);
    const MassProperties u = union_mass_properties(t.centres, t.radii, 256);
    const RadialDeviation bumps = radial_deviation(t.centres, t.radii, Vec3::Zero(), radius);
    std::printf(
        "cms sphere N=%5d cap/R=%.4f Verr=%+.4f bump max/R=%.4f rms/R=%.4f (in %.4f, out %.4f) "
        "radii/R %.3f-%.3f %.2f s\n",
        n, info.radius_cap / radius, u.volume / exact.volume - 1.0, bumps.max_abs / radius,
        bumps.rms / radius, bumps.max_inward / radius, bumps.max_outward / radius,
        *std::min_element(t.radii.begin(), t.radii.end()) / radius,
        *std::max_element(t.radii.begin(), t.radii.end()) / radius, info.seconds);
    EXPECT_EQ(t.centres.size(), static_cast<std::size_t>(n));
    // More balls need smaller surface balls: the cap falls with N.
    EXPECT_LT(info.radius_cap, previous_cap);
    previous_cap = info.radius_cap;
    // Volume matched on the fill grid (64 cells across), measured here on a finer one: the
    // difference is the two grids' discretisation, well under 1 %.
    EXPECT_LT(std::fabs(u.volume / exact.volume - 1.0), 0.01);
    // The cover is complete to the grid: no dip or bump deeper than two cells (2 x 2R/64).
    EXPECT_LT(bumps.max_abs, 2.0 * info.grid_cell);
    EXPECT_GT(bumps.rms, 0.0);  // and it is bumpy, as a union of balls must be
    // Every ball lies in the sphere up to the common growth of match_volume (< one cell).
    for (std::size_t i = 0; i < t.centres.size(); ++i)
      EXPECT_LE(t.centres[i].norm() + t.radii[i], radius + info.grid_cell);
    // One rigid body: the overlap graph of the balls is connected.
    EXPECT_TRUE(is_connected(t.centres.size(), pairs_within(t.centres, t.radii, 1.0)));
  }
}

TEST(FillQuality, BondedFractionAndTrendOnSphereAndEllipsoid) {
  const std::vector<int> counts = {50, 150, 350, 1000, 3000};
  const auto sphere = bonded_series(
      sphere_distance(1e-4), ellipsoid_mass_properties(Vec3::Constant(1e-4)), counts, "bms sphere");
  const auto ellipsoid =
      bonded_series(ellipsoid_distance(paper_ellipsoid), ellipsoid_mass_properties(paper_ellipsoid),
                    counts, "bms ellipsoid");
  for (const auto* s : {&sphere, &ellipsoid}) {
    // Touching equal spheres wholly inside: below FCC's 0.7405, rising towards it with N.
    for (std::size_t i = 1; i < s->size(); ++i)
      EXPECT_GE((*s)[i].volume_fraction, (*s)[i - 1].volume_fraction - 0.01);
    EXPECT_LT(s->back().volume_fraction, 0.7405);
    EXPECT_GT(s->back().volume_fraction, 0.55);
    expect_decreasing(*s, &FillQuality::surface_rms_relative, "rms");
    expect_decreasing(*s, &FillQuality::hausdorff_relative, "hausdorff");
    expect_decreasing(*s, &FillQuality::inertia_error, "inertia");
    expect_decreasing(*s, &FillQuality::extent_error, "extent");
  }
}

TEST(FillQuality, MeshEllipsoidMatchesTheAnalyticOne) {
  const TriangleMesh mesh = ellipsoid_mesh(paper_ellipsoid, 4);
  const SignedDistance shape = mesh_distance(mesh, 64, "ellipsoid");
  const MassProperties exact = mesh_mass_properties(mesh);
  RigidFillOptions rigid;
  rigid.sphere_count = 150;
  const FillQuality cms = assess_fill(fill_rigid(shape, rigid), shape, exact);
  print("cms mesh", 150, cms);
  EXPECT_LT(cms.volume_error, 0.03);
  // Voxel surface (64 across) vs exact distance: within about a voxel of the analytic fill.
  EXPECT_LT(cms.surface_rms_relative, 0.02);
  BondedFillOptions bonded;
  bonded.target_count = 350;
  const FillQuality bms = assess_fill(fill_bonded(shape, bonded), shape, exact);
  print("bms mesh", 350, bms);
  EXPECT_EQ(bms.sphere_count, 350);
  EXPECT_TRUE(bms.connected);
  EXPECT_NEAR(bms.volume_fraction, 0.507, 0.03);  // analytic ellipsoid at 350 gives 0.507
}

}  // namespace
}  // namespace shapepress::geometry
