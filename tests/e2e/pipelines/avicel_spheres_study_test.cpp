// The spherical Avicel PH 200 study (pipelines/avicel-spheres/Makefile) reduced to what runs in
// the default suite: the shipped config with a punch ten times faster (0.2 m/s) and a quarter of
// the settle (20 ms), the reference run, its report, and a sweep of three points (β = 0 and 1.3
// at λp = 0.3, λp = 1 at β = 1.3) with its table, charts and report. The Makefile's rules are the
// user's; only CONFIG, BETAS and LAMBDAS are given.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include "common/csv.hpp"
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
using shapepress::testing::with_config_key;
using shapepress::testing::write_text;

// The max_stress_Pa of a compaction's SUMMARY line (compact's standard output).
double summary_peak_stress(const fs::path& summary) {
  const std::string text = read_text(summary);
  const std::size_t at = text.find("max_stress_Pa=");
  EXPECT_NE(at, std::string::npos) << summary;
  return at == std::string::npos ? 0.0 : std::stod(text.substr(at + 14));
}

TEST(AvicelSpheresStudy, ReducedStudyRunsTheReferenceTheSweepAndTheirReports) {
  const fs::path out = fresh_directory("avicel_spheres");
  std::string config = read_text(repository_root() / "pipelines/configs/avicel-ph200-spheres.toml");
  config = with_config_key(config, "generate", "settle_time", "\"20 ms\"");
  config = with_config_key(config, "punch", "speed", "\"0.2 m/s\"");
  config = with_config_key(config, "punch", "unload_speed", "\"0.2 m/s\"");
  write_text(out / "reduced.toml", config);
  const std::string study =
      "make -s -C " + shell_quoted(repository_root() / "pipelines" / "avicel-spheres") +
      " SHAPEPRESS=" + shell_quoted(SHAPEPRESS_BINARY) + " OUT=" + shell_quoted(out / "study") +
      " CONFIG=" + shell_quoted(out / "reduced.toml") + " BETAS='0 1.3' LAMBDAS='0.3 1' THREADS=1";
  const auto made = run_command(study + " -j2");
  ASSERT_EQ(made.exit_code, 0) << made.output;

  const fs::path s = out / "study";
  for (const char* file :
       {"run/punch.csv", "run/time.txt", "report/report.html", "report/metrics.json",
        "report/stress_strain.svg", "sweep/sweep.csv", "sweep/peak_stress_beta.svg",
        "sweep/peak_stress_lambda.svg", "sweep/report/report.html"})
    EXPECT_TRUE(fs::exists(s / file)) << file;

  // One row per sweep point, β and λp as named, every peak positive.
  const CsvTable sweep = read_csv(s / "sweep" / "sweep.csv");
  const std::vector<double> beta = sweep.column("beta"), lambda = sweep.column("lambda_p"),
                            peak = sweep.column("peak_stress_MPa");
  ASSERT_EQ(beta.size(), 3u);
  std::map<std::pair<double, double>, double> peaks;
  for (std::size_t i = 0; i < beta.size(); ++i) {
    EXPECT_GT(peak[i], 0.0) << "beta " << beta[i] << ", lambda_p " << lambda[i];
    peaks[{beta[i], lambda[i]}] = peak[i];
    std::printf("beta %g, lambda_p %g: peak %g MPa\n", beta[i], lambda[i], peak[i]);
  }
  ASSERT_EQ(peaks.size(), 3u);
  // Eq. 6's β ν π R δ 3p term adds to every contact's force: β = 1.3 presses harder than β = 0.
  const double table4 = peaks[{1.3, 0.3}], without = peaks[{0.0, 0.3}];
  EXPECT_GT(table4, without);
  // The sweep's β = 1.3, λp = 0.3 point is the reference run's config without snapshots: the same
  // bits, so the same peak as the reference run's SUMMARY (to the table's 6 digits).
  const double reference = summary_peak_stress(s / "run" / "summary.txt") / 1e6;
  EXPECT_NEAR(table4, reference, 1e-5 * reference);

  // Nothing is out of date: `make -q` exits 0 only when no rule would run.
  const auto again = run_command(study + " -q");
  EXPECT_EQ(again.exit_code, 0) << again.output;
}

}  // namespace
}  // namespace shapepress
