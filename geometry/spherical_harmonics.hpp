#pragma once
// Real, orthonormal spherical harmonics Y_lm (∫ Y_lm Y_l'm' dΩ = δ), evaluated for all l ≤ L.
#include <vector>

#include "geometry/mesh.hpp"

namespace shapepress::geometry {

// Values at the unit direction u, ordered (l, m) with m = -l…l, index l² + l + m. m < 0 are the
// sin(|m|φ) terms, m > 0 the cos(mφ) terms.
std::vector<double> real_spherical_harmonics(const Vec3& u, int max_degree);

}  // namespace shapepress::geometry
