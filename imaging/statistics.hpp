#pragma once
// Distributions over all particles of a batch: sizes (number- and volume-weighted), aspect
// ratio, and the mean Fourier spectrum with the fitted parameters the particle generator takes.
#include <string>
#include <vector>

#include "imaging/fourier.hpp"

namespace shapepress::imaging {

// What the statistics need from one measured particle, in SI units.
struct ParticleSample {
  double equivalent_diameter_m = 0.0;
  double equivalent_diameter_px = 0.0;  // decides whether its outline resolves the harmonics
  double aspect_ratio = 0.0;
  double circularity = 0.0;
  double solidity = 0.0;
  double convexity = 0.0;
  double fourier_mean_radius_px = 0.0;
  FourierSpectrum fourier{};
};

struct Percentiles {
  double x10 = 0.0, x50 = 0.0, x90 = 0.0;
  double span = 0.0;  // (x90 - x10) / x50
  double mean = 0.0;  // weighted mean
};

struct SizeDistribution {
  Percentiles number;           // Q0, weights 1
  Percentiles volume;           // Q3, weights d³ (sphere of the equivalent diameter)
  std::vector<double> edges_m;  // log-spaced class edges
  std::vector<double> Q0, Q3;   // cumulative fractions at the edges
};

struct AspectRatioDistribution {
  double mean = 0.0, std_dev = 0.0;
  double s50 = 0.0;                // median (QICPIC's S50)
  std::vector<double> levels;      // 0.05, 0.10, … 0.95
  std::vector<double> quantiles;   // ASR at those levels (number-weighted)
  double pearson_with_size = 0.0;  // correlation of ASR with the equivalent diameter
  double spearman_with_size = 0.0;
  std::vector<double> edges;  // histogram classes over [0, 1]
  std::vector<int> counts;
};

struct FourierSummary {
  int particles_used = 0;
  double min_diameter_px = 0.0;  // smaller outlines do not resolve D8 and are left out
  FourierSpectrum mean_spectrum{};
  FourierSpectrum std_spectrum{};
  double D2 = 0.0;                  // mean D2
  double D3 = 0.0, D8 = 0.0;        // from log D_n = a - α log n fitted over n = 3…8
  double irregularity_slope = 0.0;  // α
  double decay_exponent = 0.0;      // β in D_n = D8 (n/8)^-β fitted over n = 8…last_order
  int last_order = 0;
};

struct ShapeSummary {
  int particle_count = 0;
  SizeDistribution size;
  AspectRatioDistribution asr;
  FourierSummary fourier;
  double mean_circularity = 0.0, mean_solidity = 0.0, mean_convexity = 0.0;
};

// Weighted quantile at level p of values (midpoint rule on the cumulative weights).
double weighted_quantile(std::vector<double> values, std::vector<double> weights, double p);

// Throws InputError when `particles` is empty.
ShapeSummary summarize(const std::vector<ParticleSample>& particles,
                       double min_fourier_diameter_px = 20.0);

// One processed image, as reported in summary.json.
struct ImageReport {
  std::string file;
  int width = 0, height = 0;
  int info_bar_rows = 0;
  double pixel_size_m = 0.0;
  std::string pixel_size_source;  // "sem-metadata" or "--pixel-size"
  bool bright_particles = true;
  double threshold = 0.0;
  int particles = 0;
  int excluded_on_edge = 0;
  int excluded_by_size = 0;
  std::string background = "none";    // the flattening applied (none on a dense field)
  double background_fraction = -1.0;  // Otsu's background pixels / image (quadratic only)
};

std::string summary_to_json(const ShapeSummary& summary, const std::vector<ImageReport>& images,
                            const std::vector<std::string>& skipped,
                            const std::string& command_line);

}  // namespace shapepress::imaging
