// Hertz and Tatara plate forces against the tabulated theory curves for the paper's rubber
// sphere (R = 10 mm, E = 18.5 MPa, ν = 0.46), tests/data/analysis/tatara_hertz_*.csv.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/sphere_plates.hpp"
#include "common/csv.hpp"

namespace shapepress::analysis {
namespace {

TEST(TataraReference, HertzAndTataraMatchTheTabulatedTheoryCurves) {
  const CsvTable table = read_csv(std::string(SHAPEPRESS_TEST_DATA) +
                                  "/analysis/tatara_hertz_R10mm_E18.5MPa_nu0.46.csv");
  const std::vector<double> delta = table.column("Delta_m");
  const std::vector<double> hertz = table.column("F_hertz_N");
  const std::vector<double> tatara = table.column("F_tatara_N");
  const ElasticSphere rubber{0.01, 18.5e6, 0.46};
  ASSERT_EQ(delta.size(), 41u);  // 0 to 40 % deformation by 1 %
  int compared = 0;
  for (std::size_t i = 1; i < delta.size(); ++i) {
    // The table holds 7 significant digits ("%.6e"): agreement to 1e-6 is the table's own
    // resolution, not a modelling tolerance. It is a theory curve, so nothing looser is needed.
    EXPECT_NEAR(hertz_plate_force(rubber, delta[i]), hertz[i], 1e-6 * hertz[i]) << delta[i];
    EXPECT_NEAR(tatara_plate_force(rubber, delta[i]), tatara[i], 1e-6 * tatara[i]) << delta[i];
    ++compared;
  }
  EXPECT_EQ(compared, 40);
  // The large-deformation correction matters: Tatara is 59 % above Hertz at 40 % deformation.
  const double d = delta.back();
  EXPECT_NEAR(tatara_plate_force(rubber, d) / hertz_plate_force(rubber, d), 1.59295, 1e-5);
}

}  // namespace
}  // namespace shapepress::analysis
