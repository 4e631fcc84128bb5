// packed.h5 and the engine state made from it: what `pack` writes reads back whole, a scaled
// template keeps its shape's mass and inertia, bonds stay within bodies and start force-free,
// and a file whose bond joins two bodies is refused naming the dataset.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "common/error.hpp"
#include "geometry/template_quality.hpp"
#include "packing/bed_state.hpp"
#include "packing/body_packing.hpp"
#include "simulate/clumps.hpp"
#include "tests/support/body_beds.hpp"
#include "tests/support/errors.hpp"
#include "tests/support/files.hpp"

namespace shapepress::packing {
namespace {

using shapepress::testing::cluster_bed;
using shapepress::testing::fresh_directory;
using shapepress::testing::input_error_of;
using ::testing::HasSubstr;

constexpr double r = 20e-6;

TEST(BodyPacking, WritesAndReadsBackEveryBodyParticleAndBond) {
  BodyPacking p = cluster_bed(BodyKind::bms, r, 2, 2, 3, 0.3);
  p.measures.solid_fraction_shape = 0.59;
  p.measures.orientation_order = -0.02;
  const auto file = fresh_directory("body_packing_round_trip") / "packed.h5";
  write_packing(file, p, Provenance{"test", "", 3});
  ASSERT_TRUE(std::filesystem::exists(file.parent_path() / "packed.xmf"));
  EXPECT_TRUE(is_body_packing(file));
  const BodyPacking q = read_packing(file);
  ASSERT_EQ(q.size(), p.size());
  EXPECT_EQ(q.templates[0].name, "bms/cluster13");
  EXPECT_EQ(q.templates[0].bonds, p.templates[0].bonds);
  EXPECT_EQ(q.particles.x, p.particles.x);
  EXPECT_EQ(q.particles.radius, p.particles.radius);
  EXPECT_EQ(q.particle_body, p.particle_body);
  EXPECT_EQ(q.first_particle, p.first_particle);
  EXPECT_EQ(q.bonds, p.bonds);
  EXPECT_EQ(q.bond_rest_length, p.bond_rest_length);
  for (std::size_t b = 0; b < p.size(); ++b) {
    EXPECT_EQ(q.bodies[b].scale, p.bodies[b].scale);
    EXPECT_EQ(q.bodies[b].centre, p.bodies[b].centre);
    EXPECT_NEAR(q.bodies[b].orientation.w, p.bodies[b].orientation.w, 1e-15);
  }
  EXPECT_EQ(q.box.length_x, p.box.length_x);
  EXPECT_EQ(q.top, p.top);
  EXPECT_EQ(q.measures.solid_fraction_shape, 0.59);
  EXPECT_EQ(q.measures.orientation_order, -0.02);
}

TEST(BodyPacking, NoBondJoinsTwoBodiesAndBondsStartForceFree) {
  const BodyPacking p = cluster_bed(BodyKind::bms, r, 3, 2);
  ASSERT_EQ(p.bonds.size(), p.size() * 36);  // 12 spokes and 24 rim bonds per cluster
  for (const auto& [i, j] : p.bonds)
    EXPECT_EQ(p.particle_body[static_cast<std::size_t>(i)],
              p.particle_body[static_cast<std::size_t>(j)]);
  BedRequest request{1541.0, 0, BondParameters{}, false};
  const Bed bed = bed_from_packing(p, request);
  ASSERT_EQ(bed.bonds.size(), p.bonds.size());
  for (const double normal_force : bed.bonds.history.normal_force)
    EXPECT_NEAR(normal_force, 0.0, 1e-12 * bed.bonds.normal_spring[0] * r);
  // A sub-sphere's body id is its body's first particle.
  for (std::size_t i = 0; i < bed.state.size(); ++i)
    EXPECT_EQ(bed.state.body[i], p.first_particle[static_cast<std::size_t>(p.particle_body[i])]);
  EXPECT_NEAR(bed.sphere_volume / bed.shape_volume, 13.0 / 27.0, 1e-12);
}

// Contacts between bodies may take the bodies' curvature (contact_radius = "body"): every
// sub-sphere of a bonded body carries the radius of the sphere of its body's shape volume.
TEST(BodyPacking, EverySubSphereCarriesItsBodysVolumeEquivalentRadius) {
  BodyPacking p = cluster_bed(BodyKind::bms, r, 2, 1);
  p.bodies[1].scale = 0.7;
  p.bodies[1].shape_volume *= 0.7 * 0.7 * 0.7;
  place_bodies(p);
  const Bed bed = bed_from_packing(p, {1541.0, 0, BondParameters{}, false});
  for (std::size_t i = 0; i < bed.state.size(); ++i) {
    const PackedBody& body = p.bodies[static_cast<std::size_t>(p.particle_body[i])];
    ASSERT_GT(body.shape_volume, 0.0);
    EXPECT_NEAR(bed.state.body_radius[i],
                std::cbrt(3.0 * body.shape_volume / (4.0 * std::numbers::pi)),
                1e-12 * bed.state.body_radius[i]);
    EXPECT_GT(bed.state.body_radius[i], 2.0 * bed.state.radius[i]);
  }
}

TEST(BodyPacking, AStoredRestLengthLoadsTheBond) {
  BodyPacking p = cluster_bed(BodyKind::bms, r, 1, 1);
  p.bond_rest_length[0] *= 1.01;  // the bond pressed by 1 % of its length
  const Bed bed = bed_from_packing(p, {1541.0, 0, BondParameters{}, false});
  EXPECT_NEAR(bed.bonds.history.at(0).normal_force,
              bed.bonds.normal_spring[0] * 0.01 * bed.bonds.history.at(0).length,
              1e-9 * bed.bonds.normal_spring[0] * r);
}

// A body weighs ρ × its body volume (the union of its sub-spheres closed by a ball of their
// radius), at any scale, with that volume's inertia: as a rigid clump, and as bonded sub-spheres
// whose masses add up to it.
TEST(BodyPacking, AScaledBodyWeighsItsBodyVolumeWithItsInertia) {
  const double density = 1541.0, scale = 0.7;
  for (const BodyKind kind : {BodyKind::cms, BodyKind::bms}) {
    BodyPacking p = cluster_bed(kind, r, 1, 1);
    p.bodies[0].scale = scale;
    p.bodies[0].body_volume = 0.0;  // from the template at this scale
    place_bodies(p);
    BedRequest request{density, 0, BondParameters{}, true};
    const Bed bed = bed_from_packing(p, request);
    ASSERT_EQ(bed.clumps.size(), 1u);
    // The closed union of the placed sub-spheres, integrated on its own grid.
    std::vector<geometry::Vec3> centres;
    for (std::size_t i = 0; i < p.particles.size(); ++i)
      centres.emplace_back(p.particles.x[i], p.particles.y[i], p.particles.z[i]);
    const geometry::MassProperties g =
        geometry::closed_union_mass_properties(centres, p.particles.radius, scale * r, 1000);
    // 13 touching spheres hold more than their own volume once closed (the pores between them).
    const double s3 = scale * scale * scale;
    EXPECT_GT(g.volume, 1.2 * s3 * p.templates[0].sphere_volume);
    EXPECT_NEAR(bed.clumps.mass[0], density * g.volume, 0.01 * bed.clumps.mass[0]);
    EXPECT_DOUBLE_EQ(bed.clumps.mass[0], density * s3 * p.templates[0].body_volume);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(bed.clumps.rotation[0].principal_inertia[k], density * g.principal_moments[k],
                  0.02 * bed.clumps.rotation[0].principal_inertia[k]);
      EXPECT_DOUBLE_EQ(bed.clumps.rotation[0].principal_inertia[k],
                       density * s3 * scale * scale * p.templates[0].body_inertia[k]);
    }
    const Bed bonded = bed_from_packing(p, {density, 0, BondParameters{}, false});
    if (kind == BodyKind::bms) {
      double mass = 0.0;
      for (double m : bonded.state.mass)
        mass += m;
      EXPECT_NEAR(mass, bed.clumps.mass[0], 1e-12 * mass);
    }
    for (std::size_t i = 0; i < bed.state.size(); ++i)
      EXPECT_NEAR(bed.state.position.z[i], p.particles.z[i], 1e-15);
  }
}

TEST(BodyPacking, RefusesABondBetweenTwoBodiesNamingTheDataset) {
  BodyPacking p = cluster_bed(BodyKind::bms, r, 2, 1);
  p.bonds.back() = {0, 13};  // body 0's centre to body 1's
  const auto file = fresh_directory("body_packing_cross_bond") / "packed.h5";
  write_packing(file, p, Provenance{"test", "", std::nullopt});
  const std::string message = input_error_of([&] { read_packing(file); });
  EXPECT_THAT(message, HasSubstr("/bonds/pairs"));
  EXPECT_THAT(message, HasSubstr("bodies 0 and 1"));
  EXPECT_THAT(message, HasSubstr(file.string()));
}

TEST(BodyPacking, RefusesBmsBodiesWithoutBondParameters) {
  const BodyPacking p = cluster_bed(BodyKind::bms, r, 1, 1);
  EXPECT_THAT(input_error_of([&] {
                bed_from_packing(p, {1541.0, 0, std::nullopt, false});
              }),
              HasSubstr("[bond]"));
}

TEST(BodyPacking, IsNotASpherePackingOrAnyOtherFile) {
  const auto dir = fresh_directory("body_packing_kind");
  shapepress::testing::write_text(dir / "spheres.txt", "0 0 0 1e-3\n");
  EXPECT_FALSE(is_body_packing(dir / "spheres.txt"));
}

}  // namespace
}  // namespace shapepress::packing
