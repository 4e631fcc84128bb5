// generate from measured statistics as a user runs the chain (issue 19): synth-images →
// shape-stats → generate on a mixed population (discs, ellipses, rough Fourier outlines), whose
// projected ASR has a mass of round particles near 1 beside elongated ones.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress::geometry {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::run_shapepress;
namespace fs = std::filesystem;

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(GenerateFromImages, MixedPopulationMatchesTheMeasuredProjectedAsr) {
  const fs::path dir = fresh_directory("generate_from_images");
  auto r = run_shapepress("--quiet synth-images --out " + (dir / "images").string() +
                          " --images 2 --particles 60 --shape mixed --seed 2026");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_shapepress("--quiet shape-stats " + (dir / "images" / "synth_000.tif").string() + " " +
                     (dir / "images" / "synth_001.tif").string() + " --out " +
                     (dir / "stats").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The case of the issue: a quarter or more of the silhouettes near ASR 1 (the discs), a tenth
  // of them below 0.7.
  const nlohmann::json summary = read_json(dir / "stats" / "summary.json");
  const std::vector<double> levels = summary["asr"]["quantile_levels"];
  const std::vector<double> quantiles = summary["asr"]["quantiles"];
  ASSERT_EQ(levels.size(), 19u);
  EXPECT_GT(quantiles[14], 0.97) << "75 % quantile";
  EXPECT_LT(quantiles[1], 0.7) << "10 % quantile";

  r = run_shapepress("--quiet generate --targets " + (dir / "stats" / "summary.json").string() +
                     " --count 40 --seed 3 --subdivisions 3 --directions 32 --out " +
                     (dir / "shapes").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json facts = read_json(dir / "shapes" / "run.json")["facts"];
  EXPECT_EQ(facts["particles"], 40);
  const double ks = facts["projected_asr_ks"];
  EXPECT_LT(ks, 0.1) << r.output;
  EXPECT_DOUBLE_EQ(facts["projected_asr_ks_tolerance"].get<double>(), 0.1);
  EXPECT_TRUE(facts["warnings"].empty()) << facts["warnings"].dump();
  EXPECT_EQ(r.output.find("warn"), std::string::npos) << r.output;
  const std::vector<double> generated = facts["projected_asr_quantiles"];
  ASSERT_EQ(generated.size(), quantiles.size());
  // The round mass is there: the generated 95 % quantile is as near 1 as the images'.
  EXPECT_NEAR(generated.back(), quantiles.back(), 0.02);

  // Above a tolerance the population misses: a warning in the output (not --quiet, which shows
  // errors only) and in run.json.
  r = run_shapepress("generate --targets " + (dir / "stats" / "summary.json").string() +
                     " --count 3 --subdivisions 2 --ks-tolerance 0.001 --out " +
                     (dir / "few").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("--ks-tolerance"), std::string::npos) << r.output;
  const nlohmann::json few = read_json(dir / "few" / "run.json")["facts"];
  ASSERT_EQ(few["warnings"].size(), 1u);
  EXPECT_NE(few["warnings"][0].get<std::string>().find("KS distance"), std::string::npos);
  EXPECT_GT(few["projected_asr_ks"].get<double>(), 0.001);
}

}  // namespace
}  // namespace shapepress::geometry
