#include "common/suggest.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace shapepress {
namespace {

TEST(Suggest, EditDistance) {
  EXPECT_EQ(edit_distance("compact", "compact"), 0u);
  EXPECT_EQ(edit_distance("compcat", "compact"), 2u);
  EXPECT_EQ(edit_distance("", "fill"), 4u);
  EXPECT_EQ(edit_distance("plate", "plates"), 1u);
}

TEST(Suggest, ClosestMatchFindsTyposAndPrefixesButNotStrangers) {
  std::vector<std::string> stages{"shape-stats", "generate", "fill", "pack", "compact", "plate"};
  EXPECT_EQ(closest_match("compcat", stages), "compact");
  EXPECT_EQ(closest_match("shapestats", stages), "shape-stats");
  EXPECT_EQ(closest_match("gen", stages), "generate");
  EXPECT_EQ(closest_match("plat", stages), "plate");
  EXPECT_FALSE(closest_match("xyzzy-frobnicate", stages).has_value());
}

}  // namespace
}  // namespace shapepress
