#include "imaging/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <numeric>

#include "common/error.hpp"
#include "common/provenance.hpp"

namespace shapepress::imaging {

double weighted_quantile(std::vector<double> values, std::vector<double> weights, double p) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return values[a] < values[b]; });
  double total = std::accumulate(weights.begin(), weights.end(), 0.0);
  double below = 0.0, previous_level = 0.0, previous_value = values[order.front()];
  for (std::size_t k = 0; k < order.size(); ++k) {
    double w = weights[order[k]], v = values[order[k]];
    double level = (below + 0.5 * w) / total;  // the class mid-point of this particle
    if (p <= level) {
      if (k == 0) return v;
      double t = (p - previous_level) / (level - previous_level);
      return previous_value + t * (v - previous_value);
    }
    below += w;
    previous_level = level;
    previous_value = v;
  }
  return values[order.back()];
}

namespace {

Percentiles percentiles(const std::vector<double>& x, const std::vector<double>& w) {
  Percentiles p;
  p.x10 = weighted_quantile(x, w, 0.10);
  p.x50 = weighted_quantile(x, w, 0.50);
  p.x90 = weighted_quantile(x, w, 0.90);
  p.span = p.x50 > 0 ? (p.x90 - p.x10) / p.x50 : 0.0;
  double total = std::accumulate(w.begin(), w.end(), 0.0);
  p.mean = std::inner_product(x.begin(), x.end(), w.begin(), 0.0) / total;
  return p;
}

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  double ma = std::accumulate(a.begin(), a.end(), 0.0) / n;
  double mb = std::accumulate(b.begin(), b.end(), 0.0) / n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

std::vector<double> ranks(const std::vector<double>& v) {  // average ranks for ties
  std::vector<std::size_t> order(v.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && v[order[j + 1]] == v[order[i]])
      ++j;
    for (std::size_t k = i; k <= j; ++k)
      r[order[k]] = 0.5 * (i + j);
    i = j + 1;
  }
  return r;
}

// Least-squares slope and intercept of log D_n against log n over [first, last].
std::pair<double, double> fit_power_law(const FourierSpectrum& d, int first, int last) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (int k = first; k <= last; ++k) {
    if (d[k] <= 0) continue;
    double x = std::log(k), y = std::log(d[k]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++n;
  }
  if (n < 2) return {0.0, 0.0};
  double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  return {slope, (sy - slope * sx) / n};
}

SizeDistribution size_distribution(const std::vector<double>& d) {
  SizeDistribution size;
  std::vector<double> ones(d.size(), 1.0), volume(d.size());
  for (std::size_t i = 0; i < d.size(); ++i)
    volume[i] = d[i] * d[i] * d[i];
  size.number = percentiles(d, ones);
  size.volume = percentiles(d, volume);
  auto [lo, hi] = std::minmax_element(d.begin(), d.end());
  constexpr int classes = 20;
  double a = std::log(*lo * 0.999), b = std::log(*hi * 1.001);
  double total_volume = std::accumulate(volume.begin(), volume.end(), 0.0);
  for (int k = 0; k <= classes; ++k) {
    double edge = std::exp(a + (b - a) * k / classes);
    double n_below = 0, v_below = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
      if (d[i] > edge) continue;
      n_below += 1;
      v_below += volume[i];
    }
    size.edges_m.push_back(edge);
    size.Q0.push_back(n_below / d.size());
    size.Q3.push_back(v_below / total_volume);
  }
  return size;
}

AspectRatioDistribution aspect_ratio_distribution(const std::vector<double>& asr,
                                                  const std::vector<double>& d) {
  AspectRatioDistribution out;
  const double n = static_cast<double>(asr.size());
  out.mean = std::accumulate(asr.begin(), asr.end(), 0.0) / n;
  double ss = 0;
  for (double a : asr)
    ss += (a - out.mean) * (a - out.mean);
  out.std_dev = asr.size() > 1 ? std::sqrt(ss / (n - 1)) : 0.0;
  std::vector<double> ones(asr.size(), 1.0);
  out.s50 = weighted_quantile(asr, ones, 0.5);
  for (int k = 1; k <= 19; ++k) {
    out.levels.push_back(0.05 * k);
    out.quantiles.push_back(weighted_quantile(asr, ones, 0.05 * k));
  }
  out.pearson_with_size = pearson(asr, d);
  out.spearman_with_size = pearson(ranks(asr), ranks(d));
  constexpr int classes = 20;
  out.counts.assign(classes, 0);
  for (int k = 0; k <= classes; ++k)
    out.edges.push_back(static_cast<double>(k) / classes);
  for (double a : asr)
    ++out.counts[std::clamp(static_cast<int>(a * classes), 0, classes - 1)];
  return out;
}

FourierSummary fourier_summary(const std::vector<ParticleSample>& particles, double min_px) {
  FourierSummary f;
  f.min_diameter_px = min_px;
  FourierSpectrum sum{}, sum_sq{};
  std::vector<double> r0;
  for (const ParticleSample& p : particles) {
    if (p.equivalent_diameter_px < min_px) continue;
    ++f.particles_used;
    r0.push_back(p.fourier_mean_radius_px);
    for (int n = 0; n <= fourier_max_order; ++n) {
      sum[n] += p.fourier[n];
      sum_sq[n] += p.fourier[n] * p.fourier[n];
    }
  }
  if (f.particles_used == 0) return f;
  for (int n = 0; n <= fourier_max_order; ++n) {
    f.mean_spectrum[n] = sum[n] / f.particles_used;
    f.std_spectrum[n] = std::sqrt(
        std::max(0.0, sum_sq[n] / f.particles_used - f.mean_spectrum[n] * f.mean_spectrum[n]));
  }
  f.D2 = f.mean_spectrum[2];
  auto [alpha, a] = fit_power_law(f.mean_spectrum, 3, 8);
  f.irregularity_slope = -alpha;
  f.D3 = std::exp(a + alpha * std::log(3.0));
  f.D8 = std::exp(a + alpha * std::log(8.0));
  // Harmonic n has a wavelength of 2π r0 / n pixels: fit only those of at least 4 px.
  std::nth_element(r0.begin(), r0.begin() + r0.size() / 2, r0.end());
  double median_r0 = r0[r0.size() / 2];
  f.last_order = std::clamp(static_cast<int>(std::floor(std::numbers::pi * median_r0 / 2.0)), 10,
                            fourier_max_order);
  f.decay_exponent = -fit_power_law(f.mean_spectrum, 8, f.last_order).first;
  return f;
}

}  // namespace

ShapeSummary summarize(const std::vector<ParticleSample>& particles,
                       double min_fourier_diameter_px) {
  if (particles.empty()) throw InputError("no particle found in any image: nothing to summarize");
  ShapeSummary s;
  s.particle_count = static_cast<int>(particles.size());
  std::vector<double> d, asr;
  for (const ParticleSample& p : particles) {
    d.push_back(p.equivalent_diameter_m);
    asr.push_back(p.aspect_ratio);
    s.mean_circularity += p.circularity / s.particle_count;
    s.mean_solidity += p.solidity / s.particle_count;
    s.mean_convexity += p.convexity / s.particle_count;
  }
  s.size = size_distribution(d);
  s.asr = aspect_ratio_distribution(asr, d);
  s.fourier = fourier_summary(particles, min_fourier_diameter_px);
  return s;
}

std::string summary_to_json(const ShapeSummary& s, const std::vector<ImageReport>& images,
                            const std::vector<std::string>& skipped,
                            const std::string& command_line) {
  using nlohmann::json;
  auto percentiles_json = [](const Percentiles& p) {
    return json{
        {"x10_m", p.x10}, {"x50_m", p.x50}, {"x90_m", p.x90}, {"span", p.span}, {"mean_m", p.mean}};
  };
  json j;
  j["format"] = "shapepress shape-stats summary 1";
  j["provenance"] = {{"shapepress_version", shapepress_version()},
                     {"git_revision", shapepress_git_revision()},
                     {"command_line", command_line}};
  j["particle_count"] = s.particle_count;
  // size.x10_m/x50_m/x90_m are volume-weighted (Q3), as laser diffraction and QICPIC report.
  j["size"] = {
      {"diameter", "equivalent circle diameter"},
      {"basis", "volume (Q3)"},
      {"x10_m", s.size.volume.x10},
      {"x50_m", s.size.volume.x50},
      {"x90_m", s.size.volume.x90},
      {"span", s.size.volume.span},
      {"number", percentiles_json(s.size.number)},
      {"volume", percentiles_json(s.size.volume)},
      {"distribution", {{"edges_m", s.size.edges_m}, {"Q0", s.size.Q0}, {"Q3", s.size.Q3}}}};
  j["asr"] = {{"definition", "Feret min / Feret max"},
              {"mean", s.asr.mean},
              {"std", s.asr.std_dev},
              {"S50", s.asr.s50},
              {"quantile_levels", s.asr.levels},
              {"quantiles", s.asr.quantiles},
              {"correlation_with_size",
               {{"pearson", s.asr.pearson_with_size}, {"spearman", s.asr.spearman_with_size}}},
              {"histogram", {{"edges", s.asr.edges}, {"counts", s.asr.counts}}}};
  const FourierSummary& f = s.fourier;
  j["fourier"] = {
      {"normalisation", "Mollon & Zhao 2012: r(theta) = r0 (1 + sum Dn cos(n theta + phi_n))"},
      {"particles_used", f.particles_used},
      {"min_diameter_px", f.min_diameter_px},
      {"D2", f.D2},
      {"D3", f.D3},
      {"D8", f.D8},
      {"irregularity_slope", f.irregularity_slope},
      {"decay_exponent", f.decay_exponent},
      {"decay_fit_orders", {8, f.last_order}},
      {"mean_spectrum", f.mean_spectrum},
      {"std_spectrum", f.std_spectrum}};
  j["shape"] = {{"mean_circularity", s.mean_circularity},
                {"mean_solidity", s.mean_solidity},
                {"mean_convexity", s.mean_convexity}};
  json list = json::array();
  for (const ImageReport& r : images)
    list.push_back({{"file", r.file},
                    {"width_px", r.width},
                    {"height_px", r.height},
                    {"info_bar_rows", r.info_bar_rows},
                    {"pixel_size_m", r.pixel_size_m},
                    {"pixel_size_source", r.pixel_size_source},
                    {"polarity", r.bright_particles ? "bright" : "dark"},
                    {"threshold", r.threshold},
                    {"particles", r.particles},
                    {"excluded_on_edge", r.excluded_on_edge},
                    {"excluded_by_size", r.excluded_by_size},
                    {"background", r.background},
                    {"background_pixel_fraction", r.background_fraction}});
  j["images"] = list;
  j["skipped"] = skipped;
  return j.dump(2) + "\n";
}

}  // namespace shapepress::imaging
