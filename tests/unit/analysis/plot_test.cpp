#include "analysis/plot.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "tests/support/files.hpp"

namespace shapepress::analysis {
namespace {

using shapepress::testing::read_text;

Chart two_series() {
  return {"Test chart",
          "strain",
          "stress [MPa]",
          "strain",
          "stress_MPa",
          {{"load", {0.0, 0.1, 0.2}, {0.0, 1.0, 4.0}},
           {"unload, it's dashed", {0.2, 0.15}, {4.0, 0.0}, SeriesStyle::dashed}}};
}

// A log axis starts where the chart says, not at its smallest point: a loading curve's first
// stresses lie decades below the peaks the chart is for.
TEST(PlotScript, ALogAxisStartsWhereTheChartSays) {
  Chart chart = two_series();
  chart.log_y = true;
  EXPECT_EQ(gnuplot_script(chart, "a.svg", "a.png").find("set yrange"), std::string::npos);
  chart.log_y_from = 0.001;
  const std::string script = gnuplot_script(chart, "a.svg", "a.png");
  EXPECT_NE(script.find("set logscale y\nset yrange [0.001:*]\n"), std::string::npos) << script;
  chart.log_y = false;  // a linear axis keeps gnuplot's autoscale
  EXPECT_EQ(gnuplot_script(chart, "a.svg", "a.png").find("set yrange"), std::string::npos);
}

class PlotTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = std::filesystem::temp_directory_path() /
              ("shapepress_plot_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder_);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }
  std::filesystem::path folder_;
};

TEST(PlotScript, HoldsTheDataInlineAndBothTerminals) {
  const std::string s = gnuplot_script(two_series(), "a.svg", "a.png");
  EXPECT_NE(s.find("$series0 << EOD\n0 0\n0.1 1\n0.2 4\nEOD"), std::string::npos) << s;
  EXPECT_NE(s.find("set terminal svg"), std::string::npos);
  EXPECT_NE(s.find("set terminal pngcairo"), std::string::npos);
  EXPECT_NE(s.find("'unload, it''s dashed'"), std::string::npos);  // quote doubled for gnuplot
  EXPECT_NE(s.find("dt 2"), std::string::npos);                    // the dashed style
  EXPECT_NE(s.find("with lines lw 2 lc 1"), std::string::npos);    // colour by position
  Chart same_colour = two_series();
  same_colour.series[0].colour = same_colour.series[1].colour = 3;  // one run's load and unload
  const std::string t = gnuplot_script(same_colour, "a.svg", "a.png");
  EXPECT_NE(t.find("with lines lw 2 lc 3"), std::string::npos) << t;
  EXPECT_NE(t.find("with lines dt 2 lw 2 lc 3"), std::string::npos) << t;
}

// A seed scatter drawn as error bars: a third column in the data, gnuplot's yerrorlines, and the
// CSV's <y>_error column (NaN for a series without).
TEST_F(PlotTest, ErrorBarsAreAThirdColumnInTheScriptAndTheCsv) {
  Chart chart = two_series();
  chart.series[0].y_error = {0.5, 0.25, 1.0};
  const std::string s = gnuplot_script(chart, "a.svg", "a.png");
  EXPECT_NE(s.find("$series0 << EOD\n0 0 0.5\n0.1 1 0.25\n0.2 4 1\nEOD"), std::string::npos) << s;
  EXPECT_NE(s.find("$series0 using 1:2:3 title 'load' with yerrorlines"), std::string::npos) << s;
  EXPECT_NE(s.find("$series1 using 1:2 title"), std::string::npos) << s;
  if (find_gnuplot().empty()) GTEST_SKIP() << "gnuplot is not installed";
  const CsvTable table = read_csv(plot_chart(chart, folder_ / "bars").csv);
  const std::vector<double> error = table.column("stress_MPa_error");
  EXPECT_EQ(error[2], 1.0);
  EXPECT_TRUE(std::isnan(error[3]));
}

TEST_F(PlotTest, WritesSvgPngDataAndScript) {
  if (find_gnuplot().empty()) GTEST_SKIP() << "gnuplot is not installed";
  const ChartFiles files = plot_chart(two_series(), folder_ / "chart");
  EXPECT_NE(read_text(files.svg).find("<svg"), std::string::npos);
  EXPECT_GT(std::filesystem::file_size(files.png), 1000u);
  const std::string png = read_text(files.png);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const CsvTable table = read_csv(files.csv);
  EXPECT_EQ(table.columns, (std::vector<std::string>{"series", "strain", "stress_MPa"}));
  ASSERT_EQ(table.rows.size(), 5u) << "one row per point of both series";
  EXPECT_EQ(table.column("series"), (std::vector<double>{0, 0, 0, 1, 1}));
  EXPECT_EQ(table.column("stress_MPa")[2], 4.0);
  EXPECT_NE(read_text(files.csv).find("# series 1 = unload, it's dashed"), std::string::npos);
  EXPECT_NE(read_text(files.script).find("set output 'chart.svg'"), std::string::npos);
  for (const auto& entry : std::filesystem::directory_iterator(folder_))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos)
        << "temporary file left: " << entry.path();
}

TEST_F(PlotTest, MissingGnuplotIsAComputationErrorNamingIt) {
  const char* old_path = std::getenv("PATH");
  const std::string saved = old_path ? old_path : "";
  ::setenv("PATH", folder_.c_str(), 1);  // a folder without gnuplot
  std::string message;
  try {
    plot_chart(two_series(), folder_ / "chart");
  } catch (const ComputationError& e) {
    message = e.what();
  }
  ::setenv("PATH", saved.c_str(), 1);
  EXPECT_NE(message.find("gnuplot"), std::string::npos) << message;
  EXPECT_FALSE(std::filesystem::exists(folder_ / "chart.svg"));
}

}  // namespace
}  // namespace shapepress::analysis
