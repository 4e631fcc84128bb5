// Every config shipped in pipelines/configs/ and pipelines/*/ read by its stage and run for a few
// steps, so that a config that no longer parses (a key renamed, a table moved, a unit refused)
// fails here and not in a user's hands. The run is the shipped file as it is, with only what sets
// its length shortened, each named in the table below: `compact --steps` (a total step count the
// stage offers) and, where a stage has no such option, the config's own end (the plate's
// max_deformation, the settle's time, the FEM's increments) set in a copy of the file.
// A config added without a row here fails EveryShippedConfigHasAShortRun.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "common/provenance.hpp"
#include "packing/body_packing.hpp"
#include "tests/support/body_beds.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using shapepress::testing::fresh_directory;
using shapepress::testing::read_text;
using shapepress::testing::repository_root;
using shapepress::testing::run_shapepress;
using shapepress::testing::shell_quoted;
using shapepress::testing::with_config_key;
using shapepress::testing::write_text;

// A key of one [table] set to a TOML value in the copy of a config.
struct Shortened {
  std::string table, key, value;
};

// What a short run needs besides its config.
enum class Input {
  none,
  bonded_bed,      // packed.h5: 4 BMS clusters in the 1 mm die of the Avicel and demo beds
  sphere_lattice,  // packing.txt ('x y z r'): 50 spheres of 1 mm in the bench's 21 mm die
  shapes,          // shapes/particle_000{0,1,2}.stl and their BMS templates.h5 (40 sub-spheres)
};

struct ShortRun {
  // The stage and its arguments; {config}, {out} and {dir} stand for the shortened copy, the
  // run's output folder and the scratch folder.
  std::string arguments;
  std::vector<Shortened> shortened;
  Input input = Input::none;
  std::string output;  // the file a finished run writes, in {out}
};

const std::string compact_steps = "compact --config {config} --steps 20 --out {out}";
const std::string compact_packed =
    "compact --config {config} --packing {dir}/packed.h5 --steps 20 --out {out}";
// A generated bed settles for 10 µs instead of the config's 30–120 ms (its pour is still made).
const Shortened short_settle{"generate", "settle_time", "\"0.01 ms\""};
// The pack's settle for 2 ms of its 0.3–0.5 s (three bodies, then pressed as the config says).
const Shortened short_pack_settle{"settle", "max_time", "\"2 ms\""};
const std::string pack_three =
    "pack {dir}/templates.h5 --config {config} --count 3 --out {out}/packed.h5";

// Keyed by the config's path under pipelines/.
const std::map<std::string, ShortRun>& short_runs() {
  static const std::map<std::string, ShortRun> runs = {
      {"configs/avicel-ph200-bms-calibrated.toml",
       {compact_packed, {}, Input::bonded_bed, "punch.csv"}},
      {"configs/avicel-ph200-bms.toml", {compact_packed, {}, Input::bonded_bed, "punch.csv"}},
      {"configs/avicel-ph200-spheres-calibrated.toml",
       {compact_steps, {short_settle}, Input::none, "punch.csv"}},
      {"configs/avicel-ph200-spheres.toml",
       {compact_steps, {short_settle}, Input::none, "punch.csv"}},
      {"configs/avicel-ph200.toml", {compact_packed, {}, Input::bonded_bed, "punch.csv"}},
      {"configs/compact-spheres.toml", {compact_steps, {short_settle}, Input::none, "punch.csv"}},
      {"configs/fem-avicel-particle.toml",
       {"fem-plate --config {config} --out {out}",
        {{"particle", "mesh", "\"{dir}/shapes/particle_0000.stl\""},
         {"plate", "max_deformation", "0.01"},
         {"fem", "increments", "1"}},
        Input::shapes,
        "force.csv"}},
      {"configs/fem-rubber-sphere.toml",
       {"fem-plate --config {config} --arc-elements 4 --coarse-arc-elements 2 --out {out}",
        {{"plate", "max_deformation", "0.02"}, {"fem", "increments", "2"}},
        Input::none,
        "force.csv"}},
      {"configs/hertz-compaction-bench.toml",
       {"compact --config {config} --packing {dir}/packing.txt --steps 20 --out {out}",
        {},
        Input::sphere_lattice,
        "punch.csv"}},
      {"configs/pack-avicel-bms-reduced.toml",
       {pack_three, {short_pack_settle}, Input::shapes, "packed.h5"}},
      {"configs/pack-avicel-bms.toml",
       {pack_three, {short_pack_settle}, Input::shapes, "packed.h5"}},
      // Past its ramp (1 % of deformation), to 1.2 %.
      {"configs/plate-avicel-bms.toml",
       {"plate --config {config} --particle bms --out {out}",
        {{"bms", "templates", "\"{dir}/templates.h5\""}, {"plate", "max_deformation", "0.012"}},
        Input::shapes,
        "force.csv"}},
      {"configs/plate-rubber-sphere-multicontact.toml",
       {"plate --config {config} --out {out}",
        {{"plate", "max_deformation", "0.002"}},
        Input::none,
        "force.csv"}},
      {"configs/plate-rubber-sphere.toml",
       {"plate --config {config} --out {out}",
        {{"plate", "max_deformation", "0.002"}},
        Input::none,
        "force.csv"}},
      // The agglomerate of 60 sub-spheres, not 545, past its ramp (10 % of deformation).
      {"configs/rubber-sphere.toml",
       {"plate --config {config} --particle bms --count 60 --out {out}",
        {{"plate", "max_deformation", "0.101"}},
        Input::none,
        "force.csv"}},
      {"demo/compact-bed-demo.toml", {compact_packed, {}, Input::bonded_bed, "punch.csv"}},
      {"demo/compact-demo.toml", {compact_steps, {short_settle}, Input::none, "punch.csv"}},
      {"demo/pack-demo.toml",
       {pack_three + " --summary {dir}/summary.json",
        {short_pack_settle},
        Input::shapes,
        "packed.h5"}},
      {"demo/plate-demo.toml",
       {"plate --config {config} --out {out}",
        {{"plate", "max_deformation", "0.002"}},
        Input::none,
        "force.csv"}},
  };
  return runs;
}

// Every .toml in pipelines/configs/ and in the folders beside it, by its path under pipelines/.
std::vector<std::string> shipped_configs() {
  const fs::path pipelines = repository_root() / "pipelines";
  std::vector<std::string> configs;
  for (const auto& folder : fs::directory_iterator(pipelines)) {
    if (!folder.is_directory()) continue;
    for (const auto& file : fs::directory_iterator(folder.path()))
      if (file.path().extension() == ".toml")
        configs.push_back(fs::relative(file.path(), pipelines).generic_string());
  }
  std::sort(configs.begin(), configs.end());
  return configs;
}

std::string replaced_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at))
    text.replace(at, from.size(), to), at += to.size();
  return text;
}

void make_input(Input input, const fs::path& dir) {
  switch (input) {
    case Input::none:
      return;
    case Input::bonded_bed: {
      // Sub-spheres of 1/14 mm: two clusters (7 radii each) span the die.
      const packing::BodyPacking bed =
          shapepress::testing::cluster_bed(packing::BodyKind::bms, 1e-3 / 14.0, 2, 1, 7);
      packing::write_packing(dir / "packed.h5", bed, Provenance{"test", "", 7});
      return;
    }
    case Input::sphere_lattice: {
      std::ofstream out(dir / "packing.txt");
      for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 5; ++j)
          for (int i = 0; i < 5; ++i)
            out << 1.05e-3 * (i + 0.5) << ' ' << 1.05e-3 * (j + 0.5) << ' ' << 1.05e-3 * (k + 0.5)
                << " 0.5e-3\n";
      return;
    }
    case Input::shapes: {
      auto r = run_shapepress("--quiet generate --targets " + std::string(SHAPEPRESS_TEST_DATA) +
                              "/geometry/avicel_ph200_projected.toml --count 3 --seed 7 --out " +
                              shell_quoted(dir / "shapes"));
      ASSERT_EQ(r.exit_code, 0) << r.output;
      r = run_shapepress("--quiet fill " + shell_quoted(dir / "shapes") +
                         "/particle_000*.stl --kind bms --count 40 --lattice random --out " +
                         shell_quoted(dir / "templates.h5"));
      ASSERT_EQ(r.exit_code, 0) << r.output;
      // pack --summary: the sizes a shape-stats summary states (the demo's pack reads its
      // images'), Q3's x10/x50/x90 of a powder of a few hundred µm.
      write_text(dir / "summary.json",
                 R"json({"format": "shapepress shape-stats summary 1", "size": {"basis":
                 "volume (Q3)", "x10_m": 180e-6, "x50_m": 250e-6, "x90_m": 350e-6}})json");
      return;
    }
  }
}

class ShippedConfig : public ::testing::TestWithParam<std::string> {};

TEST_P(ShippedConfig, ReadByItsStageAndRunsAFewSteps) {
  const std::string name = GetParam();
  const auto row = short_runs().find(name);
  ASSERT_NE(row, short_runs().end()) << name << ": no short run in this test's table";
  const ShortRun& run = row->second;
  const fs::path dir = fresh_directory("shipped_config");
  make_input(run.input, dir);
  std::string text = read_text(repository_root() / "pipelines" / name);
  for (const Shortened& s : run.shortened)
    text = with_config_key(text, s.table, s.key, replaced_all(s.value, "{dir}", dir.string()));
  const fs::path config = dir / fs::path(name).filename();
  write_text(config, text);
  std::string arguments = replaced_all(run.arguments, "{config}", shell_quoted(config));
  arguments = replaced_all(arguments, "{out}", shell_quoted(dir / "run"));
  arguments = replaced_all(arguments, "{dir}", dir.string());
  const auto result = run_shapepress("--quiet " + arguments);
  ASSERT_EQ(result.exit_code, 0) << "shapepress " << arguments << "\n" << result.output;
  EXPECT_TRUE(fs::exists(dir / "run" / run.output)) << result.output;
}

INSTANTIATE_TEST_SUITE_P(Pipelines, ShippedConfig, ::testing::ValuesIn(shipped_configs()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string id = info.param.substr(0, info.param.size() - 5);
                           for (char& c : id)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return id;
                         });

// The table has a row for every shipped config and none for a config that is gone.
TEST(ShippedConfigs, EveryShippedConfigHasAShortRun) {
  const std::vector<std::string> shipped = shipped_configs();
  EXPECT_GE(shipped.size(), 19u);
  for (const std::string& name : shipped)
    EXPECT_TRUE(short_runs().contains(name)) << name << ": add its short run to this test";
  for (const auto& [name, run] : short_runs())
    EXPECT_NE(std::find(shipped.begin(), shipped.end(), name), shipped.end())
        << name << " is no longer shipped: remove its row";
}

}  // namespace
}  // namespace shapepress
