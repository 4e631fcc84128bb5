#include "geometry/generate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include <fmt/format.h>
#include <omp.h>

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

// Runs task(i) for the particles from results.size() to n in parallel blocks, `results` (a list
// of `work`) growing to each block's end, and hands the work to the hook after each block (a
// checkpoint, or a stop on a signal: then false). A few particles a thread per block keep the
// threads busy and a signal answered within seconds; a particle's result depends on it alone, so
// neither the blocks nor the thread count change a bit. No hook: one block.
template <class Result, class Task>
bool in_blocks(std::vector<Result>& results, std::size_t n, const GenerateWork& work,
               const GenerateHooks& hooks, const Task& task) {
  const std::size_t block =
      hooks.after_block ? static_cast<std::size_t>(4 * omp_get_max_threads()) : n;
  while (results.size() < n) {
    const std::size_t from = results.size();
    std::size_t to = std::min(n, from + block);
    if (hooks.block_steps > 0)
      to = std::min(to, from + static_cast<std::size_t>(hooks.block_steps -
                                                        work.steps() % hooks.block_steps));
    results.resize(to);
#pragma omp parallel for schedule(dynamic, 1)
    for (std::size_t i = from; i < to; ++i)
      results[i] = task(i);
    if (hooks.after_block && !hooks.after_block(work)) return false;
  }
  return true;
}

// The exact first stretch of stretch_to_box_ratios, along x, y, z (a stretch scales the extents
// along its own axes exactly).
void stretch_along_xyz(TriangleMesh& mesh, double elongation, double flatness) {
  const Vec3 e = bounding_box(mesh.vertices).size();
  stretch_along(mesh, Mat3::Identity(),
                Vec3(1.0, elongation * e.x() / e.y(), elongation * flatness * e.x() / e.z()));
}

// Then along the minimum box's axes, which for a nearly round base shape are close to x, y, z:
// one box search, and one correction when it disagrees, instead of a loop of them.
BoxCorrection box_correction(const TriangleMesh& mesh, double elongation, double flatness,
                             double tolerance, std::uint64_t seed) {
  const OrientedBox box = minimum_oriented_box(mesh.vertices, seed);
  const Vec3 s = box.lengths;
  if (std::abs(s[1] / s[0] - elongation) < tolerance &&
      std::abs(s[2] / s[1] - flatness) < tolerance)
    return {};
  return {true, box.axes, Vec3(1.0, elongation * s[0] / s[1], elongation * flatness * s[0] / s[2])};
}

void apply(TriangleMesh& mesh, const BoxCorrection& correction) {
  if (correction.applied) stretch_along(mesh, correction.axes, correction.factors);
}

// The shape a particle takes in the projected-ASR fit: its 3D S/L `ratio`, split as I/L =
// ratio^share and S/I = ratio^(1 - share), and the amplitude of its roughness relative to the
// spectrum's D_l.
struct ShapeChoice {
  double ratio = 1.0, share = 0.5, roughness = 1.0;
};

// The shapes the fit chooses from: S/L from 0.05 to 1 in steps of 0.025 for each split at the
// population's roughness, then at S/L = 1 that roughness stepped down to a smooth sphere. A rough
// sphere's silhouettes stay near Feret ratio 0.95 (its D3 alone costs a few per cent of width),
// so the round particles that images show near ASR 1 (the discs of a mixture) exist only as
// smooth ones.
std::vector<ShapeChoice> shape_choices(double roughness, const std::vector<double>& shares) {
  std::vector<ShapeChoice> choices;
  for (double share : shares)
    for (int k = 0; k <= 38; ++k)
      choices.push_back({0.05 + 0.025 * k, share, roughness});
  for (int j = 1; j <= 8; ++j)
    choices.push_back({1.0, shares.front(), roughness * (1.0 - j / 8.0)});
  return choices;
}

// The unit-roughness draw with its radial field r(u) - 1 scaled: its vertices lie on the
// icosphere's rays, so |v| is r(u) (floored as in rough_sphere).
std::vector<Vec3> with_roughness(const std::vector<Vec3>& vertices, double roughness) {
  std::vector<Vec3> scaled(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const double r = vertices[i].norm();
    scaled[i] = vertices[i] / r * std::max(1.0 + roughness * (r - 1.0), 0.05);
  }
  return scaled;
}

// Projected ASRs are binned on [0, 1] for the fit's cumulative distributions.
constexpr int asr_bins = 400;

std::uint16_t asr_bin(double asr) {
  return static_cast<std::uint16_t>(std::clamp(static_cast<int>(asr * asr_bins), 0, asr_bins - 1));
}

ChoiceViews choice_views(const std::vector<Vec3>& vertices, const std::vector<ShapeChoice>& choices,
                         const std::vector<Vec3>& directions) {
  ChoiceViews views(choices.size());
  double hull_roughness = -1.0;
  std::vector<Vec3> hull;
  for (std::size_t c = 0; c < choices.size(); ++c) {
    // A stretch maps the hull to the stretched body's hull: one hull per roughness.
    if (choices[c].roughness != hull_roughness) {
      hull_roughness = choices[c].roughness;
      const std::vector<Vec3> rough = with_roughness(vertices, hull_roughness);
      hull.clear();
      for (std::size_t id : convex_hull_vertices(rough))
        hull.push_back(rough[id]);
    }
    const double a = choices[c].ratio, e = std::pow(a, choices[c].share);
    std::vector<Vec3> stretched = hull;
    for (Vec3& p : stretched)
      p = Vec3(p.x(), e * p.y(), a * p.z());
    for (const Vec3& d : directions)
      views[c].push_back(asr_bin(projected_feret(stretched, d).ratio()));
    std::sort(views[c].begin(), views[c].end());
  }
  return views;
}

// Squared distance between the pooled silhouettes' cumulative distribution and the target's,
// summed over the bins: `others` the cumulative counts of every other particle, `mine` this
// particle's sorted bins.
double cdf_misfit(const std::vector<double>& others, const std::vector<std::uint16_t>& mine,
                  const std::vector<double>& target_cdf, double total) {
  double misfit = 0.0;
  std::size_t k = 0;
  for (int b = 0; b < asr_bins; ++b) {
    while (k < mine.size() && mine[k] <= b)
      ++k;
    const double gap = (others[static_cast<std::size_t>(b)] + static_cast<double>(k)) / total -
                       target_cdf[static_cast<std::size_t>(b)];
    misfit += gap * gap;
  }
  return misfit;
}

// Chooses each particle's shape so that the silhouettes of the whole population, pooled over
// random directions, follow the image's projected-ASR distribution: coordinate descent on the
// Cramér–von Mises misfit of the pooled cumulative distribution, one particle at a time, from a
// start where particle i stands for level p_i of the distribution. The pooled silhouettes of a
// particle spread over a range of ratios, so matching per-particle levels one by one cannot
// work; matching the pooled distribution deconvolves the orientation spread as a whole.
std::vector<std::size_t> fit_choices(const std::vector<ChoiceViews>& views,
                                     const std::vector<double>& start_asr,
                                     const ShapeTargets& targets, int sweeps) {
  const std::size_t n = views.size(), m = views.front().front().size();
  const std::size_t choices = views.front().size();
  std::vector<double> target_cdf(asr_bins);
  for (int b = 0; b < asr_bins; ++b)
    target_cdf[static_cast<std::size_t>(b)] = targets.asr_cdf((b + 1.0) / asr_bins);
  std::vector<std::size_t> chosen(n);
  for (std::size_t i = 0; i < n; ++i) {
    double best = 2.0;
    for (std::size_t c = 0; c < choices; ++c) {
      const double median = (views[i][c][m / 2] + 0.5) / asr_bins;
      if (std::abs(median - start_asr[i]) < best) {
        best = std::abs(median - start_asr[i]);
        chosen[i] = c;
      }
    }
  }
  std::vector<double> histogram(asr_bins, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint16_t b : views[i][chosen[i]])
      histogram[b] += 1.0;
  const double total = static_cast<double>(n * m);
  std::vector<double> others(asr_bins);
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    bool changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::uint16_t b : views[i][chosen[i]])
        histogram[b] -= 1.0;
      double running = 0.0;
      for (int b = 0; b < asr_bins; ++b)
        others[static_cast<std::size_t>(b)] = running += histogram[static_cast<std::size_t>(b)];
      double best = cdf_misfit(others, views[i][chosen[i]], target_cdf, total);
      for (std::size_t c = 0; c < choices; ++c) {
        const double misfit = cdf_misfit(others, views[i][c], target_cdf, total);
        if (misfit < best) {
          best = misfit;
          chosen[i] = c;
          changed = true;
        }
      }
      for (std::uint16_t b : views[i][chosen[i]])
        histogram[b] += 1.0;
    }
    if (!changed) break;
  }
  return chosen;
}

// The projected-distribution branch of generate_population: each particle's 3D S/L, its split
// between elongation and flatness, and its roughness. Images cannot tell how a particle's
// shortening splits between I/L and S/I; explicit targets fix it, else the fit picks per particle
// between the even split and the prolate one (I = S). A prolate particle shows nearly the same
// Feret ratio from most directions (only views near its long axis look rounder), an even or
// flat one a broad spread: a narrow peak in the images (a batch of like ellipses) needs the
// former.
bool fit_projected_distribution(std::vector<GeneratedParticle>& particles,
                                const ShapeTargets& targets, const GenerateOptions& options,
                                double e_target, double f_target, GenerateWork& work,
                                const GenerateHooks& hooks) {
  const std::size_t n = particles.size();
  Rng rng(mix(options.seed));
  std::vector<std::size_t> rank(n);
  for (std::size_t i = 0; i < n; ++i)
    rank[i] = i;
  for (std::size_t i = n; i-- > 1;)
    std::swap(rank[i], rank[static_cast<std::size_t>(uniform01(rng) * (i + 1)) % (i + 1)]);
  const bool split_given = targets.elongation.has_value() || targets.flatness.has_value();
  const std::vector<double> shares =
      split_given && e_target * f_target < 1.0
          ? std::vector<double>{std::log(e_target) / std::log(e_target * f_target)}
          : std::vector<double>{0.5, 1.0};
  std::vector<std::vector<Vec3>> directions(n);
  std::vector<double> start_asr(n);
  for (std::size_t i = 0; i < n; ++i) {
    Rng view(mix(particles[i].seed ^ 0x5eedULL));
    for (int k = 0; k < options.calibration_directions; ++k)
      directions[i].push_back(random_direction(view));
    start_asr[i] = targets.asr_quantile((static_cast<double>(rank[i]) + 0.5) / n);
  }
  // The images' spectrum is a mean over their particles, smooth ones included: when the fit
  // makes some particles smoother, the others carry more roughness so that the population's
  // mean amplitude stays the measured one (at most twice it, one refit).
  double roughness = 1.0;
  std::vector<ShapeChoice> choices;
  std::vector<std::size_t> chosen;
  std::size_t passes = 0;
  for (int fit = 0; fit < 2; ++fit) {
    choices = shape_choices(roughness, shares);
    if (work.views.size() <= passes) work.views.emplace_back();
    std::vector<ChoiceViews>& views = work.views[passes++];
    for (const ChoiceViews& restored : views) {
      const std::size_t seen = restored.empty() ? 0 : restored.front().size();
      if (restored.size() != choices.size() ||
          seen != static_cast<std::size_t>(options.calibration_directions))
        throw InputError(fmt::format(
            "the checkpoint's silhouettes ({} shapes of {} views) are not this run's ({} of {})",
            restored.size(), seen, choices.size(), options.calibration_directions));
    }
    if (!in_blocks(views, n, work, hooks, [&](std::size_t i) {
          return choice_views(particles[i].mesh.vertices, choices, directions[i]);
        }))
      return false;
    chosen = fit_choices(views, start_asr, targets, options.calibration_iterations);
    double mean = 0.0;
    for (std::size_t c : chosen)
      mean += choices[c].roughness / static_cast<double>(n);
    if (mean >= 0.99 || roughness >= 2.0) break;
    roughness = std::min(2.0, roughness / std::max(mean, 0.5));
  }
  if (work.views.size() > passes)
    throw InputError(fmt::format("the checkpoint holds {} passes of the fit, this run makes {}",
                                 work.views.size(), passes));
#pragma omp parallel for schedule(dynamic, 1)
  for (std::size_t i = 0; i < n; ++i) {
    GeneratedParticle& p = particles[i];
    ShapeChoice shape = choices[chosen[i]];
    TriangleMesh rough{with_roughness(p.mesh.vertices, shape.roughness), p.mesh.triangles};
    // The unit draw passed the mesh checks; an amplified one may fold: it keeps unit roughness.
    if (shape.roughness > 1.0 && !check_mesh(rough).valid()) {
      shape.roughness = 1.0;
      rough.vertices = with_roughness(p.mesh.vertices, 1.0);
    }
    p.mesh = std::move(rough);
    p.roughness = shape.roughness;
    p.elongation_target = std::pow(shape.ratio, shape.share);
    p.flatness_target = std::pow(shape.ratio, 1.0 - shape.share);
    stretch_along(p.mesh, Mat3::Identity(), Vec3(1.0, p.elongation_target, shape.ratio));
  }
  return true;
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
  stretch_along_xyz(mesh, elongation, flatness);
  apply(mesh, box_correction(mesh, elongation, flatness, tolerance, seed));
}

std::int64_t GenerateWork::steps() const {
  std::size_t done = draws.size() + corrections.size() + descriptors.size();
  for (const std::vector<ChoiceViews>& pass : views)
    done += pass.size();
  return static_cast<std::int64_t>(done);
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
                                                   const GenerateOptions& options) {
  GenerateWork work;
  return *generate_population(targets, options, work, {});
}

std::optional<std::vector<GeneratedParticle>> generate_population(const ShapeTargets& targets,
                                                                  const GenerateOptions& options,
                                                                  GenerateWork& work,
                                                                  const GenerateHooks& hooks) {
  options.check();
  targets.check();
  const std::size_t n = static_cast<std::size_t>(options.count);
  if (work.draws.size() > n || work.corrections.size() > n || work.descriptors.size() > n ||
      std::any_of(work.views.begin(), work.views.end(),
                  [&](const auto& v) { return v.size() > n; }))
    throw InputError(fmt::format("the checkpoint holds more particles than this run's {}", n));
  const std::vector<double> spectrum = roughness_spectrum(targets, options.max_degree);
  std::vector<GeneratedParticle> particles(n);
  const double e_target = targets.target_elongation(), f_target = targets.target_flatness();

  // 1. Base shapes (unit, unstretched), redrawn until CGAL finds them valid; per-particle size
  //    and 3D ratio targets from the particle's own stream. A draw a checkpoint kept is made
  //    again from its seed, unchecked.
  const auto stream = [&](std::size_t i) { return mix(options.seed ^ mix(i + 1)); };
  for (std::size_t i = 0; i < n; ++i) {
    GeneratedParticle& particle = particles[i];
    Rng rng(stream(i));
    particle.size_m = targets.size_quantile(uniform01(rng));
    // Spread deviates, turned into ratios below once the whole population's are known.
    particle.elongation_target = std::clamp(standard_normal(rng), -2.0, 2.0);
    particle.flatness_target = std::clamp(standard_normal(rng), -2.0, 2.0);
  }
  const std::size_t restored_draws = work.draws.size();
#pragma omp parallel for schedule(dynamic, 1)
  for (std::size_t i = 0; i < restored_draws; ++i)
    particles[i].mesh = rough_sphere(spectrum, work.draws[i].seed, options.subdivisions);
  const bool drawn = in_blocks(work.draws, n, work, hooks, [&](std::size_t i) {
    BaseDraw accepted;
    for (int draw = 0; draw <= options.max_redraws; ++draw) {
      accepted.seed = mix(stream(i) + static_cast<std::uint64_t>(draw));
      particles[i].mesh = rough_sphere(spectrum, accepted.seed, options.subdivisions);
      if (check_mesh(particles[i].mesh).valid()) break;
      accepted.redraws = draw + 1;
    }
    return accepted;
  });
  if (!drawn) return std::nullopt;
  for (std::size_t i = 0; i < n; ++i) {
    particles[i].seed = work.draws[i].seed;
    particles[i].redraws = work.draws[i].redraws;
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

  // 2. Shape: either the image's projected-ASR distribution (population calibration of one
  //    stretch ratio per particle on its convex hull) or 3D box ratios per particle.
  if (targets.projected_distribution()) {
    if (!work.corrections.empty())
      throw InputError("the checkpoint holds box stretches, this run fits projected ratios");
    if (!fit_projected_distribution(particles, targets, options, e_target, f_target, work, hooks))
      return std::nullopt;
  } else {
    if (!work.views.empty())
      throw InputError("the checkpoint holds a projected-ratio fit, this run stretches to boxes");
    const std::size_t restored = work.corrections.size();
#pragma omp parallel for schedule(dynamic, 1)
    for (std::size_t i = 0; i < restored; ++i) {
      GeneratedParticle& p = particles[i];
      stretch_along_xyz(p.mesh, p.elongation_target, p.flatness_target);
      apply(p.mesh, work.corrections[i]);
    }
    const bool stretched = in_blocks(work.corrections, n, work, hooks, [&](std::size_t i) {
      GeneratedParticle& p = particles[i];
      stretch_along_xyz(p.mesh, p.elongation_target, p.flatness_target);
      const BoxCorrection correction =
          box_correction(p.mesh, p.elongation_target, p.flatness_target, 2e-3, 1);
      apply(p.mesh, correction);
      return correction;
    });
    if (!stretched) return std::nullopt;
  }

  // 3. Size (equivalent-circle diameter of the mean silhouette, Cauchy: sqrt(A/π)) and centre.
  for (GeneratedParticle& p : particles) {
    scale_mesh(p.mesh, p.size_m / std::sqrt(surface_area(p.mesh) / std::numbers::pi));
    translate_mesh(p.mesh, -mesh_mass_properties(p.mesh).centre);
  }
  return particles;
}

std::optional<std::vector<ShapeDescriptors>> describe_population(
    const std::vector<GeneratedParticle>& particles, int directions, std::uint64_t seed,
    GenerateWork& work, const GenerateHooks& hooks) {
  if (work.descriptors.size() > particles.size())
    throw InputError(fmt::format("the checkpoint describes {} particles, this run makes {}",
                                 work.descriptors.size(), particles.size()));
  for (const ShapeDescriptors& d : work.descriptors)
    if (d.projected_asr.size() != static_cast<std::size_t>(directions))
      throw InputError(fmt::format("the checkpoint's descriptors have {} views, this run {}",
                                   d.projected_asr.size(), directions));
  const bool described =
      in_blocks(work.descriptors, particles.size(), work, hooks, [&](std::size_t i) {
        return describe(particles[i].mesh, {directions, seed + 1000 + i});
      });
  if (!described) return std::nullopt;
  return work.descriptors;
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
