// compact's quasi-static judgement on hand-made records: loading and unloading judged each on
// its own records from a tenth of the peak, the kinetic energy of unloading against the work the
// punch had done when unloading began, and the inertial number ε̇ d √(ρ/σ) of each record.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "scenarios/compact.hpp"

namespace shapepress::scenarios {
namespace {

PunchRecord record(double time, double gap, double stress, PunchPhase phase, double work,
                   double kinetic) {
  PunchRecord r;
  r.time = time;
  r.gap = gap;
  r.stress = stress;
  r.top_force = stress * 1e-6;
  r.bottom_force = 0.99 * r.top_force;
  r.phase = phase;
  r.punch_work = work;
  r.kinetic_energy = kinetic;
  return r;
}

TEST(QuasiStatic, LoadingAndUnloadingAreJudgedEachOnItsOwn) {
  // Loading: 1 mm → 0.9 mm in 10 records of 1 ms (a strain rate near 0.1/ms), stress to 10 MPa,
  // kinetic energy a thousandth of the work. Unloading: the gap back up at the same rate, the
  // stress down, with a kinetic energy that is 5 % of the work done at the end of loading.
  std::vector<PunchRecord> records;
  double work = 0.0;
  for (int k = 0; k <= 10; ++k) {
    work += k * 1e-6;
    records.push_back(
        record(1e-3 * k, 1e-3 - 1e-5 * k, 1e6 * k, PunchPhase::load, work, 1e-3 * work));
  }
  const double loaded_work = work;
  for (int k = 1; k <= 5; ++k)
    records.push_back(record(1e-2 + 1e-3 * k, 0.9e-3 + 1e-5 * k, 1e7 - 2e6 * k, PunchPhase::unload,
                             work - 1e-6 * k, 0.05 * loaded_work));
  const InertialScale scale{250e-6, 1541.0 * 100.0};
  const QuasiStaticCheck check = quasi_static_check(records, scale);
  // Loading records from 1 MPa on (a tenth of the peak); the first one's rate is from the record
  // at zero stress before it.
  EXPECT_EQ(check.records, 10);
  EXPECT_NEAR(check.max_kinetic_to_work, 1e-3, 1e-12);
  EXPECT_NEAR(check.mean_force_imbalance, 0.01, 1e-12);
  // The largest I of loading is at its lowest judged stress, 1 MPa, with ε̇ = 1e-5/1e-3/gap.
  const double rate = 1e-5 / 1e-3 / (1e-3 - 1e-5);
  EXPECT_NEAR(check.max_inertial_number, rate * 250e-6 * std::sqrt(1541.0 * 100.0 / 1e6),
              1e-12 * check.max_inertial_number);
  // Unloading: the records at 8, 6, 4 and 2 MPa (0 MPa is below a tenth of the peak).
  EXPECT_EQ(check.unload.records, 4);
  EXPECT_NEAR(check.unload.max_kinetic_to_work, 0.05, 1e-12);
  EXPECT_FALSE(check.unload.quasi_static());  // 5 % of the work in motion
  EXPECT_FALSE(check.quasi_static());         // so the run is not
  // Without unloading records the run is judged by its loading alone.
  records.resize(11);
  const QuasiStaticCheck loading_only = quasi_static_check(records, scale);
  EXPECT_EQ(loading_only.unload.records, 0);
  EXPECT_EQ(loading_only.quasi_static(), loading_only.PhaseQuasiStatic::quasi_static());
}

TEST(QuasiStatic, TheInertialNumberGrowsAsTheSquareRootOfTheMassScaling) {
  std::vector<PunchRecord> records;
  for (int k = 0; k <= 10; ++k)
    records.push_back(
        record(1e-3 * k, 1e-3 - 1e-6 * k, 1e5 * k + 1e5, PunchPhase::load, 1e-6 * (k + 1), 0.0));
  const double plain = quasi_static_check(records, {250e-6, 1541.0}).max_inertial_number;
  const double scaled = quasi_static_check(records, {250e-6, 1541.0 * 100.0}).max_inertial_number;
  EXPECT_GT(plain, 0.0);
  EXPECT_NEAR(scaled / plain, 10.0, 1e-9);
  // No scale given (a caller without the bed's size): no inertial number, not a false one.
  EXPECT_EQ(quasi_static_check(records).max_inertial_number, 0.0);
}

}  // namespace
}  // namespace shapepress::scenarios
