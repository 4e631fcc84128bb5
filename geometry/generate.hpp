#pragma once
// Particle generation from shape statistics: a star-shaped random field on the sphere (real
// spherical harmonics with Gaussian coefficients whose degree-l amplitude follows the Fourier
// spectrum D_l of the images, after Mollon & Zhao 2014 and Wei et al. 2018), stretched to the
// target L:I:S, scaled to a size drawn from the size distribution. With the image's projected-ASR
// distribution as the target, each particle's stretch and roughness are chosen so that the whole
// population's silhouettes follow it (docs/stages.md, "generate"). Each particle is reproducible
// from (seed, index) and redrawn until its mesh is closed, manifold and self-intersection free.
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/mesh.hpp"
#include "geometry/shape_targets.hpp"

namespace shapepress::geometry {

// D_l for l = 0…max_degree: D3…D8 log-linear through D3 and D8, beyond 8 D8 (l/8)^-β; l < 3
// zero (elongation comes from the explicit stretch, not from D2).
std::vector<double> roughness_spectrum(const ShapeTargets& targets, int max_degree);

// Unit-radius rough sphere: r(u) = 1 + Σ_l Σ_m a_lm Y_lm(u) on an icosphere, a_lm ~ N(0, σ_l²)
// with σ_l² (2l+1)/(4π) = D_l²/2 (the degree-l part has the variance of a cosine of amplitude
// D_l, the 2D descriptor's meaning).
TriangleMesh rough_sphere(const std::vector<double>& spectrum, std::uint64_t seed,
                          int subdivisions = 4);

// Stretches along the mesh's own minimum oriented box axes until I/L and S/I are within
// `tolerance` of the targets: exactly along x, y, z, then at most one correction along the box
// axes (one or two box searches).
void stretch_to_box_ratios(TriangleMesh& mesh, double elongation, double flatness,
                           double tolerance = 2e-3, std::uint64_t seed = 1);

struct GenerateOptions {
  int count = 150;
  std::uint64_t seed = 1;
  int subdivisions = 4;             // icosphere level: 4 gives 2562 vertices
  int max_degree = 15;              // highest spherical-harmonic degree
  double ratio_spread = 0.05;       // relative spread of the per-particle 3D ratios (box targets)
  int calibration_directions = 24;  // per particle, for the projected-ASR calibration
  int calibration_iterations = 20;  // sweeps of the projected-ASR fit at most
  int max_redraws = 20;
  void check() const;
};

struct GeneratedParticle {
  TriangleMesh mesh;       // metres, centred on its centroid
  std::uint64_t seed = 0;  // the seed of the accepted draw
  int redraws = 0;         // rejected draws before it
  double size_m = 0.0;     // equivalent-circle diameter it was scaled to
  double elongation_target = 0.0, flatness_target = 0.0;  // 3D stretch asked for
  double roughness = 1.0;  // amplitude of its roughness relative to the spectrum's D_l
};

// Progress hook: called with the number of particles done so far.
using GenerateProgress = std::function<void(int done)>;

std::vector<GeneratedParticle> generate_population(const ShapeTargets& targets,
                                                   const GenerateOptions& options,
                                                   const GenerateProgress& progress = {});

// Kolmogorov–Smirnov distance between a sample and the target projected-ASR distribution.
double ks_distance(std::vector<double> sample, const ShapeTargets& targets);

}  // namespace shapepress::geometry
