// The deposit start of pack ([settle] insertion = "deposit", packing/deposition.hpp): the poured
// bodies laid down without an overlap of sub-spheres, inside the box and above the floor, lower
// than the pour, with their sizes and templates kept, deterministically; and the overlap measure
// it is checked by finds an overlap planted across the periodic boundary.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "packing/deposition.hpp"
#include "packing/pack.hpp"
#include "tests/support/body_beds.hpp"

namespace shapepress::packing {
namespace {

PackRequest rod_and_cluster_request(std::int64_t count) {
  PackRequest r;
  r.templates = {{"bms/rod", 1.0}, {"bms/cluster13", 1.0}};
  r.count = count;
  r.sizes.diameters = {82.9e-6, 224.6e-6, 379.3e-6};
  r.sizes.levels = {0.1, 0.5, 0.9};
  r.sizes.volume_weighted = true;
  r.diameter_min = 180e-6;
  r.diameter_max = 300e-6;
  r.box_x = 1.2e-3, r.box_y = 1.1e-3;
  r.insertion_fraction = 0.3;
  r.seed = 11;
  return r;
}

TEST(Deposition, LaysThePourDownWithoutOverlapInsideTheBoxKeepingEveryBody) {
  const std::vector<BodyTemplate> templates = {testing::rod_template(),
                                               testing::cluster_template(BodyKind::bms, 1e-5)};
  const PackRequest r = rod_and_cluster_request(80);
  std::vector<PackedBody> poured = draw_bodies(r, templates);
  const double region_top = insert_bodies(r, templates, poured);
  const Box box{r.box_x, r.box_y};
  ASSERT_EQ(largest_start_overlap(templates, poured, box, r.floor), 0.0);

  std::vector<PackedBody> laid = poured;
  DepositionMoves moves;
  moves.seed = r.seed;
  const double top = deposit_bodies(templates, laid, box, r.floor, moves);
  EXPECT_EQ(largest_start_overlap(templates, laid, box, r.floor), 0.0);
  ASSERT_EQ(laid.size(), poured.size());
  for (std::size_t b = 0; b < laid.size(); ++b) {
    EXPECT_EQ(laid[b].template_index, poured[b].template_index);
    EXPECT_EQ(laid[b].scale, poured[b].scale);
    EXPECT_EQ(laid[b].body_volume, poured[b].body_volume);
    EXPECT_GE(laid[b].centre[0], 0.0);
    EXPECT_LT(laid[b].centre[0], r.box_x);
    EXPECT_GE(laid[b].centre[1], 0.0);
    EXPECT_LT(laid[b].centre[1], r.box_y);
    std::vector<Vector3> centres;
    std::vector<double> radii;
    place_body(templates[static_cast<std::size_t>(laid[b].template_index)], laid[b], centres,
               radii);
    for (std::size_t i = 0; i < radii.size(); ++i) {
      EXPECT_GE(centres[i][2] - radii[i], r.floor);
      EXPECT_LE(centres[i][2] + radii[i], top * (1 + 1e-12));
    }
  }
  // The pour's region holds its bounding spheres at 0.3 (the rods' bodies at a few per cent):
  // the laid bed is several times lower.
  EXPECT_LT(top, 0.4 * region_top);

  std::vector<PackedBody> again = poured;
  EXPECT_EQ(deposit_bodies(templates, again, box, r.floor, moves), top);
  for (std::size_t b = 0; b < laid.size(); ++b)
    EXPECT_EQ(again[b].centre, laid[b].centre);
}

TEST(Deposition, TheOverlapCheckFindsAPairAcrossThePeriodicBoundaryAndTheFloor) {
  const std::vector<BodyTemplate> templates = {testing::rod_template()};
  const Box box{1e-3, 1e-3};
  // Two rods along x (unturned), their end spheres (radius 0.8e-5 m, 3.6e-5 m from the middle)
  // facing each other across x = 0: a's left end is seen at x + 1 mm from b's right end.
  PackedBody a, b;
  a.centre = {1e-5, 0.5e-3, 0.2e-3};
  b.centre = {a.centre[0] + box.length_x - 2.0 * 3.6e-5 - 1.5e-5, 0.5e-3, 0.2e-3};
  EXPECT_NEAR(largest_start_overlap(templates, {a, b}, box, 0.0), 0.1e-5, 1e-12);
  b.centre[0] -= 0.2e-5;  // 1 um apart
  EXPECT_EQ(largest_start_overlap(templates, {a, b}, box, 0.0), 0.0);
  a.centre[2] = 0.5e-5;  // its middle sphere of radius 1e-5 m half through the floor
  EXPECT_NEAR(largest_start_overlap(templates, {a}, box, 0.0), 0.5e-5, 1e-12);
}

}  // namespace
}  // namespace shapepress::packing
