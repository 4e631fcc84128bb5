#include "geometry/shape_targets.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/config.hpp"
#include "common/error.hpp"
#include "common/options.hpp"

namespace shapepress::geometry {
namespace {

const std::vector<double> default_levels = {0.05, 0.10, 0.15, 0.20, 0.25, 0.30, 0.35,
                                            0.40, 0.45, 0.50, 0.55, 0.60, 0.65, 0.70,
                                            0.75, 0.80, 0.85, 0.90, 0.95};

// Piecewise-linear interpolation of y(x) over increasing xs, extended linearly beyond the ends.
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
  std::size_t i = 1;
  while (i + 1 < xs.size() && x > xs[i])
    ++i;
  const double span = xs[i] - xs[i - 1];
  const double t = span > 0.0 ? (x - xs[i - 1]) / span : 0.0;
  return ys[i - 1] + t * (ys[i] - ys[i - 1]);
}

ShapeTargets from_json(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("shape targets '{}': cannot open the file", path.string()));
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("shape targets '{}': not JSON: {}", path.string(), e.what()));
  }
  auto number = [&](const char* group, const char* key) -> std::optional<double> {
    if (!j.contains(group) || !j[group].contains(key)) return std::nullopt;
    const auto& v = j[group][key];
    if (!v.is_number())
      throw InputError(
          fmt::format("shape targets '{}': {}.{} must be a number", path.string(), group, key));
    return v.get<double>();
  };
  auto required = [&](const char* group, const char* key) {
    const auto v = number(group, key);
    if (!v)
      throw InputError(fmt::format("shape targets '{}': missing {}.{}", path.string(), group, key));
    return *v;
  };
  ShapeTargets t;
  t.source = path.string();
  t.D2 = number("fourier", "D2").value_or(0.0);
  t.D3 = required("fourier", "D3");
  t.D8 = required("fourier", "D8");
  t.decay_exponent = number("fourier", "decay_exponent").value_or(2.0);
  if (j.contains("asr") && j["asr"].contains("quantiles")) {
    t.asr_quantiles = j["asr"]["quantiles"].get<std::vector<double>>();
    t.asr_levels = j["asr"].contains("quantile_levels")
                       ? j["asr"]["quantile_levels"].get<std::vector<double>>()
                       : default_levels;
  }
  t.asr_mean = number("asr", "mean");
  t.elongation = number("asr", "elongation");
  t.flatness = number("asr", "flatness");
  t.x10_m = required("size", "x10_m");
  t.x50_m = required("size", "x50_m");
  t.x90_m = required("size", "x90_m");
  return t;
}

const OptionTable<ShapeTargets>& fourier_table() {
  static const OptionTable<ShapeTargets> t = [] {
    OptionTable<ShapeTargets> f("fourier", "outline Fourier descriptors (shape-stats)");
    f.number("D2", &ShapeTargets::D2, Range::closed(0.0, 1.0), "elongation descriptor")
        .number("D3", &ShapeTargets::D3, Range::closed(0.0, 0.5), "triangularity descriptor")
        .required()
        .number("D8", &ShapeTargets::D8, Range::closed(0.0, 0.5), "roughness descriptor")
        .required()
        .number("decay_exponent", &ShapeTargets::decay_exponent, Range::closed(0.0, 10.0),
                "decay of the higher descriptors with the degree");
    return f;
  }();
  return t;
}

const OptionTable<ShapeTargets>& asr_table() {
  static const OptionTable<ShapeTargets> t = [] {
    OptionTable<ShapeTargets> a(
        "asr", "aspect ratio: the projected distribution (quantiles) or 3D box targets (mean)");
    a.numbers("quantiles", &ShapeTargets::asr_quantiles, dim::dimensionless,
              Range::open_closed(0.0, 1.0), "projected ASR (Feret min/max) at quantile_levels")
        .numbers("quantile_levels", &ShapeTargets::asr_levels, dim::dimensionless,
                 Range::closed(0.0, 1.0), "cumulative levels of quantiles")
        .default_text("0.05, 0.10, ..., 0.95")
        .when([](const ShapeTargets& s) { return s.projected_distribution(); },
              "without asr.quantiles")
        .number("mean", &ShapeTargets::asr_mean, Range::open_closed(0.0, 1.0),
                "3D S/L on average (without quantiles)")
        .number("elongation", &ShapeTargets::elongation, Range::open_closed(0.0, 1.0),
                "3D I/L on average")
        .default_text("from mean")
        .number("flatness", &ShapeTargets::flatness, Range::open_closed(0.0, 1.0),
                "3D S/I on average")
        .default_text("from mean");
    return a;
  }();
  return t;
}

const OptionTable<ShapeTargets>& size_table() {
  static const OptionTable<ShapeTargets> t = [] {
    OptionTable<ShapeTargets> z("size", "equivalent circle diameters");
    z.quantity("x10_m", &ShapeTargets::x10_m, dim::length, Range::positive(), "10 % quantile")
        .required()
        .quantity("x50_m", &ShapeTargets::x50_m, dim::length, Range::positive(), "median")
        .required()
        .quantity("x90_m", &ShapeTargets::x90_m, dim::length, Range::positive(), "90 % quantile")
        .required();
    return z;
  }();
  return t;
}

ShapeTargets from_toml(const std::filesystem::path& path) {
  const ConfigTable config = ConfigTable::load_file(path);
  ShapeTargets t;
  t.source = path.string();
  fourier_table().read(config.table("fourier"), t);
  asr_table().read(config.table("asr"), t);
  if (t.projected_distribution() && t.asr_levels.empty()) t.asr_levels = default_levels;
  size_table().read(config.table("size"), t);
  config.check_unknown_keys();
  return t;
}

}  // namespace

double ShapeTargets::asr_cdf(double a) const {
  return std::clamp(interpolate(asr_quantiles, asr_levels, a), 0.0, 1.0);
}

double ShapeTargets::asr_quantile(double p) const {
  return std::clamp(interpolate(asr_levels, asr_quantiles, p), 0.01, 1.0);
}

double ShapeTargets::size_quantile(double p) const {
  const std::vector<double> levels = {0.1, 0.5, 0.9};
  const std::vector<double> logs = {std::log(x10_m), std::log(x50_m), std::log(x90_m)};
  return std::exp(interpolate(levels, logs, std::clamp(p, 0.01, 0.99)));
}

double ShapeTargets::target_elongation() const {
  if (elongation) return *elongation;
  const double a = asr_mean.value_or(1.0);
  return flatness ? a / *flatness : std::sqrt(a);
}

double ShapeTargets::target_flatness() const {
  if (flatness) return *flatness;
  return asr_mean.value_or(1.0) / target_elongation();
}

void ShapeTargets::check() const {
  auto bad = [&](const std::string& what) {
    throw InputError(fmt::format("shape targets '{}': {}", source, what));
  };
  if (!(x10_m > 0.0 && x10_m <= x50_m && x50_m <= x90_m))
    bad(fmt::format("sizes must satisfy 0 < x10_m <= x50_m <= x90_m (got {}, {}, {})", x10_m, x50_m,
                    x90_m));
  if (!(D3 >= 0.0 && D3 < 0.5 && D8 >= 0.0 && D8 < 0.5))
    bad(fmt::format("fourier.D3 = {} and fourier.D8 = {} must be in [0, 0.5)", D3, D8));
  if (projected_distribution()) {
    if (asr_levels.size() != asr_quantiles.size() || asr_levels.size() < 2)
      bad("asr.quantiles and asr.quantile_levels must have the same length (>= 2)");
    for (std::size_t i = 1; i < asr_levels.size(); ++i)
      if (!(asr_levels[i] > asr_levels[i - 1]) || asr_quantiles[i] < asr_quantiles[i - 1])
        bad("asr.quantile_levels must increase and asr.quantiles must not decrease");
  } else if (!asr_mean && !(elongation && flatness)) {
    bad("give asr.quantiles (the image distribution) or asr.mean (3D S/L)");
  }
  const double e = target_elongation(), f = target_flatness();
  if (!(e > 0.0 && e <= 1.0 && f > 0.0 && f <= 1.0))
    bad(fmt::format("elongation {} and flatness {} must be in (0, 1]", e, f));
}

std::string shape_targets_toml(const ShapeTargets& targets) {
  return fourier_table().write(targets) + "\n" + asr_table().write(targets) + "\n" +
         size_table().write(targets);
}

StageOptions shape_targets_options() {
  return {"generate",
          "generate --targets: a TOML with these keys (or the shape-stats summary.json, which "
          "has the same ones)",
          {fourier_table().docs(), asr_table().docs(), size_table().docs()}};
}

ShapeTargets read_shape_targets(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (!std::filesystem::exists(path))
    throw InputError(fmt::format("shape targets '{}': no such file", path.string()));
  ShapeTargets t;
  if (ext == ".json")
    t = from_json(path);
  else if (ext == ".toml")
    t = from_toml(path);
  else
    throw InputError(
        fmt::format("shape targets '{}': expected a .json (shape-stats summary) or "
                    ".toml file",
                    path.string()));
  t.check();
  return t;
}

}  // namespace shapepress::geometry
