// The paper's MC-DEM rubber sphere (Giannis et al. 2023 §3.1, Fig. 1, Table 1's β = 1.71): one
// sphere with the multi-contact law between plates against Tatara's large-deformation curve over
// 5–40 % (docs/models.md, "Which reading of Eq. 6"; docs/measurements.md, "Multi-contact
// sphere against Tatara"). The default suite runs the shipped config (about 1 s); the full
// validation (SHAPEPRESS_FULL_VALIDATION=1) the same at a quarter of the plate speed, which must
// give the same curve (quasi-static).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "common/config.hpp"
#include "common/csv.hpp"
#include "scenarios/plate_run.hpp"
#include "tests/support/files.hpp"
#include "tests/validation/scenarios/scenes.hpp"

namespace shapepress::scenarios {
namespace {

using testing::full_validation;

// The run's top force at deformation x, linear between its rows.
double force_at(const std::vector<PlateRow>& rows, double x) {
  double d0 = 0.0, f0 = 0.0;
  for (const PlateRow& row : rows) {
    if (row.deformation >= x) return f0 + (x - d0) / (row.deformation - d0) * (row.top_force - f0);
    d0 = row.deformation, f0 = row.top_force;
  }
  ADD_FAILURE() << "the run did not reach deformation " << x;
  return 0.0;
}

TEST(MulticontactSphere, PaperBetaFollowsTataraWithinTwelvePercentRms) {
  const std::filesystem::path repo = shapepress::testing::repository_root();
  const ConfigTable root =
      ConfigTable::load_file(repo / "pipelines/configs/plate-rubber-sphere-multicontact.toml");
  PlateConfig config = read_plate_config(root);
  root.check_unknown_keys();
  if (full_validation()) config.setup.speed *= 0.25;
  const PlateRunOutcome run = run_plate_config(config, false);
  const CsvTable t = read_csv(std::filesystem::path(SHAPEPRESS_TEST_DATA) / "analysis" /
                              "tatara_hertz_R10mm_E18.5MPa_nu0.46.csv");
  const std::vector<double> deformation = t.column("deformation"), tatara = t.column("F_tatara_N"),
                            hertz = t.column("F_hertz_N");
  double sum = 0.0, sum_hertz = 0.0;
  int points = 0;
  for (std::size_t k = 0; k < deformation.size(); ++k) {
    if (deformation[k] < 0.05 - 1e-9 || deformation[k] > 0.40 + 1e-9) continue;
    const double f = force_at(run.rows, deformation[k]);
    const double e = (f - tatara[k]) / tatara[k], e_hertz = (hertz[k] - tatara[k]) / tatara[k];
    sum += e * e, sum_hertz += e_hertz * e_hertz;
    ++points;
    // Between Hertz and 20 % above Tatara at every percent: the term stiffens, never runs away.
    EXPECT_GT(f, hertz[k]) << "at deformation " << deformation[k];
    EXPECT_LT(f, 1.2 * tatara[k]) << "at deformation " << deformation[k];
  }
  ASSERT_EQ(points, 36);
  const double rms = std::sqrt(sum / points), rms_hertz = std::sqrt(sum_hertz / points);
  // Measured 0.106 (the reading's closed form gives the same, docs/models.md); Hertz is 0.286.
  EXPECT_LT(rms, 0.12);
  EXPECT_LT(rms, 0.5 * rms_hertz);
}

}  // namespace
}  // namespace shapepress::scenarios
