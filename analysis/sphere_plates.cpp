#include "analysis/sphere_plates.hpp"

#include <cmath>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "analysis/optimize.hpp"
#include "common/error.hpp"

namespace shapepress::analysis {

double ElasticSphere::effective_modulus() const {
  return youngs_modulus / (1.0 - poisson_ratio * poisson_ratio);
}

void ElasticSphere::check() const {
  if (!(radius > 0.0)) throw InputError(fmt::format("sphere radius {} m: must be > 0", radius));
  if (!(youngs_modulus > 0.0))
    throw InputError(fmt::format("sphere Young's modulus {} Pa: must be > 0", youngs_modulus));
  if (!(poisson_ratio >= 0.0 && poisson_ratio < 0.5))
    throw InputError(fmt::format("sphere Poisson ratio {}: expected 0 <= nu < 0.5", poisson_ratio));
}

double hertz_plate_force(const ElasticSphere& sphere, double total_approach) {
  if (total_approach <= 0.0) return 0.0;
  return std::sqrt(2.0) / 3.0 * sphere.effective_modulus() * std::sqrt(sphere.radius) *
         std::pow(total_approach, 1.5);
}

double tatara_contact_approach(const ElasticSphere& sphere, double force) {
  if (force <= 0.0) return 0.0;
  const double e_star = sphere.effective_modulus(), r = sphere.radius, nu = sphere.poisson_ratio;
  const double a = std::cbrt(3.0 * force * r / (4.0 * e_star));  // Hertz contact radius
  const double hertz = std::pow(3.0 * force / (4.0 * e_star * std::sqrt(r)), 2.0 / 3.0);
  const double s = a * a + 4.0 * r * r;
  // Boussinesq: the point load's displacement felt at the far pole, 2R away (Tatara 1989).
  const double boussinesq = force * (1.0 + nu) / (std::numbers::pi * sphere.youngs_modulus) *
                            ((1.0 - nu) / std::sqrt(s) + 2.0 * r * r / (s * std::sqrt(s)));
  return hertz - boussinesq;
}

double tatara_plate_approach(const ElasticSphere& sphere, double force) {
  return 2.0 * tatara_contact_approach(sphere, force);
}

double tatara_plate_force(const ElasticSphere& sphere, double total_approach) {
  if (total_approach <= 0.0) return 0.0;
  auto residual = [&](double f) { return tatara_plate_approach(sphere, f) - total_approach; };
  // Tatara is stiffer than Hertz (the Boussinesq term is subtracted from the approach), so the
  // Hertz force undershoots the root; double it until the approach overshoots.
  double low = 0.5 * hertz_plate_force(sphere, total_approach), high = 2.0 * low;
  for (int i = 0; residual(high) < 0.0; ++i) {
    if (i > 200)
      throw ComputationError(
          fmt::format("Tatara: no force found for a plate approach of {} m", total_approach));
    low = high;
    high *= 2.0;
  }
  return find_root_brent(residual, low, high, 1e-13 * high);
}

double hertz_elliptic_contact_force(double effective_modulus, double r1, double r2,
                                    double approach) {
  if (r1 < r2) std::swap(r1, r2);
  if (!(r2 > 0.0) || approach <= 0.0) return 0.0;
  const double ratio = r1 / r2;
  if (!std::isfinite(r1) || ratio < 1.0 + 1e-6) {
    const double r = std::isfinite(r1) ? std::sqrt(r1 * r2) : r2;
    return 4.0 / 3.0 * effective_modulus * std::sqrt(r) * std::pow(approach, 1.5);
  }
  // R1/R2 as a function of e rises monotonically from 1 at e = 0: bisection.
  const auto radius_ratio = [](double e) {
    const double k = std::comp_ellint_1(e), ee = std::comp_ellint_2(e);
    return (ee / (1.0 - e * e) - k) / (k - ee);
  };
  double low = 0.0, high = 1.0;
  for (int i = 0; i < 200 && high - low > 1e-15; ++i) {
    const double mid = 0.5 * (low + high);
    (radius_ratio(mid) < ratio ? low : high) = mid;
  }
  const double e = 0.5 * (low + high);
  const double k = std::comp_ellint_1(e), ee = std::comp_ellint_2(e);
  const double a = std::sqrt(approach * (k - ee) / (k * e * e) * 2.0 * r1);
  const double b = a * std::sqrt(1.0 - e * e);
  const double p0 = approach * effective_modulus / (b * k);
  return 2.0 / 3.0 * std::numbers::pi * a * b * p0;
}

std::vector<double> hertz_plate_forces(const ElasticSphere& sphere,
                                       const std::vector<double>& approaches) {
  std::vector<double> forces;
  forces.reserve(approaches.size());
  for (double delta : approaches)
    forces.push_back(hertz_plate_force(sphere, delta));
  return forces;
}

std::vector<double> tatara_plate_forces(const ElasticSphere& sphere,
                                        const std::vector<double>& approaches) {
  std::vector<double> forces;
  forces.reserve(approaches.size());
  for (double delta : approaches)
    forces.push_back(tatara_plate_force(sphere, delta));
  return forces;
}

}  // namespace shapepress::analysis
