#include "analysis/beds.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <fmt/format.h>

#include "common/error.hpp"
#include "common/hdf5_file.hpp"
#include "common/run_metadata.hpp"
#include "common/sha256.hpp"

namespace shapepress::analysis {
namespace {

using Vec = std::array<double, 3>;

double dot(const Vec& a, const Vec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// The caliper width of discs (a_i, b_i; r_i) across the in-plane direction at angle phi.
double caliper_width(const std::vector<double>& a, const std::vector<double>& b,
                     const std::vector<double>& r, double phi) {
  const double c = std::cos(phi), s = std::sin(phi);
  double high = -HUGE_VAL, low = HUGE_VAL;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double along = a[i] * c + b[i] * s;
    high = std::max(high, along + r[i]);
    low = std::min(low, along - r[i]);
  }
  return high - low;
}

// The extremum of the width within [phi - step, phi + step] by golden section: `sign` +1 for the
// minimum, -1 for the maximum.
double refined_width(const std::vector<double>& a, const std::vector<double>& b,
                     const std::vector<double>& r, double phi, double step, double sign) {
  const double golden = (std::sqrt(5.0) - 1.0) / 2.0;
  double lo = phi - step, hi = phi + step;
  double x1 = hi - golden * (hi - lo), x2 = lo + golden * (hi - lo);
  double f1 = sign * caliper_width(a, b, r, x1), f2 = sign * caliper_width(a, b, r, x2);
  const double best_sample = sign * caliper_width(a, b, r, phi);
  while (hi - lo > 1e-6) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - golden * (hi - lo), f1 = sign * caliper_width(a, b, r, x1);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + golden * (hi - lo), f2 = sign * caliper_width(a, b, r, x2);
    }
  }
  return sign * std::min({f1, f2, best_sample});
}

// A path as run.json states it: absolute, or relative to where the stage ran, which run.json
// does not keep; tried from the working directory, then from the run folder's parent (a study's
// OUT, when the stage ran there).
std::optional<std::filesystem::path> located(const std::filesystem::path& stated,
                                             const std::filesystem::path& run_folder) {
  if (stated.is_absolute())
    return std::filesystem::exists(stated) ? std::optional(stated) : std::nullopt;
  for (const std::filesystem::path& base :
       {std::filesystem::current_path(), run_folder.parent_path()})
    if (std::filesystem::exists(base / stated)) return base / stated;
  return std::nullopt;
}

std::optional<double> fact_of(const RunRecord& record, const std::string& key) {
  if (!record.has(key)) return std::nullopt;
  return record.number(key);
}

// The projected aspect ratio of every body of packed.h5, mean and standard deviation.
std::pair<double, double> bodies_aspect_ratio(const std::filesystem::path& packing,
                                              int directions) {
  const H5Reader file(packing);
  std::vector<std::size_t> shape;
  const std::vector<double> position = file.doubles("/particles/position", &shape);
  const std::vector<double> radius = file.doubles("/particles/radius");
  const std::vector<std::int32_t> first = file.int32s("/bodies/first_particle");
  if (shape.size() != 2 || shape[1] != 3 || shape[0] != radius.size() || first.size() < 2 ||
      first.front() != 0 || static_cast<std::size_t>(first.back()) != radius.size())
    throw InputError(fmt::format(
        "{}: /particles/position (N x 3), /particles/radius (N) and /bodies/first_particle "
        "(M + 1, from 0 to N) do not agree",
        packing.string()));
  const std::vector<Vec> views = viewing_directions(directions);
  std::vector<double> ratios;
  for (std::size_t body = 0; body + 1 < first.size(); ++body) {
    SphereUnion u;
    for (auto i = static_cast<std::size_t>(first[body]);
         i < static_cast<std::size_t>(first[body + 1]); ++i) {
      u.centre.push_back({position[3 * i], position[3 * i + 1], position[3 * i + 2]});
      u.radius.push_back(radius[i]);
    }
    if (u.radius.empty())
      throw InputError(fmt::format("{}: body {} has no sub-spheres", packing.string(), body));
    ratios.push_back(mean_projected_aspect_ratio(u, views));
  }
  double mean = 0.0, square = 0.0;
  for (double r : ratios)
    mean += r / static_cast<double>(ratios.size());
  for (double r : ratios)
    square += (r - mean) * (r - mean);
  const double sd =
      ratios.size() > 1 ? std::sqrt(square / static_cast<double>(ratios.size() - 1)) : 0.0;
  return {mean, sd};
}

}  // namespace

double projected_aspect_ratio(const SphereUnion& body, const Vec& direction) {
  // An in-plane basis (e1, e2) orthogonal to the viewing direction.
  const Vec helper = std::fabs(direction[0]) < 0.9 ? Vec{1, 0, 0} : Vec{0, 1, 0};
  Vec e1{helper[1] * direction[2] - helper[2] * direction[1],
         helper[2] * direction[0] - helper[0] * direction[2],
         helper[0] * direction[1] - helper[1] * direction[0]};
  const double n1 = std::sqrt(dot(e1, e1));
  for (double& v : e1)
    v /= n1;
  const Vec e2{direction[1] * e1[2] - direction[2] * e1[1],
               direction[2] * e1[0] - direction[0] * e1[2],
               direction[0] * e1[1] - direction[1] * e1[0]};
  std::vector<double> a, b;
  for (const Vec& c : body.centre)
    a.push_back(dot(c, e1)), b.push_back(dot(c, e2));
  // Widths repeat after π; the narrowest and widest of 90 samples, then refined.
  constexpr int samples = 90;
  const double step = std::numbers::pi / samples;
  int narrowest = 0, widest = 0;
  std::vector<double> width(samples);
  for (int k = 0; k < samples; ++k) {
    width[static_cast<std::size_t>(k)] = caliper_width(a, b, body.radius, k * step);
    if (width[static_cast<std::size_t>(k)] < width[static_cast<std::size_t>(narrowest)])
      narrowest = k;
    if (width[static_cast<std::size_t>(k)] > width[static_cast<std::size_t>(widest)]) widest = k;
  }
  const double feret_min = refined_width(a, b, body.radius, narrowest * step, step, 1.0);
  const double feret_max = refined_width(a, b, body.radius, widest * step, step, -1.0);
  return feret_max > 0.0 ? feret_min / feret_max : 0.0;
}

std::vector<Vec> viewing_directions(int directions, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<Vec> out;
  for (int k = 0; k < directions; ++k) {
    // Uniform on the sphere: z uniform in [-1, 1] and the azimuth uniform (Archimedes).
    const double z = 2.0 * uniform(rng) - 1.0, azimuth = 2.0 * std::numbers::pi * uniform(rng);
    const double ring = std::sqrt(std::max(0.0, 1.0 - z * z));
    out.push_back({ring * std::cos(azimuth), ring * std::sin(azimuth), z});
  }
  return out;
}

double mean_projected_aspect_ratio(const SphereUnion& body, const std::vector<Vec>& directions) {
  double sum = 0.0;
  for (const Vec& d : directions)
    sum += projected_aspect_ratio(body, d);
  return directions.empty() ? 0.0 : sum / static_cast<double>(directions.size());
}

BedFacts bed_facts(const std::filesystem::path& run_json, const PunchCurve& curve, int directions) {
  const RunRecord run = RunRecord::read(run_json);
  BedFacts bed;
  bed.particle_kind = run.has("particle_kind") ? run.text("particle_kind") : "";
  bed.compaction_seconds = fact_of(run, "loop_s");
  if (!bed.compaction_seconds)
    bed.notes.push_back("the compaction's loop_s is not in its run.json");
  const std::int64_t spheres = run.has("spheres") ? run.integer("spheres") : 0;
  // A bed of rigid clumps: its bodies are the clumps, not their sub-spheres.
  const std::int64_t clumps = run.has("clumps") ? run.integer("clumps") : 0;
  bed.bodies = clumps > 0 ? clumps : spheres;
  if (bed.bodies > 0) bed.sub_spheres_per_body = static_cast<double>(spheres) / bed.bodies;
  const bool plain_spheres = bed.particle_kind == "sphere";
  if (plain_spheres) bed.projected_aspect_ratio = 1.0, bed.projected_aspect_ratio_sd = 0.0;

  std::optional<std::filesystem::path> stated;
  std::string recorded_hash;
  for (const auto& input : run.json().value("inputs", nlohmann::json::array()))
    if (input.value("role", "") == "packing") {
      stated = input.value("path", "");
      recorded_hash = input.value("sha256", "");
    }
  if (!stated) {
    // A bed the compaction poured itself: as it was when the loading began.
    if (!curve.solid_fraction.empty()) bed.settled_solid_fraction = curve.solid_fraction.front();
    return bed;
  }
  const std::optional<std::filesystem::path> packing = located(*stated, run_json.parent_path());
  if (!packing) {
    bed.notes.push_back(fmt::format("the packing {} is not there", stated->string()));
    return bed;
  }
  if (sha256_file(*packing) != recorded_hash) {
    bed.notes.push_back(
        fmt::format("{} changed since the run (its SHA-256 is not run.json's)", packing->string()));
    return bed;
  }
  const std::filesystem::path pack_json = run_metadata_beside(*packing);
  if (!std::filesystem::exists(pack_json)) {
    bed.notes.push_back(fmt::format("{} has no run.json beside it", packing->string()));
  } else if (const RunRecord pack = RunRecord::read(pack_json); pack.stage() == "pack") {
    bed.settled_solid_fraction = fact_of(pack, "settled_solid_fraction");
    if (const auto pressed = fact_of(pack, "precompression_solid_fraction");
        pressed && *pressed > 0)
      bed.precompression_solid_fraction = pressed;
    bed.pack_seconds = fact_of(pack, "loop_s");
    if (pack.has("bodies")) bed.bodies = pack.integer("bodies");
  } else {
    bed.notes.push_back(
        fmt::format("{} is from `{}`, not `pack`", pack_json.string(), pack.stage()));
  }
  if (bed.bodies > 0) bed.sub_spheres_per_body = static_cast<double>(spheres) / bed.bodies;
  if (!plain_spheres && H5Reader(*packing).has("/bodies/first_particle")) {
    const auto [mean, sd] = bodies_aspect_ratio(*packing, directions);
    bed.projected_aspect_ratio = mean, bed.projected_aspect_ratio_sd = sd;
  }
  return bed;
}

}  // namespace shapepress::analysis
