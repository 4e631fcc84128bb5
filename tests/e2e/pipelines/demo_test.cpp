// The embedded demo (pipelines/demo/Makefile, what scripts/run-demo.sh runs after installing and
// building) end to end as a user runs it, and its report checked: every chart and table there,
// each run named by its config and what it pressed (not by the folders "compact" and "run" the
// Makefile chose), the bonded bed visible beside the spheres it is twenty times weaker than
// (a log stress axis), the table of beds' rows, and the figures within stated windows of the
// values stored in tests/data/pipelines/demo-figures.csv.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using shapepress::testing::fresh_directory;
using shapepress::testing::read_text;
using shapepress::testing::repository_root;
using shapepress::testing::run_command;
using shapepress::testing::shell_quoted;
using shapepress::testing::text_rows;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string spheres = "compact-demo: 500 spheres";
const std::string bonded = "compact-bed-demo: 20 BMS bodies of 30 sub-spheres";

// metrics.json's value of `metric` for the run labelled `label` (NaN when absent).
double metric(const nlohmann::json& metrics, const std::string& label, const std::string& metric) {
  for (const auto& run : metrics.at("runs"))
    if (run.at("label") == label && run.at("metrics").contains(metric))
      return run.at("metrics").at(metric).at("value").get<double>();
  return NAN;
}

// The largest `y` of the chart data's series titled `title` (chart CSVs: series, x, y; a comment
// line "series k = title" each).
double series_maximum(const fs::path& csv, const std::string& title, const std::string& y) {
  const std::string text = read_text(csv);
  const std::size_t at = text.find(" = " + title + "\n");
  EXPECT_NE(at, std::string::npos) << title << " in " << csv;
  if (at == std::string::npos) return NAN;
  const std::size_t number = text.rfind("series ", at) + 7;
  const int series = std::stoi(text.substr(number, at - number));
  double largest = -INFINITY;
  for (const auto& row : text_rows(csv))
    if (std::stoi(row.at("series")) == series) largest = std::max(largest, std::stod(row.at(y)));
  return largest;
}

TEST(Demo, RunsEndToEndAndItsReportNamesShowsAndMeasuresEveryRun) {
  const fs::path out = fresh_directory("demo");
  const std::string demo = "make -s -C " + shell_quoted(repository_root() / "pipelines" / "demo") +
                           " SHAPEPRESS=" + shell_quoted(SHAPEPRESS_BINARY) +
                           " OUT=" + shell_quoted(out);
  const auto made = run_command(demo + " -j2");
  ASSERT_EQ(made.exit_code, 0) << made.output;
  const fs::path report = out / "report";

  // Every chart (SVG and PNG, its data and its gnuplot script) and every table.
  const std::string html = read_text(report / "report.html");
  for (const char* chart :
       {"stress_strain", "solid_fraction_stress", "heckel", "kawakita", "plate_force"}) {
    for (const char* file : {".svg", ".png", ".csv", ".gp"})
      EXPECT_TRUE(fs::exists(report / (std::string(chart) + file))) << chart << file;
  }
  for (const char* heading : {"Stress-strain", "Solid fraction vs stress", "Heckel plot",
                              "Kawakita plot", "Sphere between plates"})
    EXPECT_THAT(html, HasSubstr(heading));
  EXPECT_TRUE(fs::exists(report / "metrics.json"));
  EXPECT_TRUE(fs::exists(report / "beds.csv"));

  // Each run by what it is, in the legends, the tables and metrics.json; never by a folder.
  const std::string legend = read_text(report / "stress_strain.csv");
  for (const std::string& label : {spheres, bonded}) {
    EXPECT_THAT(legend, HasSubstr("= " + label + " load\n"));
    EXPECT_THAT(html, HasSubstr(label));
  }
  EXPECT_THAT(legend, Not(HasSubstr("= compact load")));
  EXPECT_THAT(legend, Not(HasSubstr("= run load")));
  for (const char* plate :
       {"plate-demo: Hertz sphere", "plate-rubber-sphere-multicontact: multi-contact sphere",
        "rubber-sphere: BMS of 545 sub-spheres"})
    EXPECT_THAT(read_text(report / "plate_force.csv"), HasSubstr("= " + std::string(plate)));

  // The bonded bed peaks twenty times below the spheres: on a linear axis it would hug the
  // zero line. The stress axes are logarithmic, from a thousandth of the smaller peak, so its
  // loading curve spans decades of the chart.
  const std::string script = read_text(report / "stress_strain.gp");
  EXPECT_THAT(script, HasSubstr("set logscale y\n"));
  EXPECT_THAT(read_text(report / "heckel.gp"), HasSubstr("set logscale x\n"));
  const std::size_t range = script.find("set yrange [");
  ASSERT_NE(range, std::string::npos);
  const double floor = std::stod(script.substr(range + 12));
  const double bonded_peak =
      series_maximum(report / "stress_strain.csv", bonded + " load", "stress_MPa");
  EXPECT_GT(bonded_peak, 100.0 * floor);
  EXPECT_LT(bonded_peak,
            series_maximum(report / "stress_strain.csv", spheres + " load", "stress_MPa") / 10.0);

  // The table of beds: one row a compaction, with what the bed was.
  std::map<std::string, std::map<std::string, std::string>> beds;
  for (auto& row : text_rows(report / "beds.csv"))
    beds[row["label"]] = row;
  ASSERT_EQ(beds.size(), 2u);
  EXPECT_EQ(beds[spheres]["particle_kind"], "sphere");
  EXPECT_EQ(beds[spheres]["bodies"], "500");
  EXPECT_EQ(beds[spheres]["sub_spheres_per_body"], "1");
  EXPECT_EQ(beds[bonded]["particle_kind"], "bms");
  EXPECT_EQ(beds[bonded]["bodies"], "20");
  EXPECT_EQ(beds[bonded]["sub_spheres_per_body"], "30");
  // pack-demo.toml settles the bed and does not press it (a pre-compression does not last).
  EXPECT_EQ(beds[bonded]["precompression_solid_fraction_percent"], "");
  for (const std::string& label : {spheres, bonded}) {
    EXPECT_GT(std::stod(beds[label]["settled_solid_fraction_percent"]), 20.0) << label;
    EXPECT_GT(std::stod(beds[label]["compaction_wall_s"]), 0.0) << label;
  }
  EXPECT_GT(std::stod(beds[bonded]["pack_wall_s"]), 0.0);

  // The figures against the stored ones, each within its window.
  std::ifstream in(report / "metrics.json");
  const nlohmann::json metrics = nlohmann::json::parse(in);
  const auto stored = text_rows(fs::path(SHAPEPRESS_TEST_DATA) / "pipelines" / "demo-figures.csv");
  EXPECT_GE(stored.size(), 10u);
  for (const auto& row : stored) {
    const double value = metric(metrics, row.at("label"), row.at("metric"));
    const double expected = std::stod(row.at("value")), window = std::stod(row.at("window"));
    std::printf("%s %s: %.6g (stored %.6g, window %g)\n", row.at("label").c_str(),
                row.at("metric").c_str(), value, expected, window);
    EXPECT_NEAR(value, expected, window * std::fabs(expected))
        << row.at("label") << " " << row.at("metric");
  }

  // A second make has nothing to do.
  const auto again = run_command(demo + " -q");
  EXPECT_EQ(again.exit_code, 0) << again.output;
}

}  // namespace
}  // namespace shapepress
