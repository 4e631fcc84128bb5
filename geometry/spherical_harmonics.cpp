#include "geometry/spherical_harmonics.hpp"

#include <cmath>
#include <numbers>

namespace shapepress::geometry {

std::vector<double> real_spherical_harmonics(const Vec3& u, int max_degree) {
  const int L = max_degree;
  const double x = std::clamp(u.z(), -1.0, 1.0);
  const double s = std::sqrt(std::max(0.0, 1.0 - x * x));
  const double phi = std::atan2(u.y(), u.x());
  // Fully normalised associated Legendre functions P̄_l^m(x) (4π-orthonormal with the φ part),
  // by the standard stable recurrences.
  std::vector<double> P(static_cast<std::size_t>((L + 1) * (L + 1)), 0.0);
  auto at = [&](int l, int m) -> double& { return P[static_cast<std::size_t>(l * (L + 1) + m)]; };
  at(0, 0) = 1.0 / std::sqrt(4.0 * std::numbers::pi);
  for (int m = 1; m <= L; ++m)
    at(m, m) = -std::sqrt((2.0 * m + 1.0) / (2.0 * m)) * s * at(m - 1, m - 1);
  for (int m = 0; m < L; ++m)
    at(m + 1, m) = std::sqrt(2.0 * m + 3.0) * x * at(m, m);
  for (int m = 0; m <= L; ++m)
    for (int l = m + 2; l <= L; ++l) {
      const double a = std::sqrt((4.0 * l * l - 1.0) / (static_cast<double>(l) * l - m * m));
      const double b =
          std::sqrt(((l - 1.0) * (l - 1.0) - m * m) / (4.0 * (l - 1.0) * (l - 1.0) - 1.0));
      at(l, m) = a * (x * at(l - 1, m) - b * at(l - 2, m));
    }
  std::vector<double> Y(static_cast<std::size_t>((L + 1) * (L + 1)));
  for (int l = 0; l <= L; ++l) {
    Y[static_cast<std::size_t>(l * l + l)] = at(l, 0);
    for (int m = 1; m <= l; ++m) {
      Y[static_cast<std::size_t>(l * l + l + m)] = std::sqrt(2.0) * at(l, m) * std::cos(m * phi);
      Y[static_cast<std::size_t>(l * l + l - m)] = std::sqrt(2.0) * at(l, m) * std::sin(m * phi);
    }
  }
  return Y;
}

}  // namespace shapepress::geometry
