#include "simulate/packing.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "common/error.hpp"
#include "common/hdf5_file.hpp"

namespace shapepress::simulate {

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
        !std::isfinite(y) || !std::isfinite(z))
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
    if (!(list.radius[i] > 0.0))
      throw InputError(path.string() + ": /particles/radius[" + std::to_string(i) + "] <= 0");
  }
  return list;
}

SphereList read_spheres(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  return (ext == ".h5" || ext == ".hdf5") ? read_sphere_hdf5(path) : read_sphere_text(path);
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
  for (std::int64_t k = 0; k < request.count; ++k) {
    const double r =
        0.5 * (request.diameter_min + (request.diameter_max - request.diameter_min) * unit(random));
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

SphereState make_state(const SphereList& spheres, double density, int material) {
  SphereState state;
  for (std::size_t i = 0; i < spheres.size(); ++i)
    state.add_sphere(spheres.x[i], spheres.y[i], spheres.z[i], spheres.radius[i], density,
                     material);
  return state;
}

}  // namespace shapepress::simulate
