#include "simulate/neighbor_list.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.hpp"

namespace shapepress::simulate {
namespace {

struct CellGrid {
  int n[3] = {1, 1, 1};
  double origin[3] = {0, 0, 0};
  double size[3] = {1, 1, 1};
  bool periodic[3] = {false, false, false};

  int coordinate(double value, int axis) const {
    int c = static_cast<int>(std::floor((value - origin[axis]) / size[axis]));
    if (periodic[axis]) {
      c %= n[axis];
      if (c < 0) c += n[axis];
    } else {
      c = std::clamp(c, 0, n[axis] - 1);
    }
    return c;
  }
};

CellGrid make_grid(const SphereState& state, const Box& box, double cell) {
  CellGrid g;
  const SphereArray<double>* coords[3] = {&state.position.x, &state.position.y, &state.position.z};
  const double lengths[3] = {box.length_x, box.length_y, 0.0};
  for (int axis = 0; axis < 3; ++axis) {
    if (lengths[axis] > 0.0) {
      g.periodic[axis] = true;
      // A pair must meet through one image only: its reach (at most one cell) below L/2. Fewer
      // than three cells are fine then (a 1 mm box of Avicel spheres up to 470 µm has two); the
      // search visits each distinct neighbour cell once (last_offset below).
      if (!(2.0 * cell < lengths[axis]))
        throw InputError("periodic box length " + std::to_string(lengths[axis]) +
                         " m is not more than twice the neighbour reach " + std::to_string(cell) +
                         " m (2 × largest radius + skin): a pair could meet through two images");
      g.n[axis] = std::max(1, static_cast<int>(std::floor(lengths[axis] / cell)));
      g.size[axis] = lengths[axis] / g.n[axis];
    } else {
      const auto [lo, hi] = std::minmax_element(coords[axis]->begin(), coords[axis]->end());
      g.origin[axis] = *lo;
      g.size[axis] = cell;
      // Bounded extent: the cap keeps a runaway sphere from allocating a huge grid.
      g.n[axis] = std::clamp(static_cast<int>((*hi - *lo) / cell) + 1, 1, 1 << 12);
    }
  }
  return g;
}

// The image (-1, 0, +1 box lengths) that brings a separation to its nearest image (|d| < 1.5 L
// here: positions are wrapped at builds and move less than half a skin between them).
int minimum_image(double d, double length) {
  if (length <= 0.0) return 0;
  const double half = 0.5 * length;
  return d > half ? -1 : (d < -half ? 1 : 0);
}

// PairList::image's code of the images (ix, iy), each in -1..1.
std::uint8_t image_code(int ix, int iy) {
  return static_cast<std::uint8_t>(3 * (ix + 1) + iy + 1);
}

// The shift (x, y) of each periodic image code (image_code), for the force loops.
void set_image_shifts(PairList& list, const Box& box) {
  for (int ix = -1; ix <= 1; ++ix)
    for (int iy = -1; iy <= 1; ++iy) {
      list.image_shift[2 * image_code(ix, iy)] = ix * std::max(box.length_x, 0.0);
      list.image_shift[2 * image_code(ix, iy) + 1] = iy * std::max(box.length_y, 0.0);
    }
}

void append_pairs(PairList& list, const PairList& part) {
  list.first.insert(list.first.end(), part.first.begin(), part.first.end());
  list.second.insert(list.second.end(), part.second.begin(), part.second.end());
  list.image.insert(list.image.end(), part.image.begin(), part.image.end());
}

// The spheres sorted into the grid's cells by a counting sort, keeping index order within a
// cell: each sphere's cell coordinates, where each cell's members start, and the members in cell
// order with packed copies of their x, y, z, r (a cell's candidates are then read as one stream
// instead of four scattered arrays).
struct CellSort {
  std::vector<std::int32_t> cell_x, cell_y, cell_z;
  std::vector<std::int32_t> cell_start;  // cells + 1 offsets into members
  std::vector<std::int32_t> members;
  std::vector<double> packed;  // x, y, z, r of members[m] at 4 m
};

CellSort sort_into_cells(const SphereState& state, const CellGrid& g) {
  const int count = static_cast<int>(state.size());
  const int cells = g.n[0] * g.n[1] * g.n[2];
  std::vector<std::int32_t> cell_of(count), cell_x(count), cell_y(count), cell_z(count);
  std::vector<std::int32_t> cell_start(static_cast<std::size_t>(cells) + 1, 0);
  for (int i = 0; i < count; ++i) {
    cell_x[i] = g.coordinate(state.position.x[i], 0);
    cell_y[i] = g.coordinate(state.position.y[i], 1);
    cell_z[i] = g.coordinate(state.position.z[i], 2);
    const int c = (cell_z[i] * g.n[1] + cell_y[i]) * g.n[0] + cell_x[i];
    cell_of[i] = c;
    ++cell_start[c + 1];
  }
  for (int c = 0; c < cells; ++c)
    cell_start[c + 1] += cell_start[c];
  std::vector<std::int32_t> members(count);
  std::vector<double> packed(4 * static_cast<std::size_t>(count));
  std::vector<std::int32_t> fill(cell_start.begin(), cell_start.end() - 1);
  for (int i = 0; i < count; ++i) {
    const int m = fill[cell_of[i]]++;
    members[m] = i;
    packed[4 * m] = state.position.x[i];
    packed[4 * m + 1] = state.position.y[i];
    packed[4 * m + 2] = state.position.z[i];
    packed[4 * m + 3] = state.radius[i];
  }
  return {std::move(cell_x),     std::move(cell_y),  std::move(cell_z),
          std::move(cell_start), std::move(members), std::move(packed)};
}

// The gather lists of a list sorted by first: each sphere's pairs as first and as second
// (second_pairs filled in pair order, so each sphere's are sorted by pair index).
void add_gather_lists(PairList& list, int count) {
  const std::size_t pairs = list.size();
  for (std::size_t p = 0; p < pairs; ++p) {
    ++list.first_offset[list.first[p] + 1];
    ++list.second_offset[list.second[p] + 1];
  }
  for (int i = 0; i < count; ++i) {
    list.first_offset[i + 1] += list.first_offset[i];
    list.second_offset[i + 1] += list.second_offset[i];
  }
  list.second_pairs.resize(pairs);
  std::vector<std::int32_t> fill(list.second_offset.begin(), list.second_offset.end() - 1);
  for (std::size_t p = 0; p < pairs; ++p)
    list.second_pairs[fill[list.second[p]]++] = static_cast<std::int32_t>(p);
}

}  // namespace

PairList build_pair_list(const SphereState& state, const Box& box, double skin,
                         std::span<const std::int32_t> rigid_group) {
  const int count = static_cast<int>(state.size());
  PairList list;
  set_image_shifts(list, box);
  list.first_offset.assign(static_cast<std::size_t>(count) + 1, 0);
  list.second_offset.assign(static_cast<std::size_t>(count) + 1, 0);
  if (count == 0) return list;
  const double r_max = *std::max_element(state.radius.begin(), state.radius.end());
  const CellGrid g = make_grid(state, box, 2.0 * r_max + skin);
  const CellSort sorted = sort_into_cells(state, g);
  const std::vector<std::int32_t>& cell_x = sorted.cell_x;
  const std::vector<std::int32_t>& cell_y = sorted.cell_y;
  const std::vector<std::int32_t>& cell_z = sorted.cell_z;
  const std::vector<std::int32_t>& cell_start = sorted.cell_start;
  const std::vector<std::int32_t>& members = sorted.members;
  const std::vector<double>& packed = sorted.packed;

  // Offsets -1..last per axis: with fewer than three periodic cells, -1 and +1 (and 0) name the
  // same cell, which must be searched once.
  const auto last_offset = [&](int axis) {
    return g.periodic[axis] ? std::min(1, g.n[axis] - 2) : 1;
  };
  const int last_x = last_offset(0), last_y = last_offset(1);
  const auto& x = state.position.x;
  const auto& y = state.position.y;
  const auto& z = state.position.z;
  const int threads = omp_get_max_threads();
  std::vector<PairList> parts(threads);
  // About eight partners within reach per sphere in a dense bed: reserve so a build does not
  // reallocate its way up.
  for (PairList& part : parts) {
    const std::size_t expected = 8 * static_cast<std::size_t>(count) / threads + 64;
    part.first.reserve(expected);
    part.second.reserve(expected);
    part.image.reserve(expected);
  }
  // Static schedule: thread t gets a contiguous range of i, so concatenating the parts in thread
  // order gives the list sorted by first, whatever the thread count.
#pragma omp parallel num_threads(threads) if (count >= 1024)
  {
    PairList& part = parts[omp_get_thread_num()];
    struct Partner {
      std::int32_t sphere;
      std::uint8_t image;
    };
    std::vector<Partner> partners;
#pragma omp for schedule(static)
    for (int i = 0; i < count; ++i) {
      partners.clear();
      const int ci[3] = {cell_x[i], cell_y[i], cell_z[i]};
      const double xi = x[i], yi = y[i], zi = z[i], ri_skin = state.radius[i] + skin;
      for (int dz = -1; dz <= 1; ++dz) {
        const int cz = ci[2] + dz;
        if (cz < 0 || cz >= g.n[2]) continue;
        for (int dy = -1; dy <= last_y; ++dy) {
          int cy = ci[1] + dy;  // wrapped with branches: a modulo per cell costs a division
          if (cy < 0 || cy >= g.n[1]) {
            if (!g.periodic[1]) continue;
            cy += cy < 0 ? g.n[1] : -g.n[1];
          }
          for (int dx = -1; dx <= last_x; ++dx) {
            int cx = ci[0] + dx;
            if (cx < 0 || cx >= g.n[0]) {
              if (!g.periodic[0]) continue;
              cx += cx < 0 ? g.n[0] : -g.n[0];
            }
            const int c = (cz * g.n[1] + cy) * g.n[0] + cx;
            for (int m = cell_start[c]; m < cell_start[c + 1]; ++m) {
              const int j = members[m];
              if (j <= i) continue;
              const double* pj = &packed[4 * static_cast<std::size_t>(m)];
              const int image_x = minimum_image(pj[0] - xi, box.length_x);
              const int image_y = minimum_image(pj[1] - yi, box.length_y);
              const double ddx = pj[0] - xi + image_x * box.length_x;
              const double ddy = pj[1] - yi + image_y * box.length_y;
              const double ddz = pj[2] - zi;
              const double reach = ri_skin + pj[3];
              if (ddx * ddx + ddy * ddy + ddz * ddz < reach * reach &&
                  (rigid_group.empty() || rigid_group[i] < 0 || rigid_group[i] != rigid_group[j]))
                partners.push_back({j, image_code(image_x, image_y)});
            }
          }
        }
      }
      std::sort(partners.begin(), partners.end(),
                [](const Partner& a, const Partner& b) { return a.sphere < b.sphere; });
      for (const Partner& partner : partners) {
        part.first.push_back(i);
        part.second.push_back(partner.sphere);
        part.image.push_back(partner.image);
      }
    }
  }
  for (const PairList& part : parts)
    append_pairs(list, part);
  add_gather_lists(list, count);
  return list;
}

std::vector<ContactHistory> carry_history(const PairList& old_pairs,
                                          const std::vector<ContactHistory>& old_history,
                                          const PairList& new_pairs) {
  std::vector<ContactHistory> history(new_pairs.size());
  std::size_t a = 0;
  const std::size_t old_size = old_pairs.size();
  for (std::size_t b = 0; b < new_pairs.size(); ++b) {
    const auto key = [](const PairList& l, std::size_t k) {
      return (static_cast<std::int64_t>(l.first[k]) << 32) | l.second[k];
    };
    const std::int64_t wanted = key(new_pairs, b);
    while (a < old_size && key(old_pairs, a) < wanted)
      ++a;
    if (a < old_size && key(old_pairs, a) == wanted) history[b] = old_history[a];
  }
  return history;
}

double wrapped(double v, double length) {
  if (length <= 0.0 || (v >= 0.0 && v < length)) return v;
  v -= length * std::floor(v / length);
  return v >= length ? v - length : v;  // -1e-17 wraps to exactly L: bring it to 0
}

void wrap_positions(SphereState& state, const Box& box) {
  for (double& v : state.position.x)
    v = wrapped(v, box.length_x);
  for (double& v : state.position.y)
    v = wrapped(v, box.length_y);
}

}  // namespace shapepress::simulate
