#include "geometry/signed_distance.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace shapepress::geometry {
namespace {

double sum_of_squares(const Vec3& e, const Vec3& y, double t) {
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double r = e[i] * y[i] / (t + e[i] * e[i]);
    sum += r * r;
  }
  return sum;
}

// Distance from y (first octant, semi-axes e) to the ellipsoid surface. The closest point is
// x_i = e_i² y_i / (t + e_i²) where t is the root of F(t) = Σ (e_i y_i / (t + e_i²))² - 1 on
// (-e_min², ∞), F decreasing. When y has no component along the smallest axis k and F stays
// negative there, the closest point leaves the plane y_k = 0 (Eberly 2013, degenerate case).
double ellipsoid_surface_distance(const Vec3& e, const Vec3& y) {
  int k = 0;
  const double e_min = e.minCoeff(&k);
  double lo = -e_min * e_min;
  if (y[k] == 0.0) {
    Vec3 x = Vec3::Zero();
    double in_plane = 0.0;
    bool valid = true;
    for (int i = 0; i < 3; ++i) {
      if (i == k) continue;
      const double denominator = e[i] * e[i] - e_min * e_min;
      if (denominator <= 0.0) {
        valid = false;
        break;
      }
      x[i] = e[i] * e[i] * y[i] / denominator;
      in_plane += (x[i] / e[i]) * (x[i] / e[i]);
    }
    if (valid && in_plane < 1.0) {
      x[k] = e_min * std::sqrt(1.0 - in_plane);
      return (x - y).norm();
    }
  }
  double hi = y.norm() * e.maxCoeff() + 1e-300;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (sum_of_squares(e, y, mid) > 1.0 ? lo : hi) = mid;
  }
  const double t = 0.5 * (lo + hi);
  Vec3 x;
  for (int i = 0; i < 3; ++i)
    x[i] = e[i] * e[i] * y[i] / (t + e[i] * e[i]);
  return (x - y).norm();
}

}  // namespace

Vec3 SignedDistance::gradient(const Vec3& p, double h) const {
  Vec3 g;
  for (int i = 0; i < 3; ++i) {
    Vec3 a = p, b = p;
    a[i] += h;
    b[i] -= h;
    g[i] = (distance(a) - distance(b)) / (2.0 * h);
  }
  return g;
}

SignedDistance sphere_distance(double radius, const Vec3& centre) {
  SignedDistance shape;
  shape.distance = [radius, centre](const Vec3& p) { return (p - centre).norm() - radius; };
  shape.bounds = {centre - Vec3::Constant(radius), centre + Vec3::Constant(radius)};
  shape.description = fmt::format("sphere radius {:.6g} m", radius);
  return shape;
}

SignedDistance ellipsoid_distance(const Vec3& semi_axes, const Vec3& centre) {
  SignedDistance shape;
  shape.distance = [e = semi_axes, centre](const Vec3& p) {
    const Vec3 y = (p - centre).cwiseAbs();
    const double d = ellipsoid_surface_distance(e, y);
    return y.cwiseQuotient(e).squaredNorm() < 1.0 ? -d : d;
  };
  shape.bounds = {centre - semi_axes, centre + semi_axes};
  shape.description = fmt::format("ellipsoid semi-axes {:.6g} {:.6g} {:.6g} m", semi_axes.x(),
                                  semi_axes.y(), semi_axes.z());
  return shape;
}

std::vector<Vec3> surface_samples(const SignedDistance& shape, int cells) {
  const Vec3 size = shape.bounds.size();
  const double h = size.maxCoeff() / cells;
  const Vec3 lower = shape.bounds.lower - Vec3::Constant(h);
  const Eigen::Vector3i n = ((size / h).array().ceil().cast<int>() + 3).matrix();
  std::vector<Vec3> samples;
  for (int i = 0; i < n.x(); ++i)
    for (int j = 0; j < n.y(); ++j)
      for (int k = 0; k < n.z(); ++k) {
        Vec3 p = lower + h * Vec3(i + 0.5, j + 0.5, k + 0.5);
        double d = shape(p);
        if (std::abs(d) > 0.5 * h) continue;
        for (int step = 0; step < 2; ++step) {
          const Vec3 g = shape.gradient(p, 0.25 * h);
          const double g2 = g.squaredNorm();
          if (g2 == 0.0) break;
          p -= d * g / g2;
          d = shape(p);
        }
        samples.push_back(p);
      }
  return samples;
}

}  // namespace shapepress::geometry
