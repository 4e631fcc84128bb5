// Reading run folders: the synthetic runs in tests/data/analysis (make_synthetic_runs.py).
#include "analysis/runs.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include "common/error.hpp"
#include "common/run_metadata.hpp"
#include "tests/support/errors.hpp"
#include "tests/support/files.hpp"

namespace shapepress::analysis {
namespace {

const std::filesystem::path data = std::filesystem::path(SHAPEPRESS_TEST_DATA) / "analysis";

using testing::input_error_of;

TEST(Runs, FindsTheKindOfRunAndItsProvenanceComments) {
  const RunFiles compaction = find_run(data / "compaction_run");
  EXPECT_EQ(compaction.kind, RunKind::compaction);
  EXPECT_EQ(compaction.csv.filename(), "punch.csv");
  ASSERT_EQ(compaction.comments.size(), 3u);
  EXPECT_EQ(compaction.comments[2], "phase: 0 load, 1 hold, 2 unload, 3 done");
  EXPECT_EQ(find_run(data / "plate_run").kind, RunKind::plate);
}

TEST(Runs, ReadsAPunchCurveWithH0AndDieAreaFromTheComment) {
  const PunchCurve c = read_punch_curve(data / "compaction_run" / "punch.csv");
  // H0 = solid height / D(P = 0) = 4 mm / (1 − e^{−0.5}), written with 10 digits.
  EXPECT_NEAR(c.reference_gap, 4e-3 / (1 - std::exp(-0.5)), 1e-12);
  EXPECT_DOUBLE_EQ(c.die_area, 1e-4);
  ASSERT_EQ(c.gap.size(), 101u + 5u + 20u);
  EXPECT_EQ(c.phase.front(), 0);
  EXPECT_EQ(c.phase.back(), 3);
  EXPECT_DOUBLE_EQ(c.stress[100], 100e6);
}

TEST(Runs, ErrorsNameTheFolderFileAndColumn) {
  EXPECT_NE(input_error_of([] { find_run(data / "no_such_run"); }).find("no_such_run"),
            std::string::npos);
  const std::string empty = input_error_of([] { find_run(data); });  // a folder without CSVs
  EXPECT_NE(empty.find("punch.csv"), std::string::npos) << empty;
  const std::string missing =
      input_error_of([] { read_punch_curve(data / "bad_run" / "punch.csv"); });
  EXPECT_NE(missing.find("bad_run/punch.csv"), std::string::npos) << missing;
  EXPECT_NE(missing.find("stress_Pa"), std::string::npos) << missing;
  const std::string no_force =
      input_error_of([] { read_plate_curve(data / "compaction_run" / "punch.csv"); });
  EXPECT_NE(no_force.find("deformation"), std::string::npos) << no_force;
}

TEST(Runs, APunchCsvWithoutTheH0CommentIsRejected) {
  const auto folder = shapepress::testing::fresh_directory("analysis_runs");
  {
    std::ofstream out(folder / "punch.csv");
    out << "time_s,gap_m,top_force_N,stress_Pa,solid_fraction,phase\n"
           "0,0.01,0,0,0.5,0\n0,0.009,1,1e4,0.55,0\n0,0.008,2,2e4,0.6,0\n";
  }
  const std::string message = input_error_of([&] { read_punch_curve(folder / "punch.csv"); });
  EXPECT_NE(message.find("H0"), std::string::npos) << message;
  std::filesystem::remove_all(folder);
}

// A copy of a synthetic run folder, its CSV's comment lines replaced and its run.json edited.
std::filesystem::path edited_copy(const std::string& run, const std::string& csv,
                                  const std::function<void(nlohmann::json&)>& edit) {
  const auto folder = shapepress::testing::fresh_directory("runs_" + run);
  std::ifstream in(data / run / csv);
  std::ofstream out(folder / csv);
  out << "# reworded for people: nothing here says H0, die area, sub_spheres or fills\n";
  for (std::string line; std::getline(in, line);)
    if (!line.starts_with("#")) out << line << "\n";
  std::ifstream json(data / run / "run.json");
  nlohmann::json record = nlohmann::json::parse(json);
  edit(record);
  std::ofstream(folder / "run.json") << record.dump(2);
  return folder;
}

TEST(Runs, FactsComeFromRunJsonNotTheCommentLines) {
  const auto compaction = edited_copy("compaction_run", "punch.csv", [](nlohmann::json& j) {
    j["facts"]["reference_gap_m"] = 0.0125;
    j["facts"]["die_area_m2"] = 2e-4;
  });
  const PunchCurve c = read_punch_curve(compaction / "punch.csv");
  EXPECT_DOUBLE_EQ(c.reference_gap, 0.0125);
  EXPECT_DOUBLE_EQ(c.die_area, 2e-4);
  const auto plate = edited_copy("plate_run", "force.csv", [](nlohmann::json& j) {
    j["facts"]["particle_kind"] = "bms";
    j["facts"]["sub_spheres"] = 545;
  });
  const PlateCurve p = read_plate_curve(plate / "force.csv");
  EXPECT_EQ(p.particle, "bms");
  EXPECT_EQ(p.sub_spheres, 545);
  EXPECT_EQ(p.fills, 1);
  const PlateCurve synthetic = read_plate_curve(data / "plate_run" / "force.csv");
  EXPECT_EQ(synthetic.particle, "sphere");
  EXPECT_EQ(synthetic.sub_spheres, 1);
  std::filesystem::remove_all(compaction);
  std::filesystem::remove_all(plate);
}

TEST(Runs, ARunJsonWithoutAFactIsRejectedNamingTheKey) {
  for (const char* key : {"reference_gap_m", "die_area_m2"}) {
    const auto folder = edited_copy("compaction_run", "punch.csv",
                                    [&](nlohmann::json& j) { j["facts"].erase(key); });
    const std::string message = input_error_of([&] { read_punch_curve(folder / "punch.csv"); });
    EXPECT_NE(message.find("run.json"), std::string::npos) << message;
    EXPECT_NE(message.find(key), std::string::npos) << message;
    std::filesystem::remove_all(folder);
  }
  for (const char* key : {"particle_kind", "sub_spheres", "fills"}) {
    const auto folder =
        edited_copy("plate_run", "force.csv", [&](nlohmann::json& j) { j["facts"].erase(key); });
    const std::string message = input_error_of([&] { read_plate_curve(folder / "force.csv"); });
    EXPECT_NE(message.find("run.json"), std::string::npos) << message;
    EXPECT_NE(message.find(key), std::string::npos) << message;
    std::filesystem::remove_all(folder);
  }
  // A number written as text is not read as a number.
  const auto text = edited_copy("compaction_run", "punch.csv",
                                [](nlohmann::json& j) { j["facts"]["reference_gap_m"] = "0.01"; });
  EXPECT_NE(input_error_of([&] { read_punch_curve(text / "punch.csv"); }).find("reference_gap_m"),
            std::string::npos);
  std::filesystem::remove_all(text);
}

TEST(Runs, AFolderWithoutRunJsonOrFromAnotherStageIsAnError) {
  const auto folder = edited_copy("compaction_run", "punch.csv", [](nlohmann::json&) {});
  std::filesystem::remove(folder / "run.json");
  const std::string missing = input_error_of([&] { find_run(folder); });
  EXPECT_NE(missing.find(folder.string()), std::string::npos) << missing;
  EXPECT_NE(missing.find("run.json"), std::string::npos) << missing;
  const auto plate =
      edited_copy("plate_run", "force.csv", [](nlohmann::json& j) { j["stage"] = "compact"; });
  const std::string stage = input_error_of([&] { find_run(plate); });
  EXPECT_NE(stage.find("stage \"compact\""), std::string::npos) << stage;
  EXPECT_NE(stage.find("force.csv"), std::string::npos) << stage;
  std::filesystem::remove_all(folder);
  std::filesystem::remove_all(plate);
}

}  // namespace
}  // namespace shapepress::analysis
