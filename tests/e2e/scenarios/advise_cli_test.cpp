// `shapepress advise` as a user runs it (issue 21, point 2): a cheap ladder of rigid-clump
// plate runs writes the table, the charts and the pick into run.json; run again with --resume it
// re-runs nothing and picks the same; without --resume it refuses to overwrite finished rungs.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::run_shapepress;
using shapepress::testing::shell_quoted;
using shapepress::testing::text_rows;
using ::testing::HasSubstr;

const std::filesystem::path repo = shapepress::testing::repository_root();
const std::filesystem::path shipped = repo / "pipelines/configs/rubber-sphere.toml";

nlohmann::json read_json(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(AdviseCli, PicksFromALadderAndAResumedAdviseRerunsNothing) {
  const auto dir = fresh_directory("advise_cli");
  const std::string command = "--threads 2 --quiet advise --config " + shell_quoted(shipped) +
                              " --particle cms --counts 1,20 --fractions 0.1,0.2 "
                              "--tolerance 0.05 --out " +
                              shell_quoted(dir / "advice");
  const auto first = run_shapepress(command);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const nlohmann::json meta = read_json(dir / "advice" / "run.json");
  const nlohmann::json& facts = meta.at("facts");
  EXPECT_EQ(facts.at("rungs").get<int>(), 4);
  EXPECT_EQ(facts.at("rungs_run").get<int>(), 4);
  EXPECT_EQ(facts.at("reference").get<std::string>(), "cms-20-f0.1");
  EXPECT_TRUE(std::filesystem::exists(dir / "advice" / "advice.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir / "advice" / "speed_accuracy.svg"));
  EXPECT_TRUE(std::filesystem::exists(dir / "advice" / "stability_map.svg"));
  const auto stamp = std::filesystem::last_write_time(dir / "advice" / "cms-20-f0.2" / "force.csv");
  // Every rung's counted cost (its run.json's) beside its CPU seconds, and the pick the holding
  // rung of least counted cost.
  const auto rows = text_rows(dir / "advice" / "advice.csv");
  ASSERT_EQ(rows.size(), 4u);
  std::int64_t least = -1;
  for (const auto& row : rows) {
    ASSERT_TRUE(row.contains("counted_cost") && row.contains("cpu_s"));
    const std::int64_t cost = std::stoll(row.at("counted_cost"));
    const nlohmann::json rung = read_json(dir / "advice" / row.at("label") / "run.json");
    EXPECT_EQ(cost, rung.at("facts").at("counted_cost").get<std::int64_t>()) << row.at("label");
    EXPECT_GT(cost, 0);
    EXPECT_GE(std::stod(row.at("cpu_s")), 0.0);
    if (row.at("status") == "within" || row.at("status") == "reference")
      least = least < 0 ? cost : std::min(least, cost);
    if (row.at("picked") == "1") {
      EXPECT_EQ(row.at("label"), facts.at("pick").get<std::string>());
      EXPECT_EQ(cost, facts.at("pick_counted_cost").get<std::int64_t>());
      EXPECT_EQ(facts.at("predicted_full_run_counted_cost").get<double>(), cost);  // one fill
    }
  }
  EXPECT_EQ(facts.at("pick_counted_cost").get<std::int64_t>(), least);
  EXPECT_TRUE(facts.contains("pick_cpu_s"));
  // The report reads the pick's error under one name for plate and bed ladders.
  EXPECT_LE(facts.at("pick_error_vs_reference").get<double>(), 0.05);
  EXPECT_EQ(facts.at("pick_error_vs_reference"), facts.at("pick_rms_vs_reference"));
  EXPECT_TRUE(facts.contains("predicted_full_run_cpu_s"));

  // The same ladder again: nothing is re-run, the pick is the same.
  const auto again = run_shapepress(command + " --resume");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  const nlohmann::json resumed = read_json(dir / "advice" / "run.json").at("facts");
  EXPECT_EQ(resumed.at("rungs_run").get<int>(), 0);
  EXPECT_EQ(resumed.at("rungs_reused").get<int>(), 4);
  EXPECT_EQ(resumed.at("pick"), facts.at("pick"));
  EXPECT_EQ(std::filesystem::last_write_time(dir / "advice" / "cms-20-f0.2" / "force.csv"), stamp);

  // Without --resume the finished rungs are not silently reused or overwritten.
  const auto refused = run_shapepress(command);
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("--resume"));

  // The same ladder run afresh on one thread (the rungs one after another, timed differently):
  // every counted cost the same, and so the pick, whatever the CPU seconds came out as.
  std::string fresh = command;
  fresh.replace(fresh.find("--threads 2"), 11, "--threads 1");
  fresh.replace(fresh.find(shell_quoted(dir / "advice")), shell_quoted(dir / "advice").size(),
                shell_quoted(dir / "again"));
  const auto repeated = run_shapepress(fresh);
  ASSERT_EQ(repeated.exit_code, 0) << repeated.output;
  const auto afresh = text_rows(dir / "again" / "advice.csv");
  ASSERT_EQ(afresh.size(), rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    EXPECT_EQ(afresh[k].at("counted_cost"), rows[k].at("counted_cost")) << rows[k].at("label");
    EXPECT_EQ(afresh[k].at("picked"), rows[k].at("picked")) << rows[k].at("label");
  }
  EXPECT_EQ(read_json(dir / "again" / "run.json").at("facts").at("pick"), facts.at("pick"));
}

// The rows of advice.csv by label: "status,cause".
std::map<std::string, std::string> statuses(const std::filesystem::path& csv) {
  std::map<std::string, std::string> out;
  std::ifstream in(csv);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line.rfind("label,", 0) == 0) continue;
    const auto first = line.find(','), second = line.find(',', first + 1);
    const auto third = line.find(',', second + 1);
    out[line.substr(0, first)] = line.substr(first + 1, third - first - 1);
  }
  return out;
}

// The stability map's points that fail (issue 21, point 3): a clump at the whole critical step
// blows up, and the run stops with exit 1 naming the cause instead of writing a NaN curve (the
// engine checks every 100 steps, and this run takes ~260: plate now checks at every row); with
// 20 sub-spheres that step resolves a collision with fewer than 10 steps and is refused (exit 2).
TEST(AdviseCli, StabilityMapDetectsTheRunsThatFail) {
  const auto dir = fresh_directory("advise_map");
  const auto r = run_shapepress("--threads 2 --quiet advise --config " + shell_quoted(shipped) +
                                " --particle cms --counts 20,100 --fractions 0.2,1 --out " +
                                shell_quoted(dir / "map"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto rows = statuses(dir / "map" / "advice.csv");
  EXPECT_EQ(rows.at("cms-100-f0.2"), "reference,-");
  EXPECT_EQ(rows.at("cms-20-f1"), "refused,refused");
  EXPECT_THAT(rows.at("cms-100-f1"), ::testing::StartsWith("diverged,"));
  EXPECT_NE(rows.at("cms-100-f1"), "diverged,failed");  // a named cause
  EXPECT_FALSE(std::filesystem::exists(dir / "map" / "cms-100-f1" / "force.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir / "map" / "stability_map.svg"));
  // The rung is the plate run itself: exit 1 and the engine's message, kept in rung.json.
  const nlohmann::json record = read_json(dir / "map" / "cms-100-f1" / "rung.json");
  EXPECT_EQ(record.at("exit_code").get<int>(), 1);
  EXPECT_THAT(record.at("message").get<std::string>(), HasSubstr("diverged at step"));
}

}  // namespace
}  // namespace shapepress
