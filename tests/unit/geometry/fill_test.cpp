#include <gtest/gtest.h>
#include "common/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "geometry/random_packing.hpp"
#include "geometry/sphere_fill.hpp"
#include "geometry/template_quality.hpp"

namespace shapepress::geometry {
namespace {

TEST(BondedFill, HitsTheTargetCountWithTouchingNonOverlappingSpheres) {
  const SignedDistance shape = ellipsoid_distance(Vec3(1.0, 0.84, 0.8));
  BondedFillOptions options;
  options.target_count = 350;
  const SphereTemplate t = fill_bonded(shape, options);
  EXPECT_EQ(t.centres.size(), 350u);
  const double r = t.radii.front();
  double closest = 1e9;
  for (std::size_t i = 0; i < t.centres.size(); ++i) {
    EXPECT_LE(shape(t.centres[i]), -r + 1e-12);  // wholly inside
    for (std::size_t j = i + 1; j < t.centres.size(); ++j)
      closest = std::min(closest, (t.centres[i] - t.centres[j]).norm());
  }
  EXPECT_NEAR(closest, 2.0 * r, 1e-9 * r);  // lattice neighbours touch, none overlap
  EXPECT_TRUE(is_connected(t.centres.size(), t.bonds));
  // FCC interior spheres have 12 touching neighbours; Eq. 10 with m_b = 1.15 bonds exactly those.
  for (const Bond& b : t.bonds) {
    const double d =
        (t.centres[static_cast<std::size_t>(b[0])] - t.centres[static_cast<std::size_t>(b[1])])
            .norm();
    EXPECT_NEAR(d, 2.0 * r, 1e-9 * r);
  }
}

TEST(BondedFill, HcpAndFixedRadius) {
  const SignedDistance shape = sphere_distance(1.0);
  BondedFillOptions options;
  options.lattice = Lattice::hcp;
  options.sub_sphere_radius = 0.1;
  const SphereTemplate t = fill_bonded(shape, options);
  // Sphere of radius 0.9 for centres holds ~0.74 (0.9/0.1)^3 = 540 spheres: allow lattice and
  // boundary effects of ±15 %.
  EXPECT_GT(t.centres.size(), 460u);
  EXPECT_LT(t.centres.size(), 620u);
  for (double r : t.radii)
    EXPECT_DOUBLE_EQ(r, 0.1);
  EXPECT_TRUE(is_connected(t.centres.size(), t.bonds));
}

TEST(BondedFill, SameSeedSameTemplateOtherSeedOtherOrientation) {
  const SignedDistance shape = ellipsoid_distance(Vec3(1.0, 0.7, 0.5));
  BondedFillOptions options;
  options.target_count = 120;
  const SphereTemplate a = fill_bonded(shape, options), b = fill_bonded(shape, options);
  ASSERT_EQ(a.centres.size(), b.centres.size());
  for (std::size_t i = 0; i < a.centres.size(); ++i)
    EXPECT_EQ(a.centres[i], b.centres[i]);
  options.seed = 2;
  const SphereTemplate c = fill_bonded(shape, options);
  EXPECT_NE(a.centres.front(), c.centres.front());
}

TEST(BondedFill, RandomPackingIsDenseTouchingConnectedAndWithoutSlipPlanes) {
  const SignedDistance shape = sphere_distance(1.0);
  BondedFillOptions options;
  options.lattice = Lattice::random;
  options.target_count = 300;
  const SphereTemplate t = fill_bonded(shape, options);
  ASSERT_EQ(t.centres.size(), 300u);  // exactly the count: no rattler was dropped
  const double r = t.radii.front();
  std::vector<int> touching(t.centres.size(), 0);
  double closest = 1e9;
  for (std::size_t i = 0; i < t.centres.size(); ++i) {
    EXPECT_LE(shape(t.centres[i]), -r + 1e-12);  // wholly inside
    for (std::size_t j = i + 1; j < t.centres.size(); ++j) {
      const double d = (t.centres[i] - t.centres[j]).norm();
      closest = std::min(closest, d);
      // Within 1 % of touching: what the jammed growth leaves between contacting spheres.
      if (d < 2.02 * r) ++touching[i], ++touching[j];
    }
  }
  EXPECT_GE(closest, 2.0 * r * (1.0 - 1e-12));  // none overlap
  EXPECT_TRUE(is_connected(t.centres.size(), t.bonds));
  // Jammed: the solid fraction is far above a loose random packing's (random sequential
  // addition jams at 0.38) and most spheres touch several others. A random packing of 300
  // spheres in a sphere reaches about 0.5 (the wall layer is looser than the bulk's 0.64).
  const double solid = 300.0 * r * r * r;  // (4/3 π r³ N) / (4/3 π R³), R = 1
  EXPECT_GT(solid, 0.45);
  int well_held = 0;
  for (int c : touching)
    well_held += c >= 3;
  EXPECT_GT(well_held, 240);  // >= 80 % of the spheres touch three or more neighbours
  // No lattice: bond directions spread over the sphere (an FCC has only 6 axes, so its bonds
  // fall into 6 direction classes); count distinct directions on a coarse 5-degree grid.
  std::vector<std::array<int, 2>> seen;
  for (const Bond& b : t.bonds) {
    Vec3 n = (t.centres[static_cast<std::size_t>(b[1])] - t.centres[static_cast<std::size_t>(b[0])])
                 .normalized();
    if (n.z() < 0.0) n = -n;
    const std::array<int, 2> cell = {static_cast<int>(std::acos(n.z()) * 36.0),
                                     static_cast<int>((std::atan2(n.y(), n.x()) + 3.2) * 36.0)};
    if (std::find(seen.begin(), seen.end(), cell) == seen.end()) seen.push_back(cell);
  }
  EXPECT_GT(seen.size(), 100u);
  // The same seed gives the same packing bit for bit; a fixed radius is refused (the packing's
  // radius is where it jams).
  const SphereTemplate again = fill_bonded(shape, options);
  EXPECT_EQ(again.centres, t.centres);
  options.sub_sphere_radius = 0.1;
  EXPECT_THROW(fill_bonded(shape, options), InputError);
}

TEST(BondedFill, RandomPackingFollowsAMeshLikeShape) {
  // An ellipsoid through the same SignedDistance interface (meshes plug in the same way).
  const SignedDistance shape = ellipsoid_distance(Vec3(1.0, 0.6, 0.5));
  BondedFillOptions options;
  options.lattice = Lattice::random;
  options.target_count = 80;
  options.seed = 3;
  const SphereTemplate t = fill_bonded(shape, options);
  ASSERT_EQ(t.centres.size(), 80u);
  const double r = t.radii.front();
  for (const Vec3& c : t.centres)
    EXPECT_LE(shape(c), -r + 1e-9);
  EXPECT_TRUE(is_connected(t.centres.size(), t.bonds));
}

TEST(BondedFill, RejectsBadOptions) {
  BondedFillOptions options;
  options.bond_multiplier = 1.5;
  EXPECT_THROW(options.check(), InputError);
  options = {};
  options.target_count = 0;
  EXPECT_THROW(options.check(), InputError);
}

TEST(Bonds, Equation10AndConnectivity) {
  const std::vector<Vec3> c = {{0, 0, 0}, {2.2, 0, 0}, {5, 0, 0}};
  const std::vector<double> r = {1.0, 1.0, 1.0};
  // |x0 - x1| = 2.2 < 2 * 1.15 = 2.3 bonds; |x1 - x2| = 2.8 does not.
  EXPECT_EQ(pairs_within(c, r, 1.15), (std::vector<Bond>{{0, 1}}));
  EXPECT_FALSE(is_connected(3, pairs_within(c, r, 1.15)));
  EXPECT_TRUE(is_connected(3, pairs_within(c, r, 1.41)));
  EXPECT_EQ(connected_components(3, {{0, 2}}), (std::vector<int>{0, 1, 0}));
}

TEST(MassProperties, UnionCountsOverlapsOnce) {
  // Two unit spheres at distance 1: union volume = 2 V - lens, lens = 5π/12 for d = r = 1.
  const std::vector<Vec3> c = {{0, 0, 0}, {1, 0, 0}};
  const std::vector<double> r = {1.0, 1.0};
  const MassProperties u = union_mass_properties(c, r, 160);
  const double exact = 2.0 * 4.0 / 3.0 * std::numbers::pi - 5.0 * std::numbers::pi / 12.0;
  EXPECT_NEAR(u.volume / exact, 1.0, 2e-3);  // midpoint voxels, 160 cells: ~0.1 % error
  EXPECT_NEAR(u.centre.x(), 0.5, 1e-3);
  const MassProperties sum = sphere_sum_mass_properties(c, r);
  EXPECT_GT(sum.volume / u.volume, 1.1);  // summing would count the lens twice
  // One sphere: I = 2/5 V r² about every axis.
  const MassProperties one = union_mass_properties({{0, 0, 0}}, {1.0}, 160);
  const double expected = 0.4 * (4.0 / 3.0 * std::numbers::pi);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(one.principal_moments[k] / expected, 1.0, 3e-3);
}

// Moments of the part of a ball (centre `c` on the x axis, radius r) with x in [a, b], about the
// origin's axes, per unit density: slices of radius ρ² = r² - (x - c)² give dV = π ρ² dx,
// dIxx = π ρ⁴/2 dx and dIyy = (π ρ⁴/4 + π ρ² x²) dx; the integrands are polynomials of degree 4
// in x, so Simpson's rule on 400 panels is within 1e-10 of the closed forms.
struct SliceMoments {
  double volume = 0.0, ixx = 0.0, iyy = 0.0;
};
SliceMoments ball_slab(double c, double r, double a, double b) {
  const int panels = 400;
  const double h = (b - a) / panels;
  SliceMoments m;
  for (int k = 0; k <= panels; ++k) {
    const double x = a + k * h;
    const double weight = (k == 0 || k == panels) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0);
    const double rho2 = r * r - (x - c) * (x - c);
    const double pi = std::numbers::pi;
    m.volume += weight * pi * rho2;
    m.ixx += weight * 0.5 * pi * rho2 * rho2;
    m.iyy += weight * (0.25 * pi * rho2 * rho2 + pi * rho2 * x * x);
  }
  m.volume *= h / 3.0, m.ixx *= h / 3.0, m.iyy *= h / 3.0;
  return m;
}

// Issue 6 acceptance: a dumbbell's (two overlapping spheres) voxel-integrated inertia within 1 %
// of the analytic union, I = I_A + I_B - I_lens, where a sum of spheres would count the lens
// twice.
TEST(MassProperties, OverlappingDumbbellInertiaMatchesTheAnalyticUnion) {
  const double r = 1.0, d = 1.2;  // centres at ±d/2, lens of half-width r - d/2
  const SliceMoments ball = ball_slab(0.0, r, -r, r);
  // Lens = the part of ball A (at -d/2) with x > 0 plus the part of ball B with x < 0.
  const SliceMoments cap = ball_slab(-0.5 * d, r, 0.0, r - 0.5 * d);
  const double volume = 2.0 * ball.volume - 2.0 * cap.volume;
  const double ixx = 2.0 * ball.ixx - 2.0 * cap.ixx;
  const double iyy = 2.0 * (ball.iyy + ball.volume * 0.25 * d * d) - 2.0 * cap.iyy;
  EXPECT_NEAR(ball.ixx / (0.4 * ball.volume * r * r), 1.0, 1e-9);  // the reference itself

  const MassProperties u = union_mass_properties({{-0.5 * d, 0, 0}, {0.5 * d, 0, 0}}, {r, r}, 128);
  std::printf(
      "dumbbell d = %.1f r: volume %.5f (exact %.5f), I_axis %.5f (%.5f), I_perp %.5f "
      "(%.5f)\n",
      d, u.volume, volume, u.principal_moments[0], ixx, u.principal_moments[2], iyy);
  EXPECT_NEAR(u.volume / volume, 1.0, 0.01);
  // Ascending principal moments: the symmetry axis has the smallest.
  EXPECT_NEAR(u.principal_moments[0] / ixx, 1.0, 0.01);
  EXPECT_NEAR(u.principal_moments[1] / iyy, 1.0, 0.01);
  EXPECT_NEAR(u.principal_moments[2] / iyy, 1.0, 0.01);
  const MassProperties sum =
      sphere_sum_mass_properties({{-0.5 * d, 0, 0}, {0.5 * d, 0, 0}}, {r, r});
  EXPECT_GT(sum.principal_moments[2] / iyy, 1.015) << "the plain sum counts the lens twice";
}

// The capped cover (issue 6, paper Fig. 3): a ball that reaches the surface is no larger than the
// cap, a larger one stays a cap below the surface; the interior is covered.
TEST(RigidFill, CappedBallsDrawTheSurfaceAndTheCoreStaysBelowIt) {
  const SignedDistance shape = sphere_distance(1.0);
  RigidFillOptions options;
  options.sphere_count = 100000;  // as many as the cover takes
  options.max_radius = 0.3;
  options.match_volume = false;
  options.resolution = 32;
  RigidFillInfo info;
  const SphereTemplate t = fill_rigid(shape, options, &info);
  EXPECT_TRUE(info.cover_complete);
  EXPECT_EQ(info.radius_cap, 0.3);
  const double h = info.grid_cell;  // the walk finds centres to a quarter cell
  for (std::size_t i = 0; i < t.centres.size(); ++i) {
    const double depth = 1.0 - t.centres[i].norm();
    EXPECT_LE(t.radii[i], depth + 1e-12);  // inscribed
    if (t.radii[i] > 0.3 + 1e-12) {
      EXPECT_LE(t.radii[i], depth - 0.3 + 1e-12);
    }
  }
  // Deepest first: the first ball is the core, 1 - cap about the centre.
  EXPECT_NEAR(t.radii.front(), 0.7, h);
  EXPECT_NEAR(t.centres.front().norm(), 0.0, h);
}

TEST(RigidFill, AskedCountOfASphereAndBadInput) {
  const SignedDistance shape = sphere_distance(1.0);
  RigidFillOptions options;
  options.sphere_count = 40;
  options.resolution = 32;
  RigidFillInfo info;
  const SphereTemplate t = fill_rigid(shape, options, &info);
  EXPECT_EQ(t.centres.size(), 40u);
  EXPECT_LT(info.radius_cap, 1.0);
  const SphereTemplate again = fill_rigid(shape, options);
  EXPECT_EQ(again.centres, t.centres);  // deterministic
  EXPECT_EQ(again.radii, t.radii);
  options.max_radius = -1.0;
  EXPECT_THROW(options.check(), InputError);
  // Far more balls than a 16-cell grid can place: InputError asking for a finer grid.
  options = {};
  options.resolution = 16;
  options.sphere_count = 50000;
  EXPECT_THROW(fill_rigid(shape, options), InputError);
}

TEST(RigidFill, RadialDeviationOfAnOffsetBall) {
  // A ball of radius 1 moved by 0.1 along x, against the unit sphere at the origin: the union's
  // surface lies between 0.9 and 1.1 from the origin, RMS about 0.1/√3.
  const RadialDeviation d = radial_deviation({Vec3(0.1, 0, 0)}, {1.0}, Vec3::Zero(), 1.0, 4000);
  EXPECT_NEAR(d.max_outward, 0.1, 1e-3);
  EXPECT_NEAR(d.max_inward, 0.1, 1e-3);
  EXPECT_NEAR(d.rms, 0.1 / std::sqrt(3.0), 2e-3);
  EXPECT_EQ(d.max_abs, std::max(d.max_inward, d.max_outward));
}

// What a plate meets: for `directions` plate normals u spread over the sphere (a Fibonacci
// lattice), the plate pressed δ into the unit sphere touches the sub-spheres with
// c·u + r > 1 − δ. Returns the mean and the coefficient of variation over the directions of
// Σ δᵢ^1.5, δᵢ = c·u + r − 1 + δ: the force of Hertz contacts of a rigid plate on sub-spheres
// held in place, a proxy for how much the force at small deformation depends on where the
// sub-spheres happen to sit.
struct CapLoad {
  double mean = 0.0, variation = 0.0;
};
CapLoad cap_load(const SphereTemplate& t, double delta, int directions) {
  const double r = t.radii.front();
  std::vector<double> load;
  for (int k = 0; k < directions; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / directions;
    const double phi = k * std::numbers::pi * (3.0 - std::sqrt(5.0));
    const Vec3 u(std::sqrt(1.0 - z * z) * std::cos(phi), std::sqrt(1.0 - z * z) * std::sin(phi), z);
    double sum = 0.0;
    for (const Vec3& c : t.centres)
      sum += std::pow(std::max(0.0, c.dot(u) + r - 1.0 + delta), 1.5);
    load.push_back(sum);
  }
  double mean = 0.0, var = 0.0;
  for (double l : load)
    mean += l / directions;
  for (double l : load)
    var += (l - mean) * (l - mean) / directions;
  return {mean, std::sqrt(var) / mean};
}

TEST(BondedFill, ShellPackingPutsAnEvenLayerOnTheSurface) {
  const SignedDistance shape = sphere_distance(1.0);
  BondedFillOptions options;
  options.target_count = 545;
  options.lattice = Lattice::shell;
  const SphereTemplate t = fill_bonded(shape, options);
  ASSERT_EQ(t.centres.size(), 545u);  // exactly the count
  const double r = t.radii.front();
  RandomPackingOptions packing;
  packing.count = 545;
  packing.contact_gap = 0.15;
  const ShellPacking shell = surface_conforming_packing(shape, {packing});
  EXPECT_EQ(shell.packing.centres, t.centres);  // the filler's packing, the shell first
  // The offset surface's area from the grid band: the analytic 4π(1 − r)² within 2 %.
  EXPECT_NEAR(shell.offset_area, 4.0 * std::numbers::pi * std::pow(1.0 - shell.plain_radius, 2),
              0.02 * shell.offset_area);
  double closest = 1e9;
  for (std::size_t i = 0; i < t.centres.size(); ++i) {
    EXPECT_LE(shape(t.centres[i]), -r + 1e-12);  // wholly inside
    // The shell touches the surface (to the growth's tolerance, 1e-3 r).
    if (static_cast<int>(i) < shell.shell_count) {
      EXPECT_GT(shape(t.centres[i]), -r * 1.002) << "shell sphere " << i;
    }
    for (std::size_t j = i + 1; j < t.centres.size(); ++j)
      closest = std::min(closest, (t.centres[i] - t.centres[j]).norm());
  }
  EXPECT_GE(closest, 2.0 * r * (1.0 - 1e-12));
  EXPECT_TRUE(is_connected(t.centres.size(), t.bonds));
  // The interior is as dense as the plain packing (the radius within 3 %), and a plate pressed
  // 0.05 R in meets a load that varies far less with where it presses: less than 0.6 of the
  // plain packing's spread (measured 0.12 against 0.27).
  options.lattice = Lattice::random;
  const SphereTemplate plain = fill_bonded(shape, options);
  EXPECT_NEAR(r, plain.radii.front(), 0.03 * plain.radii.front());
  const CapLoad even = cap_load(t, 0.05, 400), random = cap_load(plain, 0.05, 400);
  EXPECT_LT(even.variation, 0.6 * random.variation);
}

}  // namespace
}  // namespace shapepress::geometry

namespace shapepress::geometry {
namespace {

// Coordination (bonds by Eq. 10, m_b = 1.15) of the sub-spheres whose centres lie within a
// quarter diameter of the deepest place a wholly inside sphere can sit (the wall layer), and of
// the rest.
struct LayerCoordination {
  double outer = 0.0, inner = 0.0;
  double outer_share = 0.0;  // of all sub-spheres
};
LayerCoordination layer_coordination(const SphereTemplate& t, const SignedDistance& shape) {
  const double r = t.radii.front();
  std::vector<int> degree(t.centres.size(), 0);
  for (const Bond& b : t.bonds)
    ++degree[static_cast<std::size_t>(b[0])], ++degree[static_cast<std::size_t>(b[1])];
  double outer = 0, inner = 0;
  int n_outer = 0, n_inner = 0;
  for (std::size_t i = 0; i < t.centres.size(); ++i)
    if (-shape(t.centres[i]) - r < 0.5 * r)
      outer += degree[i], ++n_outer;
    else
      inner += degree[i], ++n_inner;
  return {outer / n_outer, inner / n_inner,
          static_cast<double>(n_outer) / static_cast<double>(t.centres.size())};
}

TEST(BondedFill, CarvedPackingKeepsTheBulkStructureUpToTheSurface) {
  // The shape cut out of a larger random packing: exactly N, no overlap, wholly inside, one
  // sub-sphere on the surface (the scale's), connected; and no wall-ordered layer: a plain
  // random fill of 300 puts 43 % of them within half a radius of the wall (5.5 bonds each, 8.5
  // inside), the carved one 21 % (measured), and its interior is as coordinated as a bulk
  // packing (8.4).
  const SignedDistance shape = sphere_distance(1.0);
  BondedFillOptions options;
  options.target_count = 300;
  options.lattice = Lattice::carved;
  const SphereTemplate t = fill_bonded(shape, options);
  ASSERT_EQ(t.centres.size(), 300u);
  const double r = t.radii.front();
  double closest = 1e9, deepest_outer = 1e9;
  for (std::size_t i = 0; i < t.centres.size(); ++i) {
    EXPECT_LE(shape(t.centres[i]), -r * (1.0 - 1e-9));
    deepest_outer = std::min(deepest_outer, -shape(t.centres[i]) - r);
    for (std::size_t j = i + 1; j < t.centres.size(); ++j)
      closest = std::min(closest, (t.centres[i] - t.centres[j]).norm());
  }
  EXPECT_GE(closest, 2.0 * r * (1.0 - 1e-9));
  EXPECT_LT(deepest_outer, 1e-6 * r);  // the N-th sub-sphere touches the surface
  EXPECT_TRUE(is_connected(t.centres.size(), t.bonds));
  options.lattice = Lattice::random;
  const SphereTemplate plain = fill_bonded(shape, options);
  const LayerCoordination carved = layer_coordination(t, shape);
  const LayerCoordination walled = layer_coordination(plain, shape);
  EXPECT_GT(walled.outer_share, 0.35);
  EXPECT_LT(carved.outer_share, 0.3);
  EXPECT_GT(carved.inner, 8.0);  // bulk random packing at m_b = 1.15 (measured 8.9)
  options.lattice = Lattice::carved;
  EXPECT_EQ(fill_bonded(shape, options).centres, t.centres);  // same seed, same template
  EXPECT_EQ(lattice_from_name("carved"), Lattice::carved);
  EXPECT_THROW(lattice_from_name("carve"), InputError);
}

}  // namespace
}  // namespace shapepress::geometry
