// `shapepress advise` on a compaction config as a user runs it (issue 21, points 2 and 3): a
// bed's templates re-filled at two sub-sphere counts and re-packed with one seed, each reduced
// bed pressed at two time-step fractions, one of which blows up. The pick, the table, the charts
// and the predicted cost land in the folder; a diverged rung is exit 1 of its own run with a
// named cause and no curve; a resumed advise re-runs nothing.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "packing/body_packing.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::run_shapepress;
using shapepress::testing::shell_quoted;
using shapepress::testing::test_data_text;
using shapepress::testing::write_text;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// advice.csv's rows by label: "status,cause".
std::map<std::string, std::string> statuses(const fs::path& csv) {
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

// A pack config of 12 Avicel-like ellipsoids of 250-350 µm (Table 2's distribution cut there)
// in a 0.8 mm die, settled without pre-compression, of which advise packs 10; Table 4's
// parameters (tests/data), pressed by 30 % at 0.05 m/s with mass scaling 100 (a run of
// seconds) and unloaded.
struct Bed {
  fs::path templates, pack_config, compact_config;
};

Bed tiny_bed(const fs::path& dir) {
  Bed bed{dir / "templates.h5", dir / "pack.toml", dir / "compact.toml"};
  const auto fill = run_shapepress(
      "--quiet fill --ellipsoid 150um,125um,110um --kind bms "
      "--count 20 --lattice random --out " +
      shell_quoted(bed.templates));
  EXPECT_EQ(fill.exit_code, 0) << fill.output;
  write_text(bed.pack_config,
             "[pack]\ncount = 12\nseed = 3\nbox_x = 0.8e-3\nbox_y = 0.8e-3\n"
             "[[template]]\nname = \"bms/ellipsoid\"\n"
             "[sizes]\nsize_quantiles = [82.9e-6, 224.6e-6, 379.3e-6]\n"
             "size_quantile_levels = [0.1, 0.5, 0.9]\n"
             "diameter_min = 250e-6\ndiameter_max = 350e-6\n"
             "[settle]\nkinetic_energy_ratio = 1e-4\n");
  write_text(bed.compact_config, test_data_text("scenarios/bonded-bed.toml") +
                                     "\n[box]\nx = \"0.8 mm\"\ny = \"0.8 mm\"\nbottom = \"0 mm\"\n"
                                     "\n[run]\nrecord_every = 100\ndensity_scale = 100\n"
                                     "\n[punch]\nmode = \"displacement\"\nspeed = \"0.05 m/s\"\n"
                                     "target_strain = 0.3\nunload_speed = \"0.05 m/s\"\n");
  return bed;
}

// advice.csv's row of `label` as fields.
std::vector<std::string> advice_fields(const fs::path& csv, const std::string& label) {
  std::ifstream in(csv);
  std::vector<std::string> fields;
  for (std::string line; std::getline(in, line);)
    if (line.rfind(label + ",", 0) == 0) {
      std::istringstream row(line);
      for (std::string cell; std::getline(row, cell, ',');)
        fields.push_back(cell);
    }
  return fields;
}

// advice.csv's row of `label` from its counted cost on but for its CPU seconds: what it cost by
// count and what it measured against the reference.
std::string judged_fields(const fs::path& csv, const std::string& label) {
  std::vector<std::string> fields = advice_fields(csv, label);
  if (fields.size() < 9) return "(no row " + label + ")";
  fields.erase(fields.begin() + 8);  // cpu_s
  std::string judged;
  for (std::size_t k = 7; k < fields.size(); ++k)
    judged += fields[k] + ",";
  return judged;
}

// The counted_cost cell of `label`'s row.
std::string counted_cost(const fs::path& csv, const std::string& label) {
  const std::vector<std::string> fields = advice_fields(csv, label);
  return fields.size() > 7 ? fields[7] : "(no row " + label + ")";
}

TEST(AdviseCompactionCli, RefillsRepacksPressesAndPicksAndAResumedAdviseRerunsNothing) {
  const fs::path dir = fresh_directory("advise_compaction");
  const Bed bed = tiny_bed(dir);
  const fs::path out = dir / "advice";
  // 0.7 of the critical step blows these beds up (energy from nowhere within 800 steps).
  const std::string command =
      "--threads 2 --quiet advise --config " + shell_quoted(bed.compact_config) + " --templates " +
      shell_quoted(bed.templates) + " --pack-config " + shell_quoted(bed.pack_config) +
      " --counts 20,30 --fractions 0.2,0.7 --bodies 10 --full-bodies 20 --tolerance 0.3 "
      "--out " +
      shell_quoted(out);
  const auto first = run_shapepress(command);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const nlohmann::json facts = read_json(out / "run.json").at("facts");
  EXPECT_EQ(facts.at("rungs").get<int>(), 4);
  EXPECT_EQ(facts.at("rungs_run").get<int>(), 4);
  EXPECT_EQ(facts.at("beds_made").get<int>(), 2);
  EXPECT_EQ(facts.at("reference").get<std::string>(), "bms-30-f0.2-s100");
  // The full run, twice the bodies in the same die: twice the work per step, twice the steps.
  EXPECT_NEAR(facts.at("predicted_full_run_cpu_s").get<double>(),
              4.0 * facts.at("pick_cpu_s").get<double>(), 1e-9);
  // The pick goes by the counted cost (its rung's run.json's), scaled the same way; the CPU
  // seconds are beside it.
  const auto pick_cost = facts.at("pick_counted_cost").get<std::int64_t>();
  EXPECT_EQ(pick_cost, read_json(out / facts.at("pick").get<std::string>() / "run.json")
                           .at("facts")
                           .at("counted_cost")
                           .get<std::int64_t>());
  EXPECT_EQ(facts.at("predicted_full_run_counted_cost").get<double>(), 4.0 * pick_cost);
  EXPECT_NEAR(facts.at("cost_saved_factor").get<double>(),
              facts.at("reference_counted_cost").get<double>() / pick_cost, 1e-12);
  EXPECT_TRUE(facts.contains("cpu_saved_factor"));
  EXPECT_EQ(counted_cost(out / "advice.csv", facts.at("pick").get<std::string>()),
            std::to_string(pick_cost));
  for (const char* chart : {"speed_accuracy.svg", "stability_map.svg"})
    EXPECT_TRUE(fs::exists(out / chart)) << chart;

  // The beds are the same bodies (template and size drawn from the one seed), each re-filled at
  // its own count.
  const packing::BodyPacking coarse = packing::read_packing(out / "bed-20" / "packed.h5");
  const packing::BodyPacking fine = packing::read_packing(out / "bed-30" / "packed.h5");
  ASSERT_EQ(coarse.bodies.size(), 10u);
  ASSERT_EQ(fine.bodies.size(), 10u);
  for (std::size_t b = 0; b < coarse.bodies.size(); ++b)
    EXPECT_DOUBLE_EQ(coarse.bodies[b].scale, fine.bodies[b].scale) << "body " << b;
  EXPECT_GT(fine.particles.size(), coarse.particles.size());

  // The diverged rungs: exit 1 of their own compact run with the engine's named cause, on the
  // map as diverged, and no curve compared.
  const auto rows = statuses(out / "advice.csv");
  EXPECT_EQ(rows.at("bms-30-f0.2-s100"), "reference,-");
  for (const char* label : {"bms-20-f0.7-s100", "bms-30-f0.7-s100"}) {
    EXPECT_THAT(rows.at(label), ::testing::StartsWith("diverged,")) << label;
    EXPECT_NE(rows.at(label), "diverged,failed") << label;  // a named cause
    const nlohmann::json record = read_json(out / label / "rung.json");
    EXPECT_EQ(record.at("exit_code").get<int>(), 1) << label;
    EXPECT_THAT(record.at("message").get<std::string>(), HasSubstr("diverged at step"));
    EXPECT_EQ(counted_cost(out / "advice.csv", label), "nan") << label;  // never the pick
  }
  const auto stamp = fs::last_write_time(out / "bms-20-f0.2-s100" / "punch.csv");

  // Again with --resume: no bed made, no rung run, the same pick.
  const auto again = run_shapepress(command + " --resume");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  const nlohmann::json resumed = read_json(out / "run.json").at("facts");
  EXPECT_EQ(resumed.at("rungs_run").get<int>(), 0);
  EXPECT_EQ(resumed.at("beds_made").get<int>(), 0);
  EXPECT_EQ(resumed.at("pick"), facts.at("pick"));
  EXPECT_EQ(fs::last_write_time(out / "bms-20-f0.2-s100" / "punch.csv"), stamp);

  // Without --resume finished work is refused, not overwritten.
  const auto refused = run_shapepress(command);
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("--resume"));
}

// A finest run made outside the ladder (a full study's) stands in for the rung it is: the ladder
// judged against it says what it says against that rung run by advise itself. A run of another
// bed or config is refused, naming what differs; with nothing within the tolerance its setting is
// the pick, at its run.json's counted cost and of no stated CPU seconds.
TEST(AdviseCompactionCli, AGivenReferenceRunJudgesTheLadderAsItsOwnRungWould) {
  const fs::path dir = fresh_directory("advise_compaction_reference");
  const Bed bed = tiny_bed(dir);
  const std::string ladder = "--threads 2 --quiet advise --config " +
                             shell_quoted(bed.compact_config) + " --templates " +
                             shell_quoted(bed.templates) + " --pack-config " +
                             shell_quoted(bed.pack_config) + " --fractions 0.2";
  const auto both = run_shapepress(ladder + " --tolerance 0.3 --counts 20,30 --bodies 10 --out " +
                                   shell_quoted(dir / "both"));
  ASSERT_EQ(both.exit_code, 0) << both.output;
  const fs::path given = dir / "both" / "bms-30-f0.2-s100";

  const std::string coarse = ladder + " --counts 20 --bodies 10 --reference-run " +
                             shell_quoted(given) + " --out " + shell_quoted(dir / "coarse");
  const auto r = run_shapepress(coarse + " --tolerance 0.3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json facts = read_json(dir / "coarse" / "run.json").at("facts");
  EXPECT_EQ(facts.at("reference").get<std::string>(), "given-bms-30-f0.2-s100");
  EXPECT_EQ(facts.at("rungs_run").get<int>(), 1);
  EXPECT_FALSE(facts.contains("reference_cpu_s"));
  EXPECT_EQ(facts.at("reference_counted_cost").get<std::int64_t>(),
            read_json(given / "run.json").at("facts").at("counted_cost").get<std::int64_t>());
  EXPECT_EQ(judged_fields(dir / "coarse" / "advice.csv", "bms-20-f0.2-s100"),
            judged_fields(dir / "both" / "advice.csv", "bms-20-f0.2-s100"));
  EXPECT_EQ(statuses(dir / "coarse" / "advice.csv").at("given-bms-30-f0.2-s100"), "reference,-");
  // The report draws a bed's ladder from the advise folder.
  const auto report = run_shapepress("--quiet report --advice " + shell_quoted(dir / "coarse") +
                                     " --out " + shell_quoted(dir / "report"));
  ASSERT_EQ(report.exit_code, 0) << report.output;
  for (const char* chart : {"bed_speed_accuracy.svg", "stability_map.svg"})
    EXPECT_TRUE(fs::exists(dir / "report" / chart)) << chart;
  const nlohmann::json advice = read_json(dir / "report" / "metrics.json").at("advice").at(0);
  EXPECT_EQ(advice.at("reference").get<std::string>(), "given-bms-30-f0.2-s100");
  EXPECT_EQ(advice.at("rungs").size(), 2u);

  // Nothing within 0 %: the given run's setting, its counted cost predicted, no CPU seconds.
  const auto strict = run_shapepress(coarse + " --resume --tolerance 0");
  ASSERT_EQ(strict.exit_code, 0) << strict.output;
  const nlohmann::json picked = read_json(dir / "coarse" / "run.json").at("facts");
  EXPECT_EQ(picked.at("pick").get<std::string>(), "given-bms-30-f0.2-s100");
  EXPECT_EQ(picked.at("rungs_run").get<int>(), 0);
  EXPECT_FALSE(picked.contains("predicted_full_run_cpu_s"));
  EXPECT_EQ(picked.at("pick_counted_cost"), facts.at("reference_counted_cost"));

  // Another bed (8 bodies) is refused before anything runs.
  const auto fewer = run_shapepress(ladder + " --counts 20 --bodies 8 --reference-run " +
                                    shell_quoted(given) + " --out " + shell_quoted(dir / "fewer"));
  EXPECT_EQ(fewer.exit_code, 2) << fewer.output;
  EXPECT_THAT(fewer.output, HasSubstr("10 bodies, against the ladder's 8"));
  EXPECT_FALSE(fs::exists(dir / "fewer" / "bed-20"));

  // A setting the ladder runs itself is refused before anything runs.
  const auto twice = run_shapepress(ladder + " --counts 20,30 --bodies 10 --reference-run " +
                                    shell_quoted(given) + " --out " + shell_quoted(dir / "twice"));
  EXPECT_EQ(twice.exit_code, 2) << twice.output;
  EXPECT_THAT(twice.output, HasSubstr("the ladder runs its setting itself"));
  EXPECT_FALSE(fs::exists(dir / "twice" / "bed-20"));

  // Another contact law: refused, naming the line.
  const fs::path other = dir / "other-friction";
  fs::copy(given, other);
  std::ifstream in(other / "effective.toml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = text.find("sliding_friction = ");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, text.find('\n', at) - at, "sliding_friction = 0.9");
  write_text(other / "effective.toml", text);
  const auto differs =
      run_shapepress(ladder + " --counts 20 --bodies 10 --resume --reference-run " +
                     shell_quoted(other) + " --out " + shell_quoted(dir / "coarse"));
  EXPECT_EQ(differs.exit_code, 2) << differs.output;
  EXPECT_THAT(differs.output, HasSubstr("pressed by another config"));
  EXPECT_THAT(differs.output, HasSubstr("sliding_friction = 0.9"));
}

TEST(AdviseCompactionCli, RefusesACompactionConfigWithoutItsBed) {
  const fs::path dir = fresh_directory("advise_compaction_bad");
  write_text(dir / "compact.toml",
             test_data_text("scenarios/bonded-bed.toml") +
                 "\n[box]\nx = \"0.8 mm\"\ny = \"0.8 mm\"\n\n[punch]\nmode = \"displacement\"\n"
                 "speed = \"0.05 m/s\"\ntarget_strain = 0.3\n");
  const auto r = run_shapepress("--quiet advise --config " + shell_quoted(dir / "compact.toml") +
                                " --counts 20 --out " + shell_quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--templates"));
}

}  // namespace
}  // namespace shapepress
