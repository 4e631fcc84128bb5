// The Avicel PH 200 study (pipelines/avicel-ph200/Makefile) reduced to what runs in the default
// suite: synthetic SEM images → shape-stats → generate → three shape classes → fill → pack →
// compact (BMS beds and the spheres) → report. Every stage's output is consumed by the next (each
// run.json names its inputs by content hash, and the hashes chain from the images to the report),
// a second `make` has nothing to do, and a `make` after a killed one resumes the killed run.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "common/sha256.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using shapepress::testing::fresh_directory;
using shapepress::testing::repository_root;
using shapepress::testing::run_command;
using shapepress::testing::shell_quoted;

nlohmann::json run_json(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  return nlohmann::json::parse(in);
}

// The SHA-256 run.json records for the input of `role` (the first such).
std::string input_hash(const nlohmann::json& record, const std::string& role) {
  for (const auto& input : record["inputs"])
    if (input["role"] == role) return input["sha256"].get<std::string>();
  return {};
}

// The rows of a CSV with text cells (report's beds.csv, describe's table; '#' lines skipped),
// each row's cells by column name.
std::vector<std::map<std::string, std::string>> csv_rows(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  const auto cells = [](const std::string& line) {
    std::vector<std::string> out(1);
    for (char c : line) {
      if (c == ',')
        out.emplace_back();
      else
        out.back().push_back(c);
    }
    return out;
  };
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> row = cells(line);
    if (header.empty()) {
      header = row;
      continue;
    }
    EXPECT_EQ(row.size(), header.size()) << line;
    auto& named = rows.emplace_back();
    for (std::size_t k = 0; k < std::min(row.size(), header.size()); ++k)
      named[header[k]] = row[k];
  }
  return rows;
}

// report's beds.csv by the runs' labels: every run is pressed with the study's one config (the
// Makefile's copy for DENSITY_SCALE=10000, avicel_study_config-s10000.toml), so a label is that
// config and the bed ("avicel_study_config-s10000: 12 spheres"), and the three beds of 12 BMS
// bodies of 40 sub-spheres are told apart by their folders ("… (asr071/run)"), by which they
// are keyed here.
std::map<std::string, std::map<std::string, std::string>> beds_table(const fs::path& path) {
  std::map<std::string, std::map<std::string, std::string>> table;
  for (auto& row : csv_rows(path)) {
    const std::string& label = row["label"];
    EXPECT_TRUE(label.starts_with("avicel_study_config-s10000: ")) << label;
    const std::size_t open = label.rfind(" (");
    table[open == std::string::npos ? label : label.substr(open + 2, label.size() - open - 3)] =
        row;
  }
  return table;
}

// The projected aspect ratio `describe` measures on a mesh (its table's projected_asr_mean).
double mesh_aspect_ratio(const fs::path& mesh, const fs::path& csv) {
  const auto described = shapepress::testing::run_shapepress(
      "--quiet describe " + shell_quoted(mesh) + " --out " + shell_quoted(csv));
  EXPECT_EQ(described.exit_code, 0) << described.output;
  const auto rows = csv_rows(csv);
  return rows.empty() ? 0.0 : std::stod(rows.front().at("projected_asr_mean"));
}

TEST(AvicelStudy, ReducedStudyRunsFromImagesToTheReportAndAKilledMakeResumes) {
  const fs::path out = fresh_directory("avicel_study");
  // The study's configs and describe's tables beside it, in a folder of their own: not in the
  // shared temporary folder, where a second run of the suite would overwrite them mid-run.
  const fs::path inputs = fresh_directory("avicel_study_inputs");
  // Twelve bodies lie in one layer of the 1 mm die: rigid, they cannot be pressed to 0.59, so
  // the reduced study packs them settled only (the shipped config without its [press]).
  std::string pack_config = shapepress::testing::read_text(repository_root() / "pipelines" /
                                                           "configs" / "pack-avicel-bms.toml");
  pack_config.erase(pack_config.find("[press]"));
  shapepress::testing::write_text(inputs / "avicel_study_pack.toml", pack_config);
  // Mass-scaled 10⁴ times a run is a few thousand steps: a record every 50 leaves the report's
  // Heckel and Kawakita fits enough points. The study's one config, for the spheres and the
  // shapes alike.
  std::string text = shapepress::testing::read_text(repository_root() / "pipelines" / "configs" /
                                                    "avicel-ph200.toml");
  const std::size_t at = text.find("record_every = ");
  text.replace(at, text.find('\n', at) - at, "record_every = 50\ncheckpoint_every = 500");
  // One layer of twelve bodies (0.17 dense) is pressed to 0.35, not to the study's 0.76: its bodies
  // would have to be crushed to a third of their height.
  const std::size_t endpoint = text.find("target_solid_fraction = ");
  text.replace(endpoint, text.find('\n', endpoint) - endpoint, "target_solid_fraction = 0.35");
  const fs::path study_config = inputs / "avicel_study_config.toml";
  shapepress::testing::write_text(study_config, text);
  const std::string study =
      "make -s -C " + shell_quoted(repository_root() / "pipelines" / "avicel-ph200") +
      " SHAPEPRESS=" + shell_quoted(SHAPEPRESS_BINARY) + " OUT=" + shell_quoted(out) +
      " PACK_CONFIG=" + shell_quoted(inputs / "avicel_study_pack.toml") +
      " STUDY_CONFIG=" + shell_quoted(study_config) +
      " BODIES=12 SUBSPHERES=40 POPULATION=6 DENSITY_SCALE=10000 THREADS=2";
  const auto first = run_command(study + " -j2");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_TRUE(fs::exists(out / "report" / "report.html"));

  // Images → statistics → shapes → the three classes → templates → beds → runs → report.
  const auto stats = run_json(out / "stats" / "run.json");
  const auto shapes = run_json(out / "shapes" / "run.json");
  EXPECT_EQ(input_hash(shapes, "targets"), sha256_file(out / "stats" / "summary.json"));
  // One material: every bed, spheres and shapes, packed by the same protocol and pressed with the
  // same config, whose effective config states the same loading modulus and no k1 of its own.
  std::string material;
  for (const std::string c : {"spheres", "asr084", "asr071", "asr053"}) {
    SCOPED_TRACE(c);
    const auto pack = run_json(out / c / "packed.h5.run.json");
    if (c != "spheres") {
      EXPECT_EQ(input_hash(pack, "templates"), sha256_file(out / c / "templates.h5"));
    }
    EXPECT_EQ(input_hash(pack, "summary"), sha256_file(out / "stats" / "summary.json"));
    EXPECT_EQ(pack["facts"]["bodies"], 12);
    const auto compact = run_json(out / c / "run" / "run.json");
    EXPECT_EQ(input_hash(compact, "packing"), sha256_file(out / c / "packed.h5"));
    EXPECT_EQ(compact["facts"]["particle_kind"], c == "spheres" ? "sphere" : "bms");
    EXPECT_EQ(compact["facts"]["density_scale"], 10000.0);
    EXPECT_EQ(input_hash(compact, "config"),
              input_hash(run_json(out / "asr071" / "run" / "run.json"), "config"));
    const std::string effective =
        shapepress::testing::read_text(out / c / "run" / "effective.toml");
    EXPECT_THAT(effective, ::testing::HasSubstr("\nloading_modulus = 1390000000\n"));
    EXPECT_THAT(effective, ::testing::Not(::testing::HasSubstr("loading_stiffness")));
    EXPECT_THAT(effective, ::testing::HasSubstr("\nmodulus_fraction = "));
    const std::size_t materials = effective.find("[[material]]");
    const std::string first_material =
        effective.substr(materials, effective.find("[[interaction]]") - materials);
    if (material.empty()) material = first_material;
    EXPECT_EQ(first_material, material);
    EXPECT_EQ(compact["facts"]["strain_reference"], "solid_fraction");
  }
  EXPECT_FALSE(stats["inputs"].empty());
  const auto report = run_json(out / "report" / "run.json");
  int runs = 0;
  for (const auto& input : report["inputs"])
    if (input["path"].get<std::string>().ends_with("punch.csv")) ++runs;
  EXPECT_EQ(runs, 4);  // three shapes and the spheres

  // The table of beds follows each run to its pack and measures its bodies: the settled solid
  // fraction and the loops' wall seconds of each, and bodies as elongated as the class's mesh.
  auto beds = beds_table(out / "report" / "beds.csv");
  ASSERT_EQ(beds.size(), 4u);
  const std::string spheres = "avicel_study_config-s10000: 12 spheres";
  ASSERT_TRUE(beds.contains(spheres));
  EXPECT_EQ(beds[spheres]["particle_kind"], "sphere");
  EXPECT_EQ(beds[spheres]["projected_aspect_ratio"], "1");
  for (const std::string c : {"asr084", "asr071", "asr053"}) {
    SCOPED_TRACE(c);
    auto& row = beds[c + "/run"];
    EXPECT_EQ(row["particle_kind"], "bms");
    EXPECT_EQ(row["bodies"], "12");
    EXPECT_EQ(row["sub_spheres_per_body"], "40");
    EXPECT_GT(std::stod(row["settled_solid_fraction_percent"]), 10.0);  // by body volume
    EXPECT_LT(std::stod(row["settled_solid_fraction_percent"]), 70.0);
    EXPECT_EQ(row["precompression_solid_fraction_percent"], "");  // settled only
    EXPECT_GT(std::stod(row["pack_wall_s"]), 0.0);
    EXPECT_GT(std::stod(row["compaction_wall_s"]), 0.0);
    const double mesh =
        mesh_aspect_ratio(out / "classes" / (c + ".stl"), inputs / ("avicel_study_" + c + ".csv"));
    EXPECT_NEAR(std::stod(row["projected_aspect_ratio"]), mesh, 0.05) << "mesh " << mesh;
  }
  EXPECT_TRUE(fs::exists(out / "report" / "shape_effect_peak_stress.svg"));

  // Nothing is out of date: `make -q` exits 0 only when no rule would run.
  const auto again = run_command(study + " -q");
  EXPECT_EQ(again.exit_code, 0) << again.output;

  // A run deleted to redo it is run again, and a study killed in a compaction continues it: the
  // next `make` resumes the killed run from its checkpoint, ends with the uninterrupted curve,
  // and makes the report again.
  const fs::path run = out / "asr071" / "run";
  const std::string uninterrupted = shapepress::testing::read_text(run / "punch.csv");
  fs::remove_all(run);
  // make in its own process group (setsid), killed with its compaction at the first checkpoint
  const auto killed = run_command("(setsid " + study + " " + shell_quoted(run / "punch.csv") +
                                  " & pid=$!; while ! ls " + shell_quoted(run / "checkpoints") +
                                  "/step_*.h5 >/dev/null 2>&1 && kill -0 $pid 2>/dev/null;"
                                  " do sleep 0.05; done; kill -KILL -$pid; wait $pid)");
  ASSERT_FALSE(fs::exists(run / "punch.csv")) << killed.output;
  ASSERT_TRUE(fs::exists(run / "checkpoints" / "resume.json")) << killed.output;
  const auto resumed = run_command(study);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_THAT(resumed.output, ::testing::HasSubstr("resuming the killed run from " +
                                                   (run / "checkpoints").string()));
  EXPECT_EQ(shapepress::testing::read_text(run / "punch.csv"), uninterrupted);
  EXPECT_GT(fs::last_write_time(out / "report" / "report.html"),
            fs::last_write_time(run / "punch.csv"));
  // The resumed run states its whole loop's wall seconds, the part before the kill included.
  EXPECT_GT(std::stod(beds_table(out / "report" / "beds.csv")["asr071/run"]["compaction_wall_s"]),
            0.0);
}

}  // namespace
}  // namespace shapepress
