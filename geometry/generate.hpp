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
#include <optional>
#include <vector>

#include "geometry/descriptors.hpp"
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

// The second stretch of stretch_to_box_ratios, along the minimum box's axes (its costly part: a
// box search), when the first one, exactly along x, y, z, leaves the ratios off.
struct BoxCorrection {
  bool applied = false;
  Mat3 axes = Mat3::Identity();
  Vec3 factors = Vec3::Ones();
};

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

std::vector<GeneratedParticle> generate_population(const ShapeTargets& targets,
                                                   const GenerateOptions& options);

// The per-particle results of generate_population's costly phases and of describe_population,
// each list a prefix of the particles: what a checkpoint keeps (geometry/generate_checkpoint.hpp)
// so that a resumed run does only the rest and ends with the same bits. Everything else
// (sizes, ratio targets, the population fit, scaling) is recomputed from these exactly.
struct BaseDraw {  // phase 1: the accepted draw, redrawn until the mesh checks passed
  std::uint64_t seed = 0;
  int redraws = 0;
};
// views[c]: the sorted ASR bins of a particle's silhouettes in its calibration directions for
// shape choice c of the projected-ASR fit.
using ChoiceViews = std::vector<std::vector<std::uint16_t>>;
struct GenerateWork {
  std::vector<BaseDraw> draws;
  std::vector<std::vector<ChoiceViews>> views;  // per pass of the projected-ASR fit (one or two)
  std::vector<BoxCorrection> corrections;       // box targets
  std::vector<ShapeDescriptors> descriptors;    // describe_population
  // Particles done, summed over the phases: the run's step count.
  std::int64_t steps() const;
};

struct GenerateHooks {
  // After each block of particles, with the work so far; false stops the run (a signal).
  std::function<bool(const GenerateWork&)> after_block;
  // Blocks end at multiples of this many steps (a checkpoint interval); 0: anywhere.
  std::int64_t block_steps = 0;
};

// generate_population resumable: skips what `work` holds, adds to it as it goes, and returns
// nothing when a hook stopped it. The particles are those of the plain call, bit for bit, for
// any thread count and wherever the run was stopped and resumed. InputError when `work` does
// not fit the options (a checkpoint of another run).
std::optional<std::vector<GeneratedParticle>> generate_population(const ShapeTargets& targets,
                                                                  const GenerateOptions& options,
                                                                  GenerateWork& work,
                                                                  const GenerateHooks& hooks);

// describe() of every particle, particle i with `directions` views seeded seed + 1000 + i
// (generate's shapes.csv), resumable as generate_population: nothing when a hook stopped it.
std::optional<std::vector<ShapeDescriptors>> describe_population(
    const std::vector<GeneratedParticle>& particles, int directions, std::uint64_t seed,
    GenerateWork& work, const GenerateHooks& hooks);

// Kolmogorov–Smirnov distance between a sample and the target projected-ASR distribution.
double ks_distance(std::vector<double> sample, const ShapeTargets& targets);

}  // namespace shapepress::geometry
