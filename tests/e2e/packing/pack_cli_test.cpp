// `shapepress pack` as a user runs it: fill → pack on a small templates file, the packed.h5 the
// reader accepts with its measures and run.json, and bad input (exit 2, the cause named, no
// file left under the final name).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "geometry/templates_file.hpp"
#include "packing/body_packing.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress::packing {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::read_text;
using shapepress::testing::run_shapepress;
using shapepress::testing::write_text;
namespace fs = std::filesystem;

// A small bed: Table 2's Avicel distribution (Q3 x10/x50/x90 = 82.9/224.6/379.3 um) cut to
// [250, 350] um, in a box of 0.8 mm.
std::string config(const std::string& templates, const std::string& extra = "",
                   const std::string& sizes = "diameter_min = 250e-6\ndiameter_max = 350e-6\n") {
  return "[pack]\ncount = 16\nseed = 3\nbox_x = 0.8e-3\nbox_y = 0.8e-3\n" + templates +
         "[sizes]\nsize_quantiles = [82.9e-6, 224.6e-6, 379.3e-6]\n"
         "size_quantile_levels = [0.1, 0.5, 0.9]\n" +
         sizes + "[settle]\nkinetic_energy_ratio = 1e-4\n" + extra;
}

const std::string two_templates =
    "[[template]]\nname = \"bms/ellipsoid\"\nweight = 3\n[[template]]\nname = \"sphere\"\n";

fs::path filled_templates(const fs::path& dir) {
  const fs::path t = dir / "t.h5";
  if (fs::exists(t)) return t;
  const auto r = run_shapepress(
      "--quiet fill --ellipsoid 150um,100um,80um --count 60 --lattice "
      "random --out " +
      t.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return t;
}

TEST(PackCli, FillThenPackWritesAPackingTheReaderAcceptsWithItsMeasures) {
  const fs::path dir = fresh_directory("pack_e2e_fill");
  const fs::path templates = filled_templates(dir);
  write_text(dir / "pack.toml",
             config(two_templates, "[press]\nsolid_fraction = 0.5\nspeed = 0.1\n"));
  const auto r =
      run_shapepress("--quiet pack " + templates.string() + " --config " +
                     (dir / "pack.toml").string() + " --out " + (dir / "packed.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("solid fraction"), std::string::npos) << r.output;
  const BodyPacking p = read_packing(dir / "packed.h5");
  EXPECT_TRUE(fs::exists(dir / "packed.xmf"));
  ASSERT_EQ(p.size(), 16u);
  std::size_t bms = 0;
  for (std::size_t b = 0; b < p.size(); ++b)
    bms += p.kind(b) == BodyKind::bms;
  EXPECT_GT(bms, 6u);  // 3 : 1 by number
  EXPECT_FALSE(p.bonds.empty());
  for (const auto& [i, j] : p.bonds)
    EXPECT_EQ(p.particle_body[i], p.particle_body[j]);
  const PackMeasures& m = p.measures;
  // A settled bed released from 0.5: looser than the press, denser than the insertion (0.2 of
  // the bounding spheres), its sub-spheres a fill's fraction of the shapes.
  EXPECT_GT(m.solid_fraction_shape, 0.25);
  EXPECT_LT(m.solid_fraction_shape, 0.6);
  EXPECT_LT(m.solid_fraction_spheres, m.solid_fraction_shape);
  EXPECT_GT(m.coordination, 0.5);
  EXPECT_LT(m.largest_overlap_relative, 0.1);  // rigid bodies at rest: small overlaps
  EXPECT_GE(m.x10, 250e-6 * (1 - 1e-9));
  EXPECT_LE(m.x90, 350e-6 * (1 + 1e-9));
  EXPECT_GT(m.target_x50, 250e-6);
  EXPECT_NEAR(p.top - p.floor, m.bed_height, 1e-12);
  const nlohmann::json run = nlohmann::json::parse(read_text(dir / "packed.h5.run.json"));
  EXPECT_EQ(run["stage"], "pack");
  EXPECT_EQ(run["facts"]["bodies"], 16);
  EXPECT_DOUBLE_EQ(run["facts"]["solid_fraction_shape"].get<double>(), m.solid_fraction_shape);
  EXPECT_GE(run["facts"]["precompression_solid_fraction"].get<double>(), 0.5 - 1e-9);
}

// press.solid_fraction_volume = "shape": the same settle as by body volume, its fraction stated
// by the shapes' volume (the ratio of the two volumes, to rounding), and the press target by it.
TEST(PackCli, APressByShapeVolumeStatesItsFractionsByTheShapes) {
  const fs::path dir = fresh_directory("pack_e2e_shape_volume");
  const fs::path templates = filled_templates(dir);
  nlohmann::json facts[2];
  const char* volumes[2] = {"body", "shape"};
  // Each past where the bed settles by its volume (0.36 by body, 0.49 by shape volume).
  const char* targets[2] = {"0.45", "0.55"};
  for (int k = 0; k < 2; ++k) {
    const fs::path out = dir / (std::string(volumes[k]) + ".h5");
    write_text(dir / "pack.toml",
               config(two_templates, "[press]\nsolid_fraction = " + std::string(targets[k]) +
                                         "\nspeed = 0.1\nsolid_fraction_volume = \"" +
                                         std::string(volumes[k]) + "\"\n"));
    const auto r = run_shapepress("--quiet pack " + templates.string() + " --config " +
                                  (dir / "pack.toml").string() + " --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    facts[k] = nlohmann::json::parse(read_text(fs::path(out.string() + ".run.json")))["facts"];
    EXPECT_EQ(facts[k]["solid_fraction_volume"], volumes[k]);
    ASSERT_TRUE(facts[k].contains("precompression_solid_fraction")) << volumes[k];
    EXPECT_GE(facts[k]["precompression_solid_fraction"].get<double>(),
              std::stod(targets[k]) - 1e-9);
  }
  const double shape_over_body =
      facts[1]["solid_fraction_shape"].get<double>() / facts[1]["solid_fraction"].get<double>();
  EXPECT_GT(shape_over_body, 1.05);  // the fill's surface offset
  EXPECT_NEAR(facts[1]["settled_solid_fraction"].get<double>() /
                  facts[0]["settled_solid_fraction"].get<double>(),
              shape_over_body, 1e-9);
}

// A target looser than the bed settles to is never reached by the punch: the bed is stated as
// settled only, with a warning, not as pre-compressed to a solid fraction it never had.
TEST(PackCli, ABedThatSettlesDenserThanItsPressIsNotStatedPreCompressed) {
  const fs::path dir = fresh_directory("pack_e2e_loose_press");
  const fs::path templates = filled_templates(dir);
  write_text(dir / "pack.toml",
             config(two_templates, "[press]\nsolid_fraction = 0.1\nspeed = 0.1\n"));
  const auto r =
      run_shapepress("pack " + templates.string() + " --config " + (dir / "pack.toml").string() +
                     " --out " + (dir / "packed.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("the punch does not touch it"), std::string::npos) << r.output;
  const nlohmann::json facts =
      nlohmann::json::parse(read_text(dir / "packed.h5.run.json"))["facts"];
  EXPECT_GT(facts["settled_solid_fraction"].get<double>(), 0.1);
  EXPECT_FALSE(facts.contains("precompression_solid_fraction"));
}

// settle.density_scale: the same bed settled, pressed and relaxed at 100 × density takes far
// fewer steps (its step is 10 times longer), and its release at the true density leaves the true
// weight's overlaps, not the scaled weight's (100^(2/3) ≈ 22 times deeper).
TEST(PackCli, MassScaledSettleTakesFewerStepsAndLeavesTheTrueWeightsOverlaps) {
  const fs::path dir = fresh_directory("pack_e2e_mass_scaled");
  const fs::path templates = filled_templates(dir);
  const auto pack = [&](const std::string& name, const std::string& settle) {
    write_text(dir / (name + ".toml"),
               config(two_templates, settle + "[press]\nsolid_fraction = 0.4\nspeed = 0.1\n"));
    const auto r = run_shapepress("--quiet pack " + templates.string() + " --config " +
                                  (dir / (name + ".toml")).string() + " --out " +
                                  (dir / (name + ".h5")).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return nlohmann::json::parse(read_text(dir / (name + ".h5.run.json")))["facts"];
  };
  const nlohmann::json plain = pack("plain", ""), scaled = pack("scaled", "density_scale = 100\n");
  ASSERT_FALSE(plain.is_null());
  ASSERT_FALSE(scaled.is_null());
  EXPECT_EQ(plain["settle_density_scale"], 1.0);
  EXPECT_DOUBLE_EQ(plain["settle_time_step_s"].get<double>(), plain["time_step_s"].get<double>());
  EXPECT_NEAR(scaled["settle_time_step_s"].get<double>() / scaled["time_step_s"].get<double>(),
              10.0, 1e-9);
  EXPECT_DOUBLE_EQ(scaled["time_step_s"].get<double>(), plain["time_step_s"].get<double>());
  EXPECT_LT(scaled["steps"].get<double>(), 0.5 * plain["steps"].get<double>());
  EXPECT_TRUE(scaled["settled"].get<bool>());
  EXPECT_LT(scaled["largest_overlap_relative"].get<double>(),
            2.0 * plain["largest_overlap_relative"].get<double>() + 0.005);
  EXPECT_NEAR(scaled["solid_fraction"].get<double>(), plain["solid_fraction"].get<double>(), 0.05);
}

TEST(PackCli, SpheresFromASummaryJson) {
  const fs::path dir = fresh_directory("pack_e2e_spheres");
  write_text(dir / "summary.json",
             R"json({"format": "shapepress shape-stats summary 1", "size": {"basis": "volume (Q3)",
                 "x10_m": 71e-6, "x50_m": 198e-6, "x90_m": 350e-6}})json");
  write_text(dir / "pack.toml",
             "[pack]\ncount = 40\nbox_x = 1e-3\nbox_y = 1e-3\n[sizes]\nsummary = "
             "\"summary.json\"\ndiameter_min = 180e-6\ndiameter_max = 400e-6\n");
  const auto r = run_shapepress("--quiet pack --config " + (dir / "pack.toml").string() +
                                " --seed 5 --out " + (dir / "packed.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const BodyPacking p = read_packing(dir / "packed.h5");
  ASSERT_EQ(p.size(), 40u);
  EXPECT_TRUE(p.bonds.empty());
  EXPECT_GT(p.measures.solid_fraction_shape, 0.4);  // a poured bed of spheres, ~0.55
  EXPECT_EQ(p.measures.solid_fraction_shape, p.measures.solid_fraction_spheres);
}

void expect_refused(const fs::path& dir, const std::string& arguments, const std::string& cause) {
  const auto r =
      run_shapepress("--quiet pack " + arguments + " --out " + (dir / "packed.h5").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(cause), std::string::npos) << "expected '" << cause << "' in\n"
                                                     << r.output;
  EXPECT_FALSE(fs::exists(dir / "packed.h5"));
  EXPECT_FALSE(fs::exists(dir / "packed.xmf"));
}

TEST(PackCli, BadInputExitsTwoNamingTheCauseAndLeavesNoFile) {
  const fs::path dir = fresh_directory("pack_e2e_bad");
  const fs::path templates = filled_templates(dir);
  const std::string t = templates.string() + " --config " + (dir / "c.toml").string();
  write_text(dir / "c.toml", config("[[template]]\nname = \"bms/needle\"\n"));
  expect_refused(dir, t, "no template /bms/needle in '" + templates.string() + "'");
  write_text(dir / "c.toml",
             config(two_templates, "", "diameter_min = 5e-3\ndiameter_max = 6e-3\n"));
  expect_refused(dir, t, "size cutoff");
  write_text(dir / "c.toml", "[pack]\ncount = 4\nbox_x = 3e-4\nbox_y = 3e-4\n" + two_templates +
                                 "[sizes]\nsize_quantiles = [82.9e-6, 224.6e-6, 379.3e-6]\n"
                                 "size_quantile_levels = [0.1, 0.5, 0.9]\ndiameter_min = "
                                 "250e-6\ndiameter_max = 350e-6\n");
  expect_refused(dir, t, "not less than the box");
  write_text(dir / "c.toml", config(two_templates, "[press]\nsolid_fraction = 0.8\n"));
  expect_refused(dir, t, "solid_fraction_ceiling");
  // Four rigid bodies lie in one layer: they cannot rearrange to 0.59, the punch jams on them.
  write_text(dir / "c.toml",
             "[pack]\ncount = 4\nseed = 3\nbox_x = 0.8e-3\nbox_y = 0.8e-3\n"
             "[[template]]\nname = \"bms/ellipsoid\"\n"
             "[sizes]\nsize_quantiles = [82.9e-6, 224.6e-6, 379.3e-6]\n"
             "size_quantile_levels = [0.1, 0.5, 0.9]\ndiameter_min = 250e-6\n"
             "diameter_max = 350e-6\n[settle]\nkinetic_energy_ratio = 1e-4\n"
             "[press]\nsolid_fraction = 0.59\n");
  expect_refused(dir, t, "short of press.solid_fraction = 0.59");
  write_text(dir / "c.toml", config(two_templates, "density_scale = 0.5\n"));
  expect_refused(dir, t, "density_scale");
  write_text(dir / "c.toml", config(two_templates, "insertion = \"dense\"\n"));
  expect_refused(dir, t, "settle.insertion");
  write_text(dir / "c.toml", config(two_templates, "insertion = 1\n"));
  expect_refused(dir, t, "settle.insertion");
  write_text(dir / "c.toml", config(two_templates, "[material]\ndensity = -1500\n"));
  expect_refused(dir, t, "material.density");
  write_text(dir / "c.toml", config(two_templates, "[material]\nyoungs_modulus = nan\n"));
  expect_refused(dir, t, "material.youngs_modulus");

  // A BMS template whose sub-spheres overlap (a CMS fill relabelled).
  std::vector<geometry::TemplateRecord> records = geometry::read_templates(templates);
  geometry::TemplateRecord& r = records.at(0);
  r.name = "overlapping";
  r.body.centres[1] = r.body.centres[0] + geometry::Vec3(0.5 * r.body.radii[0], 0.0, 0.0);
  geometry::write_templates(dir / "bad.h5", {r}, Provenance{"test", "", 1});
  write_text(dir / "c.toml", config("[[template]]\nname = \"bms/overlapping\"\n"));
  expect_refused(dir, (dir / "bad.h5").string() + " --config " + (dir / "c.toml").string(),
                 "overlap");
}

}  // namespace
}  // namespace shapepress::packing
