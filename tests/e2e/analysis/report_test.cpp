// `shapepress report` as a user runs it: on the synthetic runs of tests/data/analysis (known
// numbers), on real plate and compact runs made by the binary, and on bad input (exit codes).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <algorithm>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "common/csv.hpp"
#include "common/sha256.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::read_text;
using shapepress::testing::run_command;
using shapepress::testing::run_shapepress;
using shapepress::testing::write_text;
using ::testing::HasSubstr;
using ::testing::Not;

const std::filesystem::path data = std::filesystem::path(SHAPEPRESS_TEST_DATA) / "analysis";
const std::filesystem::path repo = shapepress::testing::repository_root();

// The values of a metric in metrics.json, one per run that has it, in run order.
std::vector<double> metric(const std::string& json, const std::string& name) {
  const std::regex pattern("\"" + name + "\": \\{\"value\": ([^,]+),");
  std::vector<double> values;
  for (auto it = std::sregex_iterator(json.begin(), json.end(), pattern);
       it != std::sregex_iterator(); ++it)
    values.push_back((*it)[1] == "null" ? NAN : std::stod((*it)[1]));
  return values;
}

// Single-quoted for the shell (GCC 12 -O3 trips -Wrestrict on "'" + std::string + "'").
std::string quote(const std::filesystem::path& path) {
  std::string quoted(1, '\'');
  quoted.append(path.string());
  quoted.push_back('\'');
  return quoted;
}

TEST(ReportE2e, SyntheticRunsGiveTheirKnownNumbers) {
  const auto out = fresh_directory("analysis_synthetic");
  const auto r =
      run_shapepress("report " + quote(data / "compaction_run") + " " + quote(data / "plate_run") +
                     " --poisson-ratio 0.46 --out " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* stem :
       {"stress_strain", "solid_fraction_stress", "heckel", "kawakita", "plate_force"})
    for (const char* ext : {".svg", ".png", ".csv", ".gp"})
      EXPECT_TRUE(std::filesystem::exists(out / (std::string(stem) + ext))) << stem << ext;
  // The unloading is on the solid-fraction axis too (beds of different strain references side
  // by side): its series ends at the unloaded bed's fraction, 1/1.04 of the densest.
  EXPECT_THAT(read_text(out / "solid_fraction_stress.csv"),
              HasSubstr("series 1 = compaction_run unload"));
  const CsvTable density = read_csv(out / "solid_fraction_stress.csv");
  const std::vector<double> series = density.column("series"),
                            fraction = density.column("solid_fraction");
  ASSERT_EQ(series.back(), 1.0);
  EXPECT_NEAR(fraction.back() * 1.04, *std::max_element(fraction.begin(), fraction.end()), 1e-6);
  const std::string json = read_text(out / "metrics.json");
  // The synthetic compaction is Heckel-exact with Py = 50 MPa, A = 0.5; 10-digit CSV values
  // leave ~1e-9 relative rounding.
  ASSERT_EQ(metric(json, "heckel_yield_pressure").size(), 1u) << json;
  EXPECT_NEAR(metric(json, "heckel_yield_pressure")[0], 50e6, 1e-6 * 50e6);
  EXPECT_NEAR(metric(json, "heckel_A")[0], 0.5, 1e-7);
  EXPECT_NEAR(metric(json, "elastic_recovery")[0], 0.04, 1e-8);  // unloaded to 1.04 H_min
  EXPECT_NEAR(metric(json, "peak_stress")[0], 100e6, 1.0);
  EXPECT_GT(metric(json, "H0")[0], 0.0);
  // The plate "simulation" is Tatara's curve itself: the report's Tatara must match it to the
  // digits written, and be 59 % above Hertz at 40 % deformation (the reference table's ratio).
  EXPECT_LT(metric(json, "tatara_max_relative_error")[0], 1e-6);
  EXPECT_NEAR(metric(json, "hertz_max_relative_error")[0], 0.59295, 1e-4);
  EXPECT_NEAR(metric(json, "radius")[0], 0.01, 1e-10);
  const std::string html = read_text(out / "report.html");
  EXPECT_THAT(html, HasSubstr("<svg"));
  EXPECT_THAT(html, HasSubstr("heckel_yield_pressure"));
  EXPECT_THAT(html, HasSubstr("make_synthetic_runs.py"));  // the inputs' provenance lines
  EXPECT_THAT(html, Not(HasSubstr("<?xml")));              // SVG embedded, not the file
}

TEST(ReportE2e, RealPlateAndCompactRunsOverlaid) {
  const auto dir = fresh_directory("analysis_real");
  // The shipped plate rig (rubber sphere, 1 % deformation) and a 500-sphere compaction.
  auto r = run_shapepress("plate --config " +
                          quote(repo / "pipelines/configs/plate-rubber-sphere.toml") + " --out " +
                          quote(dir / "plate"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string config = read_text(repo / "pipelines/configs/compact-spheres.toml");
  config = std::regex_replace(config, std::regex(R"(\ncount = \d+)"), "\ncount = 500");
  config = std::regex_replace(config, std::regex(R"(\nx = "[^"]*")"), "\nx = \"8 mm\"");
  config = std::regex_replace(config, std::regex(R"(\ny = "[^"]*")"), "\ny = \"8 mm\"");
  config = std::regex_replace(config, std::regex(R"(\nsettle_time = "[^"]*")"),
                              "\nsettle_time = \"120 ms\"");
  std::ofstream(dir / "compact.toml") << config;
  r = run_shapepress("--quiet --threads 2 compact --config " + quote(dir / "compact.toml") +
                     " --out " + quote(dir / "compact"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_shapepress("report " + quote(dir / "compact") + " " + quote(data / "compaction_run") +
                     " " + quote(dir / "plate") + " --poisson-ratio 0.46 --out " +
                     quote(dir / "report"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string json = read_text(dir / "report" / "metrics.json");
  const std::vector<double> py = metric(json, "heckel_yield_pressure");
  ASSERT_EQ(py.size(), 2u) << json;  // two compaction runs overlaid
  EXPECT_GT(py[0], 0.0);
  const std::vector<double> recovery = metric(json, "elastic_recovery");
  EXPECT_GT(recovery[0], 0.0);  // elastic spheres spring back
  EXPECT_LT(recovery[0],
            0.5);  // measured 0.20 (500 spheres, 25 % strain); a bed never regains half
  EXPECT_GT(metric(json, "work_of_compaction")[0], metric(json, "work_of_unloading")[0]);
  // The plate engine is Hertz: within a few % of Hertz, and Tatara is 6.6 % stiffer at 1 %.
  const double hertz_error = metric(json, "hertz_rms_relative_error")[0];
  const double tatara_error = metric(json, "tatara_rms_relative_error")[0];
  EXPECT_LT(hertz_error, tatara_error);
  EXPECT_GT(tatara_error, 0.02);
  // Two different compactions: their stresses differ at every compared strain.
  EXPECT_THAT(json, HasSubstr("\"stress_spread\""));
  // Overlaid: the stress–strain data hold both compaction runs' load branches.
  const std::string csv = read_text(dir / "report" / "stress_strain.csv");
  // The real run by its config and its bed; the synthetic one, whose run.json names no config,
  // by its folder.
  EXPECT_THAT(csv, HasSubstr("compact: 500 spheres load"));
  EXPECT_THAT(csv, HasSubstr("compaction_run load"));

  // Both stages wrote a run.json; the report's H0 is its fact, and the config is hashed.
  const nlohmann::json compact = nlohmann::json::parse(read_text(dir / "compact" / "run.json"));
  EXPECT_EQ(compact["stage"], "compact");
  EXPECT_EQ(compact["inputs"][0]["role"], "config");
  EXPECT_EQ(compact["inputs"][0]["sha256"], sha256_hex(read_text(dir / "compact.toml")));
  const nlohmann::json& facts = compact["facts"];
  ASSERT_TRUE(facts["reference_gap_m"].is_number()) << compact.dump(2);
  const double h0 = facts["reference_gap_m"].get<double>();
  EXPECT_NEAR(metric(json, "H0")[0], h0, 1e-9 * h0);  // metrics.json writes 10 digits
  EXPECT_DOUBLE_EQ(facts["die_area_m2"].get<double>(), 8e-3 * 8e-3);
  EXPECT_TRUE(facts["spheres"].is_number_integer());
  EXPECT_GT(facts["spheres"].get<std::int64_t>(), 0);
  EXPECT_EQ(facts["particle_kind"], "sphere");
  EXPECT_GT(facts["solid_volume_m3"].get<double>(), 0.0);
  EXPECT_GT(facts["time_step_s"].get<double>(), 0.0);
  EXPECT_GT(facts["steps"].get<std::int64_t>(), 0);
  const nlohmann::json plate = nlohmann::json::parse(read_text(dir / "plate" / "run.json"));
  EXPECT_EQ(plate["stage"], "plate");
  EXPECT_EQ(plate["facts"]["particle_kind"], "sphere");
  EXPECT_EQ(plate["facts"]["sub_spheres"], 1);
  EXPECT_EQ(plate["facts"]["fills"], 1);
  EXPECT_DOUBLE_EQ(plate["facts"]["radius_m"].get<double>(), metric(json, "radius")[0]);

  // Rewording the CSV comment lines (for people) changes nothing the report computes.
  for (const char* file : {"compact/punch.csv", "plate/force.csv"}) {
    std::istringstream in(read_text(dir / file));
    std::string text;
    for (std::string line; std::getline(in, line);) {
      if (line.starts_with("#")) {
        line = std::regex_replace(line, std::regex("H0"), "the reference height");
        line = std::regex_replace(line, std::regex("die area|sub_spheres|particle|fills"), "x");
      }
      text += line + "\n";
    }
    write_text(dir / file, text);
  }
  r = run_shapepress("report " + quote(dir / "compact") + " " + quote(data / "compaction_run") +
                     " " + quote(dir / "plate") + " --poisson-ratio 0.46 --out " +
                     quote(dir / "reworded"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_text(dir / "reworded" / "stress_strain.csv"), csv);
  const std::string reworded = read_text(dir / "reworded" / "metrics.json");
  for (const char* name : {"H0", "heckel_yield_pressure", "hertz_rms_relative_error", "radius"})
    EXPECT_EQ(metric(reworded, name), metric(json, name)) << name;
}

// The report takes the facts from run.json: one missing is exit 2 naming the file and the key,
// a folder without run.json is exit 2 naming the folder and the file.
TEST(ReportE2e, RunJsonWithoutAFactOrMissingIsExitTwo) {
  const auto dir = fresh_directory("analysis_run_json");
  std::filesystem::copy(data / "compaction_run", dir / "compaction");
  std::filesystem::copy(data / "plate_run", dir / "plate");
  const auto without = [&](const std::filesystem::path& folder, const std::string& key) {
    nlohmann::json j = nlohmann::json::parse(read_text(folder / "run.json"));
    j["facts"].erase(key);
    write_text(folder / "run.json", j.dump(2));
  };
  without(dir / "compaction", "reference_gap_m");
  auto r = run_shapepress("report " + quote(dir / "compaction") + " --out " + quote(dir / "r"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("compaction/run.json"));
  EXPECT_THAT(r.output, HasSubstr("reference_gap_m"));
  without(dir / "plate", "sub_spheres");
  r = run_shapepress("report " + quote(dir / "plate") + " --out " + quote(dir / "r"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("plate/run.json"));
  EXPECT_THAT(r.output, HasSubstr("sub_spheres"));
  std::filesystem::remove(dir / "plate" / "run.json");
  r = run_shapepress("report " + quote(dir / "plate") + " --out " + quote(dir / "r"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr((dir / "plate").string() + ": no run.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "r" / "report.html"));
  // A report writes its own run.json, listing the runs it read.
  r = run_shapepress("report " + quote(data / "plate_run") + " --out " + quote(dir / "ok"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json report = nlohmann::json::parse(read_text(dir / "ok" / "run.json"));
  EXPECT_EQ(report["stage"], "report");
  EXPECT_EQ(report["facts"]["plate_runs"], 1);
  EXPECT_EQ(report["inputs"].size(), 2u);  // force.csv and run.json
}

TEST(ReportE2e, SameNamedFoldersGetDistinctLabelsAndPlateWithoutNuIsHertzOnly) {
  const auto dir = fresh_directory("analysis_labels");
  for (const char* parent : {"a", "b"}) {
    std::filesystem::create_directories(dir / parent / "run");
    for (const char* name : {"force.csv", "run.json"})
      std::filesystem::copy_file(data / "plate_run" / name, dir / parent / "run" / name);
  }
  const auto r = run_shapepress("report " + quote(dir / "a" / "run") + " " +
                                quote(dir / "b" / "run") + " --out " + quote(dir / "report"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("Hertz only"));
  const std::string json = read_text(dir / "report" / "metrics.json");
  EXPECT_THAT(json, HasSubstr("\"label\": \"a/run\""));
  EXPECT_THAT(json, HasSubstr("\"label\": \"b/run\""));
  EXPECT_TRUE(metric(json, "tatara_rms_relative_error").empty());
  EXPECT_EQ(metric(json, "hertz_rms_relative_error").size(), 2u);
}

// The spread of a family of identical runs is zero; the synthetic curve reaches strain 0.5713.
TEST(ReportE2e, IdenticalCompactionRunsHaveNoSpread) {
  const auto dir = fresh_directory("analysis_spread");
  const auto r = run_shapepress("report " + quote(data / "compaction_run") + " " +
                                quote(data / "compaction_run") + " --out " + quote(dir));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string json = read_text(dir / "metrics.json");
  const std::smatch match = [&] {
    std::smatch m;
    std::regex_search(json, m, std::regex(R"("strain": \[([^\]]*)\], "spread": \[([^\]]*)\])"));
    return m;
  }();
  ASSERT_EQ(match.size(), 3u) << json;
  EXPECT_EQ(match[2].str(), "0, 0, 0, 0, 0, 0, 0, 0, 0, 0");
  EXPECT_THAT(match[1].str(), HasSubstr("0.5713444712"));  // the common strain range's end
}

TEST(ReportE2e, ExperimentIsOverlaidWithItsErrorsAndTablesReadInMpaMmPercent) {
  const auto dir = fresh_directory("analysis_experiment");
  // A "measured" curve 10 % stiffer than the synthetic run at every loading strain, in percent
  // and MPa: the run is 1/1.1 of it everywhere, 10 % of the 100 MPa peak (10 MPa) below at most.
  const CsvTable run = read_csv(data / "compaction_run" / "punch.csv");
  const auto strain = run.column("strain"), stress = run.column("stress_Pa"),
             phase = run.column("phase"), density = run.column("solid_fraction");
  std::string stress_strain = "# 1.1 x the synthetic run\nstrain_%,stress_MPa\n",
              solid_fraction = "stress_kPa,solid_fraction\n";
  int loading = 0;
  for (std::size_t i = 0; i < phase.size() && phase[i] == 0.0; ++i, ++loading) {
    std::ostringstream a, b;
    a.precision(12), b.precision(12);
    a << 100 * strain[i] << "," << 1.1e-6 * stress[i] << "\n";
    b << 1e-3 * stress[i] << "," << density[i] << "\n";
    stress_strain += a.str();
    solid_fraction += b.str();
  }
  write_text(dir / "measured.csv", stress_strain);
  write_text(dir / "density.csv", solid_fraction);
  const auto r = run_shapepress("report " + quote(data / "compaction_run") + " --experiment " +
                                quote(dir / "measured.csv") + " --experiment " +
                                quote(dir / "density.csv") + " --out " + quote(dir / "r"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(dir / "r" / "metrics.json");
  const auto json = nlohmann::json::parse(in);
  const auto& e = json.at("experiments");
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[0].at("axes"), "stress-strain");
  const auto& versus = e[0].at("runs").at(0);
  EXPECT_EQ(versus.at("points").get<int>(), loading);
  // 10-digit CSVs: relative rounding near 1e-9.
  EXPECT_NEAR(versus.at("rms_relative").get<double>(), 0.1 / 1.1, 1e-7);
  EXPECT_NEAR(versus.at("max_relative").get<double>(), 0.1 / 1.1, 1e-7);
  EXPECT_NEAR(versus.at("max").get<double>(), 10e6, 1.0);
  EXPECT_EQ(versus.at("unit"), "Pa");
  EXPECT_EQ(e[1].at("axes"), "solid fraction-stress");  // the same curve: no error
  EXPECT_NEAR(e[1].at("runs").at(0).at("rms").get<double>(), 0.0, 1e-9);
  const std::string html = read_text(dir / "r" / "report.html");
  EXPECT_THAT(html, HasSubstr("Against the experiment measured.csv"));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">9.091 %</td>"));
  // The tables in the units people read: the 100 MPa peak, H0 in mm, fractions in %.
  EXPECT_THAT(html, HasSubstr("peak_stress</td><td class=\"num\">100</td><td>MPa"));
  EXPECT_THAT(html, HasSubstr("elastic_recovery</td><td class=\"num\">4</td><td>%"));
  EXPECT_THAT(html, HasSubstr("H0</td><td class=\"num\">10.17</td><td>mm"));
  const std::string tables =
      html.substr(html.find("<h2>Metrics</h2>"),
                  html.find("<h2>Provenance</h2>") - html.find("<h2>Metrics</h2>"));
  EXPECT_THAT(tables, Not(HasSubstr("e+0")));
  EXPECT_THAT(read_text(dir / "r" / "stress_strain.csv"), HasSubstr("measured measured.csv"));
  // A curve without a strain or solid fraction column is exit 2 naming the file.
  write_text(dir / "bad.csv", "stress_MPa,force_N\n1,2\n");
  const auto bad = run_shapepress("report " + quote(data / "compaction_run") + " --experiment " +
                                  quote(dir / "bad.csv") + " --out " + quote(dir / "r2"));
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_THAT(bad.output, HasSubstr("bad.csv"));
  write_text(dir / "unit.csv", "strain,stress_N\n0.1,2\n");
  const auto unit = run_shapepress("report " + quote(data / "compaction_run") + " --experiment " +
                                   quote(dir / "unit.csv") + " --out " + quote(dir / "r3"));
  EXPECT_EQ(unit.exit_code, 2) << unit.output;
  EXPECT_THAT(unit.output, HasSubstr("stress_N"));
}

TEST(ReportE2e, BadInputIsExitTwoNamingTheFileOrColumn) {
  const auto out = fresh_directory("analysis_bad");
  auto r = run_shapepress("report " + quote(out / "missing_run") + " --out " + quote(out / "r"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("missing_run"));
  r = run_shapepress("report " + quote(data / "bad_run") + " --out " + quote(out / "r"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("stress_Pa"));
  EXPECT_THAT(r.output, HasSubstr("bad_run/punch.csv"));
  r = run_shapepress("report " + quote(data) + " --out " + quote(out / "r"));  // no CSV inside
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("punch.csv"));
  r = run_shapepress("report --out " + quote(out / "r"));  // no run folder
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_shapepress("report " + quote(data / "compaction_run") +
                     " --heckel-window 0.9 0.2 --out " + quote(out / "r"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("Heckel"));
  EXPECT_FALSE(std::filesystem::exists(out / "r" / "report.html"));
}

TEST(ReportE2e, PlateChartTakesAnExtraCurve) {
  // Another method's curve (a BMS plate run when it lands) on the plate chart by label.
  const auto out = fresh_directory("analysis_plate_curve");
  std::ofstream(out / "bms.csv") << "# a made-up curve\ndeformation,force_N\n0.1,1.5\n0.2,4.0\n";
  auto r = run_shapepress("report " + quote(data / "plate_run") + " --poisson-ratio 0.46" +
                          " --plate-curve 'BMS 545=" + (out / "bms.csv").string() + "' --out " +
                          quote(out / "r"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string chart = read_text(out / "r" / "plate_force.csv");
  EXPECT_THAT(chart, HasSubstr("BMS 545"));
  EXPECT_THAT(chart, HasSubstr("Tatara"));
  r = run_shapepress("report " + quote(data / "plate_run") + " --plate-curve " +
                     quote(out / "bms.csv") + " --out " + quote(out / "r2"));
  EXPECT_EQ(r.exit_code, 2) << r.output;  // no LABEL=
  EXPECT_THAT(r.output, HasSubstr("LABEL=FILE.csv"));
}

TEST(ReportE2e, PlateComparisonStartsWhereAsked) {
  // The paper's range, 5–40 %: the synthetic run is Tatara's table, so it is 41.6 % RMS off its
  // Hertz column, relative to Hertz, over those rows (tests/data/analysis/tatara_hertz_*.csv,
  // 1 % rows 5–40 %; the report's own grid moves the figure in the third digit).
  const auto out = fresh_directory("analysis_compare_from");
  auto r = run_shapepress("report " + quote(data / "plate_run") +
                          " --poisson-ratio 0.46 --compare-from 0.05 --out " + quote(out / "r"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string json = read_text(out / "r" / "metrics.json");
  EXPECT_NEAR(metric(json, "compared_from_deformation")[0], 0.05, 1e-12);
  EXPECT_NEAR(metric(json, "hertz_rms_relative_error")[0], 0.416, 0.005);
  r = run_shapepress("report " + quote(data / "plate_run") + " --compare-from 0.5 --out " +
                     quote(out / "r2"));
  EXPECT_EQ(r.exit_code, 2) << r.output;  // past the run's 40 %
  EXPECT_THAT(r.output, HasSubstr("--compare-from"));
}

TEST(ReportE2e, WithoutGnuplotTheRunFailsNamingIt) {
  const auto out = fresh_directory("analysis_no_gnuplot");
  const auto r = run_command("PATH=" + quote(out) + " " + std::string(SHAPEPRESS_BINARY) +
                             " report " + quote(data / "plate_run") + " --out " + quote(out / "r"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr("gnuplot"));
}

}  // namespace
}  // namespace shapepress
