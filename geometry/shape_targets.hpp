#pragma once
// What a particle population must look like: the shape-stats summary.json of the imaging stage,
// or a TOML with the same keys for numbers typed in from a QICPIC report:
//
//   [fourier]  D2 = 0.06  D3 = 0.03  D8 = 0.008  decay_exponent = 2.0
//   [asr]      quantile_levels = [0.05, …, 0.95]  quantiles = [...]   # projected (image) ASR
//              mean = 0.8  elongation = 0.84  flatness = 0.95          # or 3D box targets
//   [size]     x10_m = 40e-6  x50_m = 90e-6  x90_m = 180e-6           # equivalent circle
//
// With asr.quantiles the population's *projected* ASR (Feret min/max of silhouettes) follows
// that distribution; without them asr.mean (S/L), asr.elongation (I/L) and asr.flatness (S/I)
// are targets for the 3D box ratios.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/options.hpp"

namespace shapepress::geometry {

struct ShapeTargets {
  double D2 = 0.0, D3 = 0.0, D8 = 0.0, decay_exponent = 2.0;
  std::vector<double> asr_levels, asr_quantiles;  // the image's projected ASR distribution
  std::optional<double> asr_mean, elongation, flatness;
  double x10_m = 0.0, x50_m = 0.0, x90_m = 0.0;
  std::string source;

  bool projected_distribution() const { return !asr_quantiles.empty(); }
  // Probability that the target projected ASR is <= a (piecewise linear through the quantiles,
  // extended to 0 and 1 with the end slopes).
  double asr_cdf(double a) const;
  double asr_quantile(double p) const;
  // Equivalent-circle diameter at cumulative level p (log-linear through x10, x50, x90).
  double size_quantile(double p) const;
  // The 3D box ratios wanted on average: explicit ones, else e = f = sqrt(ASR).
  double target_elongation() const;
  double target_flatness() const;
  void check() const;  // InputError naming the source and the bad field
};

// .json (shape-stats summary) or .toml by extension; InputError naming the file and key.
ShapeTargets read_shape_targets(const std::filesystem::path& path);
// The targets as the TOML read_shape_targets reads back to the same values (generate's
// effective.toml, whichever file they came from).
std::string shape_targets_toml(const ShapeTargets& targets);
// The TOML's keys, for generate --help-config and docs/config-reference.md.
StageOptions shape_targets_options();

}  // namespace shapepress::geometry
