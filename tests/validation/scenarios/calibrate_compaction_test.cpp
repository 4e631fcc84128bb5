// Calibration on a compaction curve recovers a known parameter: the target is the solid
// fraction–stress curve (Fig. 8's axes) shapepress made with k1 = 2e6 N/m^1.5 on one poured bed
// (seed 1), written in MPa and % as a measured curve would be; `calibrate` fits k1 on a bed
// poured with another seed (2) from a start 40 % too low. The two beds differ, so the fit cannot
// be exact; their difference at the true k1 bounds it. On one bed the stress at a given solid
// fraction scales with k1 (every contact force is k1 δ^{3/2}, and the β term follows the
// pressure), so the fitted k1/k1_true is the stress ratio σ1/σ2 of the two beds at equal solid
// fraction where the fit is made, an average of it: it lies between that ratio's smallest and
// largest value over the window, and (for a plain average) within its RMS scatter about 1, the
// seed-to-seed scatter. Then a calibration interrupted after three evaluations and resumed from
// its evaluations.csv ends where the uninterrupted one did, running only the ones it lacked.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/compaction.hpp"
#include "analysis/runs.hpp"
#include "common/csv.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using shapepress::testing::fresh_directory;
using shapepress::testing::read_text;
using shapepress::testing::run_shapepress;
using shapepress::testing::test_data_text;
using shapepress::testing::write_text;
using ::testing::HasSubstr;

constexpr double true_k1 = 2e6;          // N/m^1.5, tests/data/scenarios/calibration-bed.toml's
constexpr double window_stress = 0.5e6;  // Pa: the fit and the bound from here to the peak

// The loading rows of a punch.csv: solid fraction and stress [Pa].
struct Loading {
  std::vector<double> solid_fraction, stress;
};
Loading loading_of(const std::filesystem::path& punch_csv) {
  const CsvTable t = read_csv(punch_csv);
  const auto phase = t.column("phase"), d = t.column("solid_fraction"), p = t.column("stress_Pa");
  Loading l;
  for (std::size_t i = 0; i < phase.size() && phase[i] == 0.0; ++i)
    if (l.solid_fraction.empty() || d[i] > l.solid_fraction.back())
      l.solid_fraction.push_back(d[i]), l.stress.push_back(p[i]);
  return l;
}

double stress_at(const Loading& l, double d) {
  const auto& x = l.solid_fraction;
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), d) - x.begin());
  if (i == 0) return l.stress.front();
  if (i == x.size()) return l.stress.back();
  const double t = (d - x[i - 1]) / (x[i] - x[i - 1]);
  return l.stress[i - 1] + t * (l.stress[i] - l.stress[i - 1]);
}

double fitted(const std::filesystem::path& calibration_csv, const std::string& parameter) {
  std::ifstream in(calibration_csv);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(parameter + ",", 0) == 0) return std::stod(line.substr(line.rfind(',') + 1));
  return NAN;
}

// The evaluations.csv rows without their wall seconds (which differ between runs).
std::string evaluations_without_time(const std::filesystem::path& csv) {
  std::istringstream in(read_text(csv));
  std::string out, line;
  while (std::getline(in, line))
    out += (line.empty() || line[0] == '#' ? line : line.substr(0, line.rfind(','))) + "\n";
  return out;
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
    ++n;
  return n;
}

TEST(CompactionCalibration, RecoversTheLoadingStiffnessWithinTheSeedToSeedScatter) {
  const auto dir = fresh_directory("calibrate_compaction");
  const std::string bed = test_data_text("scenarios/calibration-bed.toml");
  write_text(dir / "seed1.toml", bed);
  write_text(dir / "seed2.toml",
             std::regex_replace(bed, std::regex("\nseed = 1\n"), "\nseed = 2\n"));
  for (const char* seed : {"seed1", "seed2"}) {
    const auto run = run_shapepress("--threads 2 --quiet compact --config " +
                                    (dir / (std::string(seed) + ".toml")).string() + " --out " +
                                    (dir / seed).string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
  }
  // The target, seed 1's loading curve in the units of a digitised figure.
  const Loading one = loading_of(dir / "seed1" / "punch.csv");
  std::string target =
      "# seed 1 of tests/data/scenarios/calibration-bed.toml\nstress_MPa,solid_fraction_%\n";
  for (std::size_t i = 0; i < one.stress.size(); ++i)
    target += std::to_string(one.stress[i] / 1e6) + "," +
              std::to_string(100 * one.solid_fraction[i]) + "\n";
  write_text(dir / "target.csv", target);
  // The two beds at the true k1: q = σ1/σ2 at seed 1's solid fractions above the window's stress.
  const Loading two = loading_of(dir / "seed2" / "punch.csv");
  double q_min = HUGE_VAL, q_max = 0.0, q_square = 0.0;
  int points = 0;
  for (std::size_t i = 0; i < one.stress.size(); ++i) {
    if (one.stress[i] < window_stress || one.solid_fraction[i] > two.solid_fraction.back())
      continue;
    const double q = one.stress[i] / stress_at(two, one.solid_fraction[i]);
    q_min = std::min(q_min, q), q_max = std::max(q_max, q), q_square += (q - 1) * (q - 1);
    ++points;
  }
  ASSERT_GT(points, 20);
  const double scatter = std::sqrt(q_square / points);

  // Seed 2's bed from k1 = 0.6 × the truth, over stresses from 0.5 MPa up.
  const std::string common =
      " calibrate --config " + (dir / "seed2.toml").string() + " --reference " +
      (dir / "target.csv").string() +
      " --fit loading_stiffness --start loading_stiffness=" + std::to_string(0.6 * true_k1) +
      " --from 0.5MPa --max-evaluations 12 --out ";
  const auto calibration = run_shapepress("--threads 2" + common + (dir / "cal").string());
  ASSERT_EQ(calibration.exit_code, 0) << calibration.output;
  const double ratio = fitted(dir / "cal" / "calibration.csv", "loading_stiffness") / true_k1;
  std::cout << "fitted k1 / true k1 = " << ratio << "; seed 1 / seed 2 stress at equal solid "
            << "fraction: " << q_min << " to " << q_max << ", RMS scatter " << scatter << "\n";
  EXPECT_GE(ratio, q_min);
  EXPECT_LE(ratio, q_max);
  EXPECT_LT(std::abs(ratio - 1.0), scatter);
  EXPECT_GT(q_min, 0.6);  // the start lies outside: the fit had to move
  EXPECT_THAT(read_text(dir / "cal" / "calibrated.toml"), HasSubstr("loading_stiffness = "));
  EXPECT_TRUE(std::filesystem::exists(dir / "cal" / "punch.csv"));

  // Interrupted after 3 evaluations: calibrate.json and the first three rows of
  // evaluations.csv, as a killed calibration leaves them.
  const auto part = dir / "part";
  std::filesystem::create_directories(part);
  std::istringstream rows(read_text(dir / "cal" / "evaluations.csv"));
  std::string kept, line;
  int data_rows = -1;  // the header is the first non-comment line
  while (std::getline(rows, line) && data_rows < 3) {
    kept += line + "\n";
    if (!line.empty() && line[0] != '#') ++data_rows;
  }
  write_text(part / "evaluations.csv", kept);
  // calibrate.json names the first folder as its output: this one instead.
  write_text(part / "calibrate.json",
             std::regex_replace(read_text(dir / "cal" / "calibrate.json"),
                                std::regex((dir / "cal").string()), part.string()));
  const auto resumed = run_shapepress("--threads 2 calibrate --resume " + part.string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(read_text(part / "calibration.csv"), read_text(dir / "cal" / "calibration.csv"));
  EXPECT_EQ(evaluations_without_time(part / "evaluations.csv"),
            evaluations_without_time(dir / "cal" / "evaluations.csv"));
  // The three from the file, and the points the search revisits as the first run did.
  EXPECT_EQ(count_of(resumed.output, "reused, not run again"),
            count_of(calibration.output, "reused, not run again") + 3);
}

// A recovery target beside the curve (calibrate --target-recovery): on one bed the loading
// curve does not depend on the multi-contact law's λp (it sets the unloading branch only), so
// the curve cannot tell λp apart and the recovery must. The target is the bed's own run at
// λp = 0.3; the fit starts at 0.6 (a stiffer unloading, a smaller recovery) and must come back
// to the target's recovery and λp. Without the target the search has nothing to move λp by.
TEST(CompactionCalibration, ARecoveryTargetFitsTheUnloadingTheCurveCannotSee) {
  const auto dir = fresh_directory("calibrate_recovery");
  write_text(dir / "bed.toml", test_data_text("scenarios/calibration-bed.toml"));
  const auto truth =
      run_shapepress("--threads 2 --quiet compact --config " + (dir / "bed.toml").string() +
                     " --out " + (dir / "truth").string());
  ASSERT_EQ(truth.exit_code, 0) << truth.output;
  const Loading loading = loading_of(dir / "truth" / "punch.csv");
  std::string target = "stress_MPa,solid_fraction_%\n";
  for (std::size_t i = 0; i < loading.stress.size(); ++i)
    target += std::to_string(loading.stress[i] / 1e6) + "," +
              std::to_string(100 * loading.solid_fraction[i]) + "\n";
  write_text(dir / "target.csv", target);
  // The recovery as `report` reads it from punch.csv.
  const double recovery =
      analysis::analyse_compaction(analysis::read_punch_curve(dir / "truth" / "punch.csv"))
          .elastic_recovery;
  ASSERT_GT(recovery, 0.005);

  const std::string common = " calibrate --config " + (dir / "bed.toml").string() +
                             " --reference " + (dir / "target.csv").string() +
                             " --fit plasticity_ratio --start plasticity_ratio=0.6 --from 0.5MPa "
                             "--max-evaluations 12";
  const auto fit =
      run_shapepress("--threads 2" + common + " --target-recovery " +
                     std::to_string(100.0 * recovery) + " --out " + (dir / "cal").string());
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  const std::string fitted_json = read_text(dir / "cal" / "run.json");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(fitted_json, m, std::regex("\"elastic_recovery\": ([0-9.eE+-]+)")));
  std::cout << "target recovery " << recovery << ", fitted " << m[1] << ", lambda_p "
            << fitted(dir / "cal" / "calibration.csv", "plasticity_ratio") << "\n";
  EXPECT_NEAR(std::stod(m[1]), recovery, 0.02 * recovery);
  EXPECT_NEAR(fitted(dir / "cal" / "calibration.csv", "plasticity_ratio"), 0.3, 0.015);
  EXPECT_THAT(read_text(dir / "cal" / "calibrated.toml"), HasSubstr("elastic recovery"));

  // A target on a run that never unloads is the user's error, named.
  write_text(dir / "no-unload.toml",
             std::regex_replace(test_data_text("scenarios/calibration-bed.toml"),
                                std::regex("unload_speed = [^\n]*\n"), ""));
  const auto refused = run_shapepress(
      "--threads 2 calibrate --config " + (dir / "no-unload.toml").string() + " --reference " +
      (dir / "target.csv").string() + " --fit plasticity_ratio --target-recovery 5 --out " +
      (dir / "refused").string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("unload_speed"));
}

}  // namespace
}  // namespace shapepress
