// A BMS body with elastic–plastic bonds loaded past yield and unloaded in the plate rig
// (issue 37, item 2):
//  - against the elastic–plastic FEM of the same sphere, loaded and unloaded (reference data in
//    tests/data/fem, made by `shapepress fem-plate`, the command in its first comment line): the
//    body keeps the deformation the FEM keeps, and carries its peak force, within the tolerances
//    below, with the bond yield stress and hardening calibrated against that curve
//    (docs/measurements.md, "The elastic–plastic FEM and bodies that keep their deformation");
//  - calibrate's fit of the bond yield stress and hardening ratio recovers them from a synthetic
//    target: the body's own curve at known values, loaded and unloaded.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <variant>

#include "common/config.hpp"
#include "common/csv.hpp"
#include "scenarios/calibrate.hpp"
#include "scenarios/plate_run.hpp"
#include "tests/support/files.hpp"

namespace shapepress::scenarios {
namespace {

const std::filesystem::path repo = shapepress::testing::repository_root();

// calibrate's fit of the N = 545 body against tests/data/fem/plastic_sphere_force.csv (20
// evaluations from σy = 1.2 MPa, H = 0.1; RMS 7.8 % loading, 8.6 % of the peak unloading), and
// the tolerances of KeepsThePlasticDeformationTheFemGives. Measured (docs/measurements.md, "The
// elastic–plastic FEM and bodies that keep their deformation"): the body peaks 5.8 % above the
// FEM and keeps deformation 0.095 where the FEM keeps 0.137. The fit weighs the whole curve, and
// the body's unloading is softer near the end than the continuum's (its last sub-spheres leave
// the plates one by one: 5 N left at 0.11, where the FEM has let go): it keeps 69 % of the FEM's
// plastic deformation. The tolerances hold that (0.05 of deformation, 8 % of the peak) and fail
// a body that keeps less than 0.087 (63 % of the FEM's), as the elastic body does (below).
constexpr double fitted_yield_stress = 788602.0, fitted_hardening_ratio = 0.0385093;
constexpr double residual_tolerance = 0.05, peak_tolerance = 0.08;

// The shipped rubber sphere (its elastic network calibrated against the elastic FEM and
// Tatara), with elastic–plastic bonds, pressed to `max_deformation` and unloaded.
PlateConfig plastic_body(int count, double max_deformation, int records, double yield_stress,
                         double hardening_ratio) {
  const ConfigTable root = ConfigTable::load_file(repo / "pipelines/configs/rubber-sphere.toml");
  PlateConfig c = read_plate_config(root);
  c.bms->count = count;
  c.bms->fills = 1;
  c.setup.max_deformation = max_deformation;
  c.setup.records = records;
  c.setup.unload = true;
  ElasticPlasticBond bond;
  bond.yield_stress = yield_stress;
  bond.hardening_ratio = hardening_ratio;
  c.bms->bond.model = bond;
  return c;
}

// The loading (step 1) and unloading (step 2) rows of a force.csv with a `step` column.
struct Branches {
  std::vector<double> loading_deformation, loading_force;
  std::vector<double> unloading_deformation, unloading_force;
  std::vector<PlateRow> rows;  // loading then unloading, for plate_unloading
  int records = 0;             // loading rows
};

Branches branches(const std::vector<double>& step, const std::vector<double>& deformation,
                  const std::vector<double>& force, double height) {
  Branches b;
  for (std::size_t k = 0; k < step.size(); ++k) {
    PlateRow row;
    row.deformation = deformation[k];
    row.approach = deformation[k] * height;
    row.top_force = force[k];
    b.rows.push_back(row);
    if (step[k] == 1.0) {
      ++b.records;
      b.loading_deformation.push_back(deformation[k]);
      b.loading_force.push_back(force[k]);
    } else {
      b.unloading_deformation.push_back(deformation[k]);
      b.unloading_force.push_back(force[k]);
    }
  }
  return b;
}

Branches branches_of(const PlateRunOutcome& run, int records, double height) {
  std::vector<double> step, deformation, force;
  for (std::size_t k = 0; k < run.rows.size(); ++k) {
    step.push_back(static_cast<int>(k) < records ? 1.0 : 2.0);
    deformation.push_back(run.rows[k].deformation);
    force.push_back(run.rows[k].top_force);
  }
  return branches(step, deformation, force, height);
}

TEST(PlasticBody, KeepsThePlasticDeformationTheFemGives) {
  // The FEM: the rubber sphere's elasticity with σy = 1 MPa, H = 1 MPa, pressed to 20 % and
  // unloaded (tests/data/fem/plastic_sphere.toml). The body: the shipped N = 545 network with
  // elastic–plastic bonds at the values `calibrate --fit yield_stress,hardening_ratio` found
  // against that curve (docs/measurements.md, "The elastic–plastic FEM and bodies that keep their
  // deformation").
  const CsvTable fem =
      read_csv(std::filesystem::path(SHAPEPRESS_TEST_DATA) / "fem" / "plastic_sphere_force.csv");
  const Branches reference =
      branches(fem.column("step"), fem.column("deformation"), fem.column("top_force_N"), 0.02);
  const PlateUnloading fem_kept = plate_unloading(reference.rows, reference.records);
  const PlateConfig config =
      plastic_body(545, 0.2, 20, fitted_yield_stress, fitted_hardening_ratio);
  const PlateRunOutcome body = run_plate_config(config, PlateParticleKind::bms);
  ASSERT_EQ(body.rows.size(), 40u);
  const PlateUnloading body_kept = plate_unloading(body.rows, 20);
  std::printf(
      "FEM: peak %.4g N, keeps deformation %.4g; body: peak %.4g N (%+.1f %%), keeps %.4g "
      "(%+.4f)\n",
      fem_kept.peak_force, fem_kept.residual_deformation, body_kept.peak_force,
      100.0 * (body_kept.peak_force / fem_kept.peak_force - 1.0), body_kept.residual_deformation,
      body_kept.residual_deformation - fem_kept.residual_deformation);
  EXPECT_NEAR(body_kept.residual_deformation, fem_kept.residual_deformation, residual_tolerance);
  EXPECT_NEAR(body_kept.peak_force, fem_kept.peak_force, peak_tolerance * fem_kept.peak_force);
  // Without plasticity the same body springs back: the deformation kept is the bonds' doing.
  PlateConfig elastic_config = config;
  elastic_config.bms->bond.model = ElasticBond{};
  const PlateRunOutcome elastic = run_plate_config(elastic_config, PlateParticleKind::bms);
  EXPECT_LT(plate_unloading(elastic.rows, 20).residual_deformation,
            0.25 * fem_kept.residual_deformation);
}

TEST(PlasticBody, CalibrationRecoversAKnownYieldStressAndHardening) {
  // The target: the body's own curve at σy = 1.5 MPa, H = 0.2, loaded to 20 % and unloaded. The
  // fit starts 60 % above σy and at twice H, and must come back within 3 % of each: the
  // objective is the same code's curve, so only the search's tolerance stands between.
  constexpr double yield_stress = 1.5e6, hardening_ratio = 0.2;
  constexpr int count = 100, records = 20;
  const PlateConfig target_config =
      plastic_body(count, 0.2, records, yield_stress, hardening_ratio);
  const PlateRunOutcome target = run_plate_config(target_config, PlateParticleKind::bms);
  ASSERT_EQ(target.rows.size(), 2u * records);
  const PlateUnloading kept = plate_unloading(target.rows, records);
  std::printf("target: peak %.4g N, keeps deformation %.4g unloaded\n", kept.peak_force,
              kept.residual_deformation);
  ASSERT_GT(kept.residual_deformation, 0.02);  // it yielded

  const Branches b = branches_of(target, records, 2.0 * target_config.setup.radius);
  CalibrationOptions options;
  options.parameters = {"yield_stress", "hardening_ratio"};
  options.reference_deformation = b.loading_deformation;
  options.reference_force = b.loading_force;
  // The unloading from the turn: the last loading row, then step 2's.
  options.reference_unloading_deformation = {b.loading_deformation.back()};
  options.reference_unloading_force = {b.loading_force.back()};
  options.reference_unloading_deformation.insert(options.reference_unloading_deformation.end(),
                                                 b.unloading_deformation.begin(),
                                                 b.unloading_deformation.end());
  options.reference_unloading_force.insert(options.reference_unloading_force.end(),
                                           b.unloading_force.begin(), b.unloading_force.end());
  options.from = 0.02;
  options.to = 0.2;
  options.start = {{"yield_stress", 1.6 * yield_stress},
                   {"hardening_ratio", 2.0 * hardening_ratio}};
  options.initial_factor = 1.5;
  options.max_evaluations = 60;
  PlateConfig start = target_config;
  const CalibrationResult fit = calibrate_plate(start, options);
  std::printf(
      "fitted sigma_y = %.5g Pa, H = %.5g after %zu runs: loading RMS %.3g, unloading %.3g\n",
      fit.values[0], fit.values[1], fit.evaluations.size(), fit.loading_rms_relative,
      fit.unloading_rms);
  EXPECT_NEAR(fit.values[0], yield_stress, 0.03 * yield_stress);
  EXPECT_NEAR(fit.values[1], hardening_ratio, 0.03 * hardening_ratio);
  EXPECT_LT(fit.rms_relative, 0.01);
}

}  // namespace
}  // namespace shapepress::scenarios
