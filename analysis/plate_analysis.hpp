#pragma once
// Numbers of a plate run (one sphere between two plates): the simulated force against Hertz and
// against Tatara's large-deformation form over the loading branch.
#include <optional>

#include "analysis/curves.hpp"
#include "analysis/runs.hpp"
#include "analysis/sphere_plates.hpp"

namespace shapepress::analysis {

struct PlateMetrics {
  // force.csv does not carry the material: R = Δ/(2·deformation) and E* from the Hertz column,
  // hertz_force = (√2/3) E* √R Δ^{3/2}; ν must be given to compute Tatara (E = E*(1−ν²)).
  double radius = 0.0;             // m
  double effective_modulus = 0.0;  // E* [Pa]
  double max_deformation = 0.0;    // Δ/(2R) at the deepest point
  double max_force = 0.0;          // N
  double compared_from = 0.0;      // deformation range of the comparison: [from, max]
  CurveDifference versus_hertz;
  std::optional<double> poisson_ratio;
  std::optional<CurveDifference> versus_tatara;
};

// The sphere implied by a plate run (E is E*(1−ν²) with the given ν, or E* when ν is unknown).
ElasticSphere infer_sphere(const PlateCurve& curve, double poisson_ratio);

// Compares the loading branch with the theories for deformations in [from_fraction·max, max]
// (or from the first recorded row if later): the first percent of approach is dominated by the
// plate's impact, not by elasticity.
PlateMetrics analyse_plate(const PlateCurve& curve, std::optional<double> poisson_ratio,
                           double from_fraction = 0.05);

}  // namespace shapepress::analysis
