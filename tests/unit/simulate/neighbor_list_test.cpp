// The Verlet half list against brute force in a periodic box, and history carried by merging.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <utility>

#include "common/error.hpp"
#include "simulate/neighbor_list.hpp"

namespace shapepress::simulate {
namespace {

SphereState random_spheres(int count, double length, std::uint32_t seed, double r_min = 0.4e-3,
                           double r_max = 0.6e-3) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> coordinate(0.0, length), radius(r_min, r_max);
  SphereState s;
  for (int i = 0; i < count; ++i)
    s.add_sphere(coordinate(random), coordinate(random), coordinate(random), radius(random), 1000.0,
                 0);
  return s;
}

TEST(NeighborList, HalfListEqualsBruteForceWithPeriodicImages) {
  const double length = 8e-3, skin = 0.2e-3;
  const SphereState s = random_spheres(600, length, 7);
  const Box box{length, length};
  const PairList list = build_pair_list(s, box, skin);
  std::set<std::pair<int, int>> expected;
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j) {
      double dx = s.position.x[j] - s.position.x[i], dy = s.position.y[j] - s.position.y[i];
      dx -= length * std::nearbyint(dx / length);
      dy -= length * std::nearbyint(dy / length);
      const double dz = s.position.z[j] - s.position.z[i];
      const double reach = s.radius[i] + s.radius[j] + skin;
      if (dx * dx + dy * dy + dz * dz < reach * reach) expected.emplace(i, j);
    }
  std::set<std::pair<int, int>> found;
  for (std::size_t p = 0; p < list.size(); ++p) {
    ASSERT_LT(list.first[p], list.second[p]);
    if (p > 0) {
      ASSERT_TRUE(std::make_pair(list.first[p - 1], list.second[p - 1]) <
                  std::make_pair(list.first[p], list.second[p]));
    }
    found.emplace(list.first[p], list.second[p]);
  }
  EXPECT_EQ(found, expected);
  EXPECT_EQ(found.size(), list.size());  // each pair once
  EXPECT_GT(list.size(), 100u);          // the scene really has crossing pairs to find
  // Every pair appears in both spheres' gather lists: as first in a contiguous range, as second
  // in the CSR, each in increasing pair order.
  const int n = static_cast<int>(list.first_offset.size()) - 1;
  ASSERT_EQ(list.second_pairs.size(), list.size());
  EXPECT_EQ(list.first_offset.back(), static_cast<int>(list.size()));
  EXPECT_EQ(list.second_offset.back(), static_cast<int>(list.size()));
  for (int i = 0; i < n; ++i) {
    for (int p = list.first_offset[i]; p < list.first_offset[i + 1]; ++p)
      ASSERT_EQ(list.first[p], i);
    for (int e = list.second_offset[i]; e < list.second_offset[i + 1]; ++e) {
      ASSERT_EQ(list.second[list.second_pairs[e]], i);
      if (e > list.second_offset[i]) {
        ASSERT_LT(list.second_pairs[e - 1], list.second_pairs[e]);
      }
    }
  }
}

TEST(NeighborList, HistoryFollowsPairsAcrossRebuilds) {
  PairList old_pairs, new_pairs;
  old_pairs.first = {0, 0, 2};
  old_pairs.second = {1, 3, 5};
  new_pairs.first = {0, 1, 2, 2};
  new_pairs.second = {3, 4, 4, 5};
  std::vector<ContactHistory> old_history(3);
  old_history[0].tangential[0] = 1.0;
  old_history[1].tangential[0] = 2.0;
  old_history[2].tangential[0] = 3.0;
  const auto carried = carry_history(old_pairs, old_history, new_pairs);
  ASSERT_EQ(carried.size(), 4u);
  EXPECT_EQ(carried[0].tangential[0], 2.0);
  EXPECT_EQ(carried[1].tangential[0], 0.0);
  EXPECT_EQ(carried[2].tangential[0], 0.0);
  EXPECT_EQ(carried[3].tangential[0], 3.0);
}

TEST(NeighborList, PeriodicBoxNotTwiceTheReachIsAnInputError) {
  // Reach 2 × 0.6 + 0.1 mm = 1.3 mm: a 2 mm period could let a pair meet through two images.
  const SphereState s = random_spheres(10, 2e-3, 1);
  EXPECT_THROW(build_pair_list(s, Box{2e-3, 2e-3}, 0.1e-3), InputError);
}

TEST(NeighborList, TwoCellsPerPeriodFindEachPairOnce) {
  // Reach ≤ 0.7 mm in a 1.5 mm period: two cells, whose -1 and +1 neighbours are one cell.
  const double length = 1.5e-3, skin = 0.1e-3;
  const SphereState s = random_spheres(40, length, 3, 0.1e-3, 0.3e-3);
  const PairList list = build_pair_list(s, Box{length, length}, skin);
  std::set<std::pair<int, int>> expected, found;
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j) {
      double dx = s.position.x[j] - s.position.x[i], dy = s.position.y[j] - s.position.y[i];
      dx -= length * std::nearbyint(dx / length);
      dy -= length * std::nearbyint(dy / length);
      const double dz = s.position.z[j] - s.position.z[i];
      const double reach = s.radius[i] + s.radius[j] + skin;
      if (dx * dx + dy * dy + dz * dz < reach * reach) expected.emplace(i, j);
    }
  for (std::size_t p = 0; p < list.size(); ++p)
    found.emplace(list.first[p], list.second[p]);
  EXPECT_EQ(found, expected);
  EXPECT_EQ(found.size(), list.size());  // no pair twice
  EXPECT_GT(list.size(), 20u);
}

TEST(NeighborList, WrapBringsPositionsIntoTheBox) {
  SphereState s;
  s.add_sphere(-1e-3, 11e-3, 5.0, 1e-4, 1.0, 0);
  wrap_positions(s, Box{10e-3, 10e-3});
  EXPECT_NEAR(s.position.x[0], 9e-3, 1e-15);
  EXPECT_NEAR(s.position.y[0], 1e-3, 1e-15);
  EXPECT_EQ(s.position.z[0], 5.0);
}

}  // namespace
}  // namespace shapepress::simulate
