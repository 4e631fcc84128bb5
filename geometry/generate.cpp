#include "geometry/generate.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "common/error.hpp"
#include "geometry/descriptors.hpp"
#include "geometry/icosphere.hpp"
#include "geometry/mesh_checks.hpp"
#include "geometry/random.hpp"
#include "geometry/spherical_harmonics.hpp"

namespace shapepress::geometry {
namespace {

// SplitMix64: independent seeds for (seed, particle, draw).
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

void stretch_along(TriangleMesh& mesh, const Mat3& axes, const Vec3& factors) {
  const Mat3 map = axes * factors.asDiagonal() * axes.transpose();
  const Vec3 centre = mesh_mass_properties(mesh).centre;
  for (Vec3& p : mesh.vertices)
    p = centre + map * (p - centre);
}

// The pooled projected ASR of every particle's hull, stretched by (1, e, e f) along x, y, z.
std::vector<double> pooled_projected_asr(const std::vector<std::vector<Vec3>>& hulls,
                                         const std::vector<std::vector<Vec3>>& directions,
                                         const std::vector<double>& ratio, double w,
                                         std::vector<double>* per_particle_mean) {
  const std::size_t n = hulls.size(), m = directions.front().size();
  std::vector<double> pooled(n * m);
#pragma omp parallel for schedule(dynamic, 4)
  for (std::size_t i = 0; i < n; ++i) {
    const double e = std::pow(ratio[i], w), s = ratio[i];
    std::vector<Vec3> stretched = hulls[i];
    for (Vec3& p : stretched)
      p = Vec3(p.x(), e * p.y(), s * p.z());
    for (std::size_t k = 0; k < m; ++k)
      pooled[i * m + k] = projected_feret(stretched, directions[i][k]).ratio();
  }
  if (per_particle_mean != nullptr) {
    per_particle_mean->assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = 0; k < m; ++k)
        (*per_particle_mean)[i] += pooled[i * m + k] / m;
  }
  return pooled;
}

double sorted_quantile(const std::vector<double>& sorted, double p) {
  const double x = p * static_cast<double>(sorted.size()) - 0.5;
  const auto i = static_cast<std::size_t>(std::clamp(std::floor(x), 0.0, sorted.size() - 1.0));
  const std::size_t j = std::min(i + 1, sorted.size() - 1);
  const double t = std::clamp(x - static_cast<double>(i), 0.0, 1.0);
  return sorted[i] + t * (sorted[j] - sorted[i]);
}

}  // namespace

std::vector<double> roughness_spectrum(const ShapeTargets& targets, int max_degree) {
  std::vector<double> D(static_cast<std::size_t>(max_degree + 1), 0.0);
  if (targets.D3 <= 0.0 || targets.D8 <= 0.0) return D;
  const double alpha = std::log(targets.D3 / targets.D8) / std::log(8.0 / 3.0);
  for (int l = 3; l <= max_degree; ++l)
    D[static_cast<std::size_t>(l)] = l <= 8
                                         ? targets.D3 * std::pow(l / 3.0, -alpha)
                                         : targets.D8 * std::pow(l / 8.0, -targets.decay_exponent);
  return D;
}

TriangleMesh rough_sphere(const std::vector<double>& spectrum, std::uint64_t seed,
                          int subdivisions) {
  TriangleMesh mesh = icosphere(subdivisions);
  const int L = static_cast<int>(spectrum.size()) - 1;
  Rng rng(seed);
  std::vector<double> coefficients(static_cast<std::size_t>((L + 1) * (L + 1)), 0.0);
  for (int l = 0; l <= L; ++l) {
    const double sigma = spectrum[static_cast<std::size_t>(l)] / std::sqrt(2.0) *
                         std::sqrt(4.0 * std::numbers::pi / (2.0 * l + 1.0));
    for (int m = -l; m <= l; ++m)
      coefficients[static_cast<std::size_t>(l * l + l + m)] = sigma * standard_normal(rng);
  }
  for (Vec3& v : mesh.vertices) {
    const std::vector<double> Y = real_spherical_harmonics(v, L);
    double r = 1.0;
    for (std::size_t k = 0; k < Y.size(); ++k)
      r += coefficients[k] * Y[k];
    v *= std::max(r, 0.05);
  }
  return mesh;
}

void stretch_to_box_ratios(TriangleMesh& mesh, double elongation, double flatness, double tolerance,
                           std::uint64_t seed) {
  // First exactly along x, y, z (a stretch scales the extents along its own axes exactly), then
  // along the minimum box's axes, which for a nearly round base shape are close to x, y, z:
  // one box search (and one correction when it disagrees) instead of a loop of them.
  const Aabb aligned = bounding_box(mesh.vertices);
  const Vec3 e = aligned.size();
  stretch_along(mesh, Mat3::Identity(),
                Vec3(1.0, elongation * e.x() / e.y(), elongation * flatness * e.x() / e.z()));
  const OrientedBox box = minimum_oriented_box(mesh.vertices, seed);
  const Vec3 s = box.lengths;
  if (std::abs(s[1] / s[0] - elongation) < tolerance &&
      std::abs(s[2] / s[1] - flatness) < tolerance)
    return;
  stretch_along(mesh, box.axes,
                Vec3(1.0, elongation * s[0] / s[1], elongation * flatness * s[0] / s[2]));
}

void GenerateOptions::check() const {
  if (count < 1 || count > 1000000)
    throw InputError(fmt::format("particle count {} must be in [1, 1000000]", count));
  if (subdivisions < 1 || subdivisions > 7)
    throw InputError(fmt::format("subdivisions {} must be in [1, 7]", subdivisions));
  if (max_degree < 3 || max_degree > 40)
    throw InputError(fmt::format("max degree {} must be in [3, 40]", max_degree));
  if (!(ratio_spread >= 0.0 && ratio_spread < 0.5))
    throw InputError(fmt::format("ratio spread {} must be in [0, 0.5)", ratio_spread));
}

std::vector<GeneratedParticle> generate_population(const ShapeTargets& targets,
                                                   const GenerateOptions& options,
                                                   const GenerateProgress& progress) {
  options.check();
  targets.check();
  const std::size_t n = static_cast<std::size_t>(options.count);
  const std::vector<double> spectrum = roughness_spectrum(targets, options.max_degree);
  std::vector<GeneratedParticle> particles(n);
  const double e_target = targets.target_elongation(), f_target = targets.target_flatness();

  // 1. Base shapes (unit, unstretched), redrawn until CGAL finds them valid; per-particle size
  //    and 3D ratio targets from the particle's own stream.
#pragma omp parallel for schedule(dynamic, 1)
  for (std::size_t i = 0; i < n; ++i) {
    GeneratedParticle& particle = particles[i];
    const std::uint64_t stream = mix(options.seed ^ mix(i + 1));
    Rng rng(stream);
    particle.size_m = targets.size_quantile(uniform01(rng));
    // Spread deviates, turned into ratios below once the whole population's are known.
    particle.elongation_target = std::clamp(standard_normal(rng), -2.0, 2.0);
    particle.flatness_target = std::clamp(standard_normal(rng), -2.0, 2.0);
    for (int draw = 0; draw <= options.max_redraws; ++draw) {
      particle.seed = mix(stream + static_cast<std::uint64_t>(draw));
      particle.mesh = rough_sphere(spectrum, particle.seed, options.subdivisions);
      if (check_mesh(particle.mesh).valid()) break;
      particle.redraws = draw + 1;
    }
  }
  for (const GeneratedParticle& p : particles)
    if (p.redraws > options.max_redraws)
      throw ComputationError(fmt::format(
          "no valid particle in {} draws: the roughness (D3 = {}, D8 = {}) folds the surface",
          options.max_redraws + 1, targets.D3, targets.D8));
  // Per-particle 3D ratios: target ± spread, with the deviates centred over the population and
  // the spread capped at (1 - target)/2 so that no ratio is clipped at 1: the population's mean
  // is the target itself, not the target minus a clipping bias.
  {
    double mean_e = 0.0, mean_f = 0.0;
    for (const GeneratedParticle& p : particles) {
      mean_e += p.elongation_target / static_cast<double>(n);
      mean_f += p.flatness_target / static_cast<double>(n);
    }
    const double de = std::min(options.ratio_spread * e_target, 0.5 * (1.0 - e_target));
    const double df = std::min(options.ratio_spread * f_target, 0.5 * (1.0 - f_target));
    for (GeneratedParticle& p : particles) {
      p.elongation_target = std::clamp(e_target + de * (p.elongation_target - mean_e), 0.05, 1.0);
      p.flatness_target = std::clamp(f_target + df * (p.flatness_target - mean_f), 0.05, 1.0);
    }
  }
  if (progress) progress(static_cast<int>(n) / 2);

  // 2. Shape: either the image's projected-ASR distribution (population calibration of one
  //    stretch ratio per particle on its convex hull) or 3D box ratios per particle.
  if (targets.projected_distribution()) {
    // Particle i stands for level p_i of the distribution (a seeded permutation of strata);
    // its S/L ratio a_i is corrected until the pooled silhouettes' quantile at p_i is the
    // image's: a fixed-point deconvolution of the orientation spread.
    Rng rng(mix(options.seed));
    std::vector<std::size_t> rank(n);
    for (std::size_t i = 0; i < n; ++i)
      rank[i] = i;
    for (std::size_t i = n; i-- > 1;)
      std::swap(rank[i], rank[static_cast<std::size_t>(uniform01(rng) * (i + 1)) % (i + 1)]);
    const bool split_given = targets.elongation.has_value() || targets.flatness.has_value();
    const double w = split_given && e_target * f_target < 1.0
                         ? std::log(e_target) / std::log(e_target * f_target)
                         : 0.5;
    std::vector<std::vector<Vec3>> hulls(n), directions(n);
    std::vector<double> level(n), ratio(n);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t id : convex_hull_vertices(particles[i].mesh.vertices))
        hulls[i].push_back(particles[i].mesh.vertices[id]);
      Rng view(mix(particles[i].seed ^ 0x5eedULL));
      for (int k = 0; k < options.calibration_directions; ++k)
        directions[i].push_back(random_direction(view));
      level[i] = (static_cast<double>(rank[i]) + 0.5) / static_cast<double>(n);
      ratio[i] = targets.asr_quantile(level[i]);
    }
    for (int iteration = 0; iteration < options.calibration_iterations; ++iteration) {
      std::vector<double> pooled = pooled_projected_asr(hulls, directions, ratio, w, nullptr);
      std::sort(pooled.begin(), pooled.end());
      for (std::size_t i = 0; i < n; ++i)
        ratio[i] = std::clamp(
            ratio[i] + targets.asr_quantile(level[i]) - sorted_quantile(pooled, level[i]), 0.05,
            1.0);
    }
    for (std::size_t i = 0; i < n; ++i) {
      particles[i].elongation_target = std::pow(ratio[i], w);
      particles[i].flatness_target = std::pow(ratio[i], 1.0 - w);
      stretch_along(particles[i].mesh, Mat3::Identity(),
                    Vec3(1.0, particles[i].elongation_target, ratio[i]));
    }
  } else {
#pragma omp parallel for schedule(dynamic, 1)
    for (std::size_t i = 0; i < n; ++i) {
      GeneratedParticle& p = particles[i];
      stretch_to_box_ratios(p.mesh, p.elongation_target, p.flatness_target);
    }
  }

  // 3. Size (equivalent-circle diameter of the mean silhouette, Cauchy: sqrt(A/π)) and centre.
  for (GeneratedParticle& p : particles) {
    scale_mesh(p.mesh, p.size_m / std::sqrt(surface_area(p.mesh) / std::numbers::pi));
    translate_mesh(p.mesh, -mesh_mass_properties(p.mesh).centre);
  }
  if (progress) progress(static_cast<int>(n));
  return particles;
}

double ks_distance(std::vector<double> sample, const ShapeTargets& targets) {
  std::sort(sample.begin(), sample.end());
  const double n = static_cast<double>(sample.size());
  double d = 0.0;
  for (std::size_t i = 0; i < sample.size(); ++i) {
    const double F = targets.asr_cdf(sample[i]);
    d = std::max({d, F - static_cast<double>(i) / n, static_cast<double>(i + 1) / n - F});
  }
  return d;
}

}  // namespace shapepress::geometry
