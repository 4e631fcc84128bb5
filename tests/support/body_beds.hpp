#pragma once
// Small beds of bodies for the tests of `compact --packing`, of packed.h5 and of pack: a
// 13-sphere BMS body (a centre and its 12 face-centred cubic neighbours, all touching, bonded to
// every touching neighbour) and the same cluster as a rigid CMS clump, laid on a lattice in a
// periodic die; and a rod of five spheres, an elongated BMS body.
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "packing/body_packing.hpp"

namespace shapepress::testing {

// The cluster of sub-sphere radius r in its body frame (symmetric: the centre of mass at the
// origin and any axes principal). Its shape is the circumscribed sphere of radius 3r.
inline packing::BodyTemplate cluster_template(packing::BodyKind kind, double r) {
  packing::BodyTemplate t;
  t.kind = kind;
  t.name = kind == packing::BodyKind::bms ? "bms/cluster13" : "cms/cluster13";
  t.source = "test";
  t.centres.push_back({0.0, 0.0, 0.0});
  const double a = 2.0 * r / std::numbers::sqrt2;  // neighbours at 2r from the centre
  for (int i = -1; i <= 1; i += 2)
    for (int j = -1; j <= 1; j += 2) {
      t.centres.push_back({i * a, j * a, 0.0});
      t.centres.push_back({i * a, 0.0, j * a});
      t.centres.push_back({0.0, i * a, j * a});
    }
  t.radii.assign(t.centres.size(), r);
  if (kind == packing::BodyKind::bms)
    for (std::int32_t i = 0; i < 13; ++i)
      for (std::int32_t j = i + 1; j < 13; ++j) {
        const auto& p = t.centres[static_cast<std::size_t>(i)];
        const auto& q = t.centres[static_cast<std::size_t>(j)];
        if (std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]) < 2.0 * r * 1.15)  // Eq. 10
          t.bonds.push_back({i, j});
      }
  const double v = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  t.sphere_volume = 13.0 * v;
  t.shape_volume = 4.0 / 3.0 * std::numbers::pi * 27.0 * r * r * r;
  // Own moments 13 × 2/5 v r², offsets Σ (|x|² - x_k²) = 12 (2r)² 2/3.
  const double moment = v * (13.0 * 0.4 * r * r + 32.0 * r * r);
  t.principal_inertia = {moment, moment, moment};
  return t;
}

// Five touching spheres in a row along x, 1.6 to 2e-5 m across, the middle one largest, bonded in
// a chain: an elongated BMS body (about 1 : 4.4) in its principal frame, whose bounding sphere
// holds several times its volume.
inline packing::BodyTemplate rod_template() {
  packing::BodyTemplate t;
  t.name = "bms/rod";
  t.source = "test";
  t.kind = packing::BodyKind::bms;
  const std::vector<double> r = {0.8, 0.9, 1.0, 0.9, 0.8};
  double x = -(r[0] + 2.0 * r[1] + r[2]);
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (i > 0) x += r[i - 1] + r[i];
    t.centres.push_back({x * 1e-5, 0.0, 0.0});
    t.radii.push_back(r[i] * 1e-5);
  }
  for (std::int32_t i = 0; i + 1 < 5; ++i)
    t.bonds.push_back({i, i + 1});
  for (double radius : t.radii)
    t.sphere_volume += 4.0 / 3.0 * std::numbers::pi * std::pow(radius, 3);
  t.shape_volume = t.sphere_volume;
  // About x the sub-spheres' own moments; about y and z the parallel-axis terms dominate.
  double own = 0.0, arm = 0.0;
  for (std::size_t i = 0; i < t.radii.size(); ++i) {
    const double v = 4.0 / 3.0 * std::numbers::pi * std::pow(t.radii[i], 3);
    own += 0.4 * v * t.radii[i] * t.radii[i];
    arm += v * t.centres[i][0] * t.centres[i][0];
  }
  t.principal_inertia = {own, own + arm, own + arm};
  packing::set_body_volume(t);
  return t;
}

// `layers` layers of `per_side` × `per_side` clusters of sub-sphere radius r, `pitch` apart (at
// least 6r, their diameter), in a periodic die of side per_side × pitch, turned at random (seed),
// at scale 1 or drawn in [1 - spread, 1].
inline packing::BodyPacking cluster_bed(packing::BodyKind kind, double r, int per_side, int layers,
                                        std::uint64_t seed = 7, double spread = 0.0,
                                        double pitch_in_radii = 7.0) {
  packing::BodyPacking p;
  p.templates.push_back(cluster_template(kind, r));
  const double pitch = pitch_in_radii * r;
  p.box = {per_side * pitch, per_side * pitch};
  p.floor = 0.0;
  p.top = layers * pitch;
  std::mt19937_64 random(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < layers; ++k)
    for (int j = 0; j < per_side; ++j)
      for (int i = 0; i < per_side; ++i) {
        packing::PackedBody b;
        b.scale = 1.0 - spread * unit(random);
        b.orientation =
            simulate::normalized({gauss(random), gauss(random), gauss(random), gauss(random)});
        b.centre = {(i + 0.5) * pitch, (j + 0.5) * pitch, (k + 0.5) * pitch};
        const double s3 = b.scale * b.scale * b.scale;
        b.shape_volume = s3 * p.templates[0].shape_volume;
        b.sphere_volume = s3 * p.templates[0].sphere_volume;
        p.bodies.push_back(b);
      }
  packing::place_bodies(p);
  return p;
}

}  // namespace shapepress::testing
