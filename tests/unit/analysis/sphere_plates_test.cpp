#include "analysis/sphere_plates.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.hpp"

namespace shapepress::analysis {
namespace {

const ElasticSphere rubber{0.01, 18.5e6, 0.46};  // the paper's rubber sphere

TEST(SpherePlates, HertzIsTwoContactsInSeries) {
  // Each plate contact takes Δ/2: F = (4/3) E* √R (Δ/2)^{3/2} = (√2/3) E* √R Δ^{3/2}.
  const double delta = 1e-3;
  const double per_contact = 4.0 / 3.0 * rubber.effective_modulus() * std::sqrt(rubber.radius) *
                             std::pow(delta / 2.0, 1.5);
  EXPECT_NEAR(hertz_plate_force(rubber, delta), per_contact, 1e-12 * per_contact);
  EXPECT_EQ(hertz_plate_force(rubber, -1e-3), 0.0);
  EXPECT_NEAR(rubber.effective_modulus(), 18.5e6 / (1 - 0.46 * 0.46), 1e-6);
}

TEST(SpherePlates, TataraInversionReproducesTheApproach) {
  for (double deformation : {1e-4, 0.01, 0.1, 0.25, 0.4}) {
    const double delta = 2.0 * rubber.radius * deformation;
    const double f = tatara_plate_force(rubber, delta);
    EXPECT_NEAR(tatara_plate_approach(rubber, f), delta, 1e-11 * delta) << deformation;
  }
}

TEST(SpherePlates, TataraTendsToHertzAtSmallDeformationAndIsStifferAtLarge) {
  // The Boussinesq term grows like F while Hertz's approach grows like F^{2/3}: the ratio tends
  // to 1 as Δ → 0 (as Δ^{1/2}), and Tatara is stiffer at every deformation.
  const double small = 2.0 * rubber.radius * 1e-6;
  EXPECT_NEAR(tatara_plate_force(rubber, small) / hertz_plate_force(rubber, small), 1.0, 2e-3);
  double previous = 1.0;
  for (double deformation : {0.05, 0.1, 0.2, 0.3, 0.4}) {
    const double delta = 2.0 * rubber.radius * deformation;
    const double ratio = tatara_plate_force(rubber, delta) / hertz_plate_force(rubber, delta);
    EXPECT_GT(ratio, previous);
    previous = ratio;
  }
}

TEST(SpherePlates, CheckRejectsNonPhysicalSpheres) {
  EXPECT_THROW((ElasticSphere{0.0, 1e6, 0.3}.check()), InputError);
  EXPECT_THROW((ElasticSphere{0.01, -1.0, 0.3}.check()), InputError);
  EXPECT_THROW((ElasticSphere{0.01, 1e6, 0.5}.check()), InputError);
  EXPECT_NO_THROW(rubber.check());
}

}  // namespace
}  // namespace shapepress::analysis
