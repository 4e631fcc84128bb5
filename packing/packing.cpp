#include "packing/packing.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <numeric>
#include <random>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "common/error.hpp"
#include "common/hdf5_file.hpp"

namespace shapepress::packing {

SphereList read_sphere_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open packing file '" + path.string() + "'");
  SphereList list;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    double x, y, z, r;
    if (!(fields >> x)) continue;  // blank or comment line
    std::string extra;
    if (!(fields >> y >> z >> r) || (fields >> extra) || !(r > 0.0) || !std::isfinite(x) ||
        !std::isfinite(y) || !std::isfinite(z) || !std::isfinite(r))
      throw InputError(path.string() + ":" + std::to_string(number) +
                       ": expected 'x y z r' in metres with r > 0");
    list.x.push_back(x);
    list.y.push_back(y);
    list.z.push_back(z);
    list.radius.push_back(r);
  }
  if (list.size() == 0) throw InputError("packing file '" + path.string() + "' has no spheres");
  return list;
}

SphereList read_sphere_hdf5(const std::filesystem::path& path) {
  H5Reader reader(path);
  // A snapshot of bodies read as loose spheres would lose its bonds or rigid clumps unnoticed:
  // the bodies fall apart at the first step.
  const bool bonded = reader.has("/bonds/pairs"), rigid = reader.has("/clumps/range");
  if (bonded || rigid)
    throw InputError(fmt::format(
        "'{}': a snapshot of {} bodies, not a sphere packing: continue it with `compact "
        "--restart`, or press a packing made by `shapepress pack`",
        path.string(), bonded ? "bonded (BMS)" : "rigid (CMS)"));
  std::vector<std::size_t> shape;
  const std::vector<double> position = reader.doubles("/particles/position", &shape);
  SphereList list;
  list.radius = reader.doubles("/particles/radius");
  if (shape.size() != 2 || shape[1] != 3 || shape[0] != list.radius.size())
    throw InputError(path.string() +
                     ": /particles/position must be N×3 with N = the length of "
                     "/particles/radius");
  for (std::size_t i = 0; i < list.radius.size(); ++i) {
    list.x.push_back(position[3 * i]);
    list.y.push_back(position[3 * i + 1]);
    list.z.push_back(position[3 * i + 2]);
    if (!(list.radius[i] > 0.0) || !std::isfinite(list.radius[i]))
      throw InputError(path.string() + ": /particles/radius[" + std::to_string(i) +
                       "] is not a finite length > 0");
    if (!std::isfinite(list.x[i]) || !std::isfinite(list.y[i]) || !std::isfinite(list.z[i]))
      throw InputError(path.string() + ": /particles/position[" + std::to_string(i) +
                       "] is not finite");
  }
  return list;
}

SphereList read_spheres(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  return (ext == ".h5" || ext == ".hdf5") ? read_sphere_hdf5(path) : read_sphere_text(path);
}

namespace {

double normal_cdf(double z) {
  return 0.5 * std::erfc(-z / std::sqrt(2.0));
}

// Inverse of the normal CDF by bisection (called a few times per distribution, not per sphere).
double probit(double q) {
  double lo = -40.0, hi = 40.0;
  for (int k = 0; k < 200 && hi - lo > 1e-15; ++k) {
    const double mid = 0.5 * (lo + hi);
    (normal_cdf(mid) < q ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

void SizeQuantiles::check() const {
  if (diameters.size() < 2 || diameters.size() != levels.size())
    throw InputError("size distribution: give at least two quantiles, as many levels as sizes");
  for (std::size_t k = 0; k < diameters.size(); ++k) {
    if (!(diameters[k] > 0.0) || !(levels[k] > 0.0 && levels[k] < 1.0))
      throw InputError("size distribution: sizes must be > 0 and levels in (0, 1)");
    if (k > 0 && !(diameters[k] > diameters[k - 1] && levels[k] > levels[k - 1]))
      throw InputError("size distribution: sizes and levels must both increase");
  }
}

namespace {

// Q of the stated weighting at a diameter: linear in (ln x, probit Q) between the quantiles.
struct GivenQ {
  std::vector<double> log_x, z;
  explicit GivenQ(const SizeQuantiles& q) {
    for (std::size_t k = 0; k < q.diameters.size(); ++k) {
      log_x.push_back(std::log(q.diameters[k]));
      z.push_back(probit(q.levels[k]));
    }
  }
  double operator()(double x) const {
    const double lx = std::log(x);
    std::size_t k = 1;
    while (k + 1 < log_x.size() && lx > log_x[k])
      ++k;
    const double t = (lx - log_x[k - 1]) / (log_x[k] - log_x[k - 1]);
    return normal_cdf(z[k - 1] + t * (z[k] - z[k - 1]));
  }
};

}  // namespace

double retained_fraction(const SizeQuantiles& q, double diameter_min, double diameter_max) {
  q.check();
  const GivenQ given_q(q);
  return given_q(diameter_max) - given_q(diameter_min);
}

SizeTable size_table(const SizeQuantiles& q, double diameter_min, double diameter_max) {
  q.check();
  if (!(diameter_min > 0.0 && diameter_max > diameter_min))
    throw InputError("size distribution: need 0 < diameter_min < diameter_max (the truncation)");
  const GivenQ given_q(q);
  // Number density q0 ∝ q3 / x³ (a sphere's volume), accumulated on a fine log grid.
  constexpr int points = 4001;
  SizeTable table;
  table.diameter.resize(points);
  table.cumulative.assign(points, 0.0);
  const double ratio = std::log(diameter_max / diameter_min);
  for (int k = 0; k < points; ++k)
    table.diameter[k] = diameter_min * std::exp(ratio * k / (points - 1));
  double previous = given_q(table.diameter[0]);
  for (int k = 1; k < points; ++k) {
    const double current = given_q(table.diameter[k]);
    const double mid = std::sqrt(table.diameter[k] * table.diameter[k - 1]);
    const double weight = q.volume_weighted ? 1.0 / (mid * mid * mid) : 1.0;
    table.cumulative[k] = table.cumulative[k - 1] + (current - previous) * weight;
    previous = current;
  }
  const double total = table.cumulative.back();
  if (!(total > 0.0))
    throw InputError("size distribution: no particles between diameter_min and diameter_max");
  for (double& c : table.cumulative)
    c /= total;
  return table;
}

double SizeTable::sample(double u) const {
  const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), u);
  if (it == cumulative.begin()) return diameter.front();
  if (it == cumulative.end()) return diameter.back();
  const std::size_t k = static_cast<std::size_t>(it - cumulative.begin());
  const double span = cumulative[k] - cumulative[k - 1];
  const double t = span > 0.0 ? (u - cumulative[k - 1]) / span : 0.0;
  return diameter[k - 1] * std::pow(diameter[k] / diameter[k - 1], t);
}

SphereList insert_random_spheres(const Box& box, const InsertionRequest& request) {
  if (!box.periodic_x() || !box.periodic_y())
    throw InputError("sphere generation needs a periodic box (box.x and box.y)");
  if (!(request.diameter_min > 0.0) || request.diameter_max < request.diameter_min)
    throw InputError("generate: need 0 < diameter_min <= diameter_max");
  const double r_max = 0.5 * request.diameter_max;
  if (request.z_high - request.z_low < 2.0 * r_max)
    throw InputError("generate: the region between the walls is thinner than one sphere");
  // Cell grid of the largest diameter: overlaps can only be with the 27 surrounding cells.
  const double cell = 2.0 * r_max;
  const int nx = std::max(1, static_cast<int>(box.length_x / cell));
  const int ny = std::max(1, static_cast<int>(box.length_y / cell));
  const int nz = std::max(1, static_cast<int>((request.z_high - request.z_low) / cell));
  std::vector<std::vector<std::int32_t>> cells(static_cast<std::size_t>(nx) * ny * nz);
  const auto cell_index = [&](double x, double y, double z, int out[3]) {
    out[0] = std::clamp(static_cast<int>(x / box.length_x * nx), 0, nx - 1);
    out[1] = std::clamp(static_cast<int>(y / box.length_y * ny), 0, ny - 1);
    out[2] = std::clamp(
        static_cast<int>((z - request.z_low) / (request.z_high - request.z_low) * nz), 0, nz - 1);
  };
  std::mt19937_64 random(request.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SphereList list;
  // A size distribution is drawn first and placed largest first: random sequential insertion
  // of a wide distribution fills a loose fill height far better that way.
  std::vector<double> drawn;
  if (request.sizes) {
    const SizeTable table = size_table(*request.sizes, request.diameter_min, request.diameter_max);
    for (std::int64_t k = 0; k < request.count; ++k)
      drawn.push_back(0.5 * table.sample(unit(random)));
    std::sort(drawn.begin(), drawn.end(), std::greater<>());
  }
  for (std::int64_t k = 0; k < request.count; ++k) {
    const double r = request.sizes
                         ? drawn[static_cast<std::size_t>(k)]
                         : 0.5 * (request.diameter_min +
                                  (request.diameter_max - request.diameter_min) * unit(random));
    bool placed = false;
    for (int attempt = 0; attempt < request.attempts_per_sphere && !placed; ++attempt) {
      const double x = box.length_x * unit(random), y = box.length_y * unit(random);
      const double z =
          request.z_low + r + (request.z_high - request.z_low - 2.0 * r) * unit(random);
      int c[3];
      cell_index(x, y, z, c);
      bool free = true;
      for (int dz = -1; dz <= 1 && free; ++dz) {
        const int cz = c[2] + dz;
        if (cz < 0 || cz >= nz) continue;
        for (int dy = -1; dy <= 1 && free; ++dy)
          for (int dx = -1; dx <= 1 && free; ++dx) {
            const int cx = (c[0] + dx + nx) % nx, cy = (c[1] + dy + ny) % ny;
            for (std::int32_t j : cells[(static_cast<std::size_t>(cz) * ny + cy) * nx + cx]) {
              double ddx = list.x[j] - x, ddy = list.y[j] - y;
              ddx -= box.length_x * std::nearbyint(ddx / box.length_x);
              ddy -= box.length_y * std::nearbyint(ddy / box.length_y);
              const double ddz = list.z[j] - z, reach = list.radius[j] + r;
              if (ddx * ddx + ddy * ddy + ddz * ddz < reach * reach) {
                free = false;
                break;
              }
            }
          }
      }
      if (!free) continue;
      cells[(static_cast<std::size_t>(c[2]) * ny + c[1]) * nx + c[0]].push_back(
          static_cast<std::int32_t>(list.size()));
      list.x.push_back(x);
      list.y.push_back(y);
      list.z.push_back(z);
      list.radius.push_back(r);
      placed = true;
    }
    if (!placed)
      throw InputError("generate: could not place sphere " + std::to_string(k + 1) + " of " +
                       std::to_string(request.count) +
                       " without overlap: make the box taller or the count smaller");
  }
  return list;
}

SphereList in_cell_order(const SphereList& list, double cell) {
  if (list.size() == 0 || !(cell > 0.0)) return list;
  const double x0 = *std::min_element(list.x.begin(), list.x.end());
  const double y0 = *std::min_element(list.y.begin(), list.y.end());
  const double z0 = *std::min_element(list.z.begin(), list.z.end());
  const auto index = [&](double v, double origin) {
    return static_cast<std::int64_t>((v - origin) / cell);  // >= 0 from the minimum
  };
  constexpr std::int64_t span = 1 << 20;  // cells per axis in the key, far beyond any bed
  std::vector<std::int64_t> key(list.size());
  for (std::size_t i = 0; i < list.size(); ++i)
    key[i] = (std::min(index(list.z[i], z0), span - 1) * span +
              std::min(index(list.y[i], y0), span - 1)) *
                 span +
             std::min(index(list.x[i], x0), span - 1);
  std::vector<std::size_t> order(list.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  SphereList sorted;
  for (std::size_t i : order) {
    sorted.x.push_back(list.x[i]);
    sorted.y.push_back(list.y[i]);
    sorted.z.push_back(list.z[i]);
    sorted.radius.push_back(list.radius[i]);
  }
  return sorted;
}

SphereState make_state(const SphereList& spheres, double density, int material) {
  SphereState state;
  for (std::size_t i = 0; i < spheres.size(); ++i)
    state.add_sphere(spheres.x[i], spheres.y[i], spheres.z[i], spheres.radius[i], density,
                     material);
  return state;
}

}  // namespace shapepress::packing
