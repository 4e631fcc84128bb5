#include "analysis/plate_analysis.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "common/error.hpp"

namespace shapepress::analysis {
namespace {

struct Inferred {
  double radius = 0.0, effective_modulus = 0.0;
};

// Taken from the deepest row, where the numbers carry the most digits.
Inferred infer(const PlateCurve& curve) {
  const std::size_t deepest = static_cast<std::size_t>(
      std::max_element(curve.approach.begin(), curve.approach.end()) - curve.approach.begin());
  const double delta = curve.approach[deepest], deformation = curve.deformation[deepest];
  if (!(delta > 0.0 && deformation > 0.0))
    throw InputError("plate run: the plates never approach (approach_m and deformation <= 0)");
  Inferred s;
  s.radius = delta / (2.0 * deformation);
  s.effective_modulus = curve.hertz_force[deepest] /
                        (std::sqrt(2.0) / 3.0 * std::sqrt(s.radius) * delta * std::sqrt(delta));
  return s;
}

}  // namespace

ElasticSphere infer_sphere(const PlateCurve& curve, double poisson_ratio) {
  const Inferred s = infer(curve);
  return {s.radius, s.effective_modulus * (1.0 - poisson_ratio * poisson_ratio), poisson_ratio};
}

PlateMetrics analyse_plate(const PlateCurve& curve, std::optional<double> poisson_ratio,
                           double from_fraction) {
  const Inferred inferred = infer(curve);
  PlateMetrics m;
  m.radius = inferred.radius;
  m.effective_modulus = inferred.effective_modulus;
  m.max_deformation = *std::max_element(curve.deformation.begin(), curve.deformation.end());
  m.max_force = *std::max_element(curve.top_force.begin(), curve.top_force.end());
  const Curve simulated = monotone_prefix({curve.deformation, curve.top_force, "simulated"});
  const Curve hertz = monotone_prefix({curve.deformation, curve.hertz_force, "Hertz"});
  simulated.check();
  // A run records its first row after the first step: the comparison starts there at the least.
  m.compared_from = std::max(from_fraction * m.max_deformation, simulated.x.front());
  const double upper = simulated.x.back();
  m.versus_hertz = compare_curves(simulated, hertz, m.compared_from, upper);
  if (poisson_ratio) {
    const ElasticSphere sphere = infer_sphere(curve, *poisson_ratio);
    sphere.check();
    m.poisson_ratio = poisson_ratio;
    std::vector<double> approaches;
    for (double d : simulated.x)
      approaches.push_back(2.0 * sphere.radius * d);
    const Curve tatara{simulated.x, tatara_plate_forces(sphere, approaches), "Tatara"};
    m.versus_tatara = compare_curves(simulated, tatara, m.compared_from, upper);
  }
  return m;
}

}  // namespace shapepress::analysis
