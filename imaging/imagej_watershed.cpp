#include "imaging/imagej_watershed.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstddef>
#include <limits>

namespace shapepress::imaging {

namespace {

// Neighbours clockwise from north (y down): N, NE, E, SE, S, SW, W, NW, the order in which
// ImageJ visits them; the order decides ties, so it is kept.
constexpr std::array<int, 8> dir_x = {0, 1, 1, 1, 0, -1, -1, -1};
constexpr std::array<int, 8> dir_y = {-1, -1, 0, 1, 1, 1, 0, -1};
constexpr float sqrt2 = 1.4142135624f;

struct Grid {
  int width, height;
  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  bool on_edge(int x, int y) const { return x == 0 || y == 0 || x == width - 1 || y == height - 1; }
};

// One horizontal sweep of the distance propagation over row y: each particle pixel takes the
// nearest of the background points known to its neighbour in the previous row, to its diagonal
// neighbour there and to its neighbour in this row (`nearest` holds them per column, -1: none).
void sweep_row(const std::vector<std::uint8_t>& mask, std::vector<float>& dist2,
               std::vector<std::int32_t>& nearest, int width, int y, int step) {
  const auto squared = [&](std::int32_t point, int x) {
    const int px = point % width, py = point / width;
    return static_cast<long long>(x - px) * (x - px) + static_cast<long long>(y - py) * (y - py);
  };
  std::int32_t previous = -1, diagonal = -1;
  for (int x = step > 0 ? 0 : width - 1; x >= 0 && x < width; x += step) {
    const std::int32_t above = nearest[x];
    const std::size_t i = static_cast<std::size_t>(y) * width + x;
    if (!mask[i]) {
      nearest[x] = static_cast<std::int32_t>(i);
    } else {
      long long best = INT_MAX;  // image edges are not background
      std::int32_t chosen = above;
      // Candidates in ImageJ's order; on equal distances the earlier one stays.
      const auto consider = [&](std::int32_t candidate) {
        if (candidate < 0) return;
        if (const long long d = squared(candidate, x); d < best) {
          best = d;
          chosen = candidate;
        }
      };
      consider(above);
      if (diagonal != above) consider(diagonal);
      if (previous != diagonal) consider(previous);
      nearest[x] = chosen;
      dist2[i] = std::min(dist2[i], static_cast<float>(best));
    }
    previous = nearest[x];
    diagonal = above;
  }
}

// Height of the distance map's ridge at a pixel, interpolated from its neighbours: a maximum or
// saddle sampled off its true position reads up to half a diagonal too low (ImageJ's
// MaximumFinder.trueEdmHeight).
float ridge_height(const std::vector<float>& edm, const Grid& g, int x, int y) {
  const std::size_t i = static_cast<std::size_t>(y) * g.width + x;
  const float v = edm[i];
  if (g.on_edge(x, y) || v == 0) return v;
  float height = v + 0.5f * sqrt2;
  bool ridge = false;
  for (int d = 0; d < 4; ++d) {
    const float a = edm[static_cast<std::size_t>(y + dir_y[d]) * g.width + x + dir_x[d]];
    const float b = edm[static_cast<std::size_t>(y - dir_y[d]) * g.width + x - dir_x[d]];
    float h = 0;
    if (v >= a && v >= b) {
      ridge = true;
      h = (a + b) / 2;
    } else {
      h = std::min(a, b);
    }
    h += d % 2 == 0 ? 1.0f : sqrt2;
    height = std::min(height, h);
  }
  return ridge ? height : v;
}

enum : std::uint8_t { listed = 1, processed = 2, seed = 4, eliminated = 8 };

// Local maxima of the distance map (pixels no neighbour exceeds both in value and in ridge
// height), lowest first, ordered as ImageJ orders them: by the ridge height scaled to a 32-bit
// integer, then by pixel index.
std::vector<std::int32_t> sorted_maxima(const std::vector<float>& edm,
                                        const std::vector<float>& ridge, const Grid& g, float low,
                                        float high) {
  std::vector<std::pair<long long, std::int32_t>> keyed;
  const float scale = static_cast<float>(2e9 / (high - low));
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const std::int32_t i = y * g.width + x;
      if (edm[i] == low) continue;
      bool maximum = true;
      for (int d = 0; d < 8 && maximum; ++d) {
        const int nx = x + dir_x[d], ny = y + dir_y[d];
        if (!g.inside(nx, ny)) continue;
        const std::int32_t j = ny * g.width + nx;
        maximum = !(edm[j] > edm[i] && ridge[j] > ridge[i]);
      }
      if (!maximum) continue;
      // Java's float-to-int conversion saturates; so does this one.
      const double key = static_cast<double>((ridge[i] - low) * scale);
      keyed.emplace_back(key >= INT_MAX ? INT_MAX : static_cast<long long>(key), i);
    }
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::int32_t> maxima;
  maxima.reserve(keyed.size());
  for (const auto& entry : keyed)
    maxima.push_back(entry.second);
  return maxima;
}

// Marks as seeds the plateau of every maximum that stands more than `tolerance` above the
// saddle to a higher one: from the highest down, the pixels within `tolerance` below it are
// flooded; a maximum whose flood reaches one flooded before, or a higher pixel, is none. The
// maxima come sorted by a rounded height, so a flood that meets a pixel higher than its start
// restarts from there.
void mark_seeds(const std::vector<float>& edm, const std::vector<float>& ridge, const Grid& g,
                const std::vector<std::int32_t>& maxima, double tolerance,
                std::vector<std::uint8_t>& type) {
  const float sorting_error = 1.1f * sqrt2 / 2.0f;
  std::vector<std::int32_t> list;
  for (auto it = maxima.rbegin(); it != maxima.rend(); ++it) {
    std::int32_t start = *it;
    if (type[start] & processed) continue;
    float top = ridge[start];
    bool restart = false;
    do {
      list.assign(1, start);
      type[start] |= listed;
      restart = false;
      bool possible = true;
      for (std::size_t k = 0; k < list.size(); ++k) {
        const int x = list[k] % g.width, y = list[k] / g.width;
        for (int d = 0; d < 8; ++d) {
          const int nx = x + dir_x[d], ny = y + dir_y[d];
          if (!g.inside(nx, ny)) continue;
          const std::int32_t j = ny * g.width + nx;
          if ((type[j] & listed) || edm[j] <= 0) continue;
          if (type[j] & processed) {
            possible = false;  // this pixel's remaining neighbours are skipped, as in ImageJ
            break;
          }
          const float v = ridge[j];
          if (v > top + sorting_error) {
            possible = false;
            break;
          }
          if (v >= top - static_cast<float>(tolerance)) {
            if (v > top) {
              restart = true;
              start = j;
              top = v;
            }
            list.push_back(j);
            type[j] |= listed;
          }
        }
      }
      for (const std::int32_t p : list)
        type[p] = restart ? 0
                          : static_cast<std::uint8_t>((type[p] & ~listed) | processed |
                                                      (possible ? seed : 0));
    } while (restart);
  }
}

// The distance map as whole-pixel levels 1-254 (ImageJ's 8-bit conversion for the watershed:
// no finer steps than a pixel), 0 on the background, 255 on the seeds.
std::vector<std::uint8_t> to_levels(const std::vector<float>& edm,
                                    const std::vector<std::uint8_t>& type, float high) {
  const double low = 1.0;
  const double offset = low - (high - low) * (1.0 / 253 / 2 - 1e-6);
  const double factor = std::min(1.0, 253 / (high - low));
  std::vector<std::uint8_t> level(edm.size());
  for (std::size_t i = 0; i < edm.size(); ++i) {
    if (edm[i] < 0.5f) {
      level[i] = 0;
    } else if (type[i] & seed) {
      level[i] = 255;
    } else {
      const double v = 1 + std::floor((edm[i] - offset) * factor + 0.5);
      level[i] = static_cast<std::uint8_t>(std::clamp(v, 1.0, 254.0));
    }
  }
  return level;
}

// Levels the maxima that seed nothing: each one's pixels above the saddle where its flood, going
// down level by level, first touches a seed (or a maximum levelled before, at that height) are
// set to the saddle's level, so that the flood of the watershed reaches them from the seed.
void level_off_minor_maxima(std::vector<std::uint8_t>& level, std::vector<std::uint8_t>& type,
                            const Grid& g, const std::vector<std::int32_t>& maxima) {
  std::vector<std::int32_t> list;
  for (auto it = maxima.rbegin(); it != maxima.rend(); ++it) {
    const std::int32_t start = *it;
    if (type[start] & (seed | eliminated)) continue;
    int low = level[start] + 1;
    list.assign(1, start);
    type[start] |= listed;
    std::size_t above_saddle = 1;
    bool saddle = false;
    while (!saddle && low > 0) {
      --low;
      above_saddle = list.size();
      for (std::size_t k = 0; k < list.size() && !saddle; ++k) {
        const int x = list[k] % g.width, y = list[k] / g.width;
        for (int d = 0; d < 8; ++d) {
          const int nx = x + dir_x[d], ny = y + dir_y[d];
          if (!g.inside(nx, ny)) continue;
          const std::int32_t j = ny * g.width + nx;
          if (type[j] & listed) continue;
          if ((type[j] & seed) || ((type[j] & eliminated) && level[j] >= low)) {
            saddle = true;
            break;
          }
          if (level[j] >= low && !(type[j] & eliminated)) {
            list.push_back(j);
            type[j] |= listed;
          }
        }
      }
    }
    for (const std::int32_t p : list)
      type[p] &= static_cast<std::uint8_t>(~listed);
    for (std::size_t k = 0; k < above_saddle; ++k) {
      level[list[k]] = static_cast<std::uint8_t>(low);
      type[list[k]] |= eliminated;
    }
  }
}

// For each arrangement of set neighbours (bit d: neighbour d set), the directions d in which a
// pixel may be reached (from its neighbour opposite d), none where the set neighbours form two
// separate arcs: filling the pixel would join two particles, so it stays a line.
std::array<std::uint8_t, 256> growth_table() {
  std::array<std::uint8_t, 256> table{};
  for (int item = 0; item < 256; ++item) {
    std::array<bool, 8> set{};
    for (int d = 0; d < 8; ++d)
      set[d] = (item >> d) & 1;
    for (int d = 0; d < 8; ++d)
      if (set[(d + 4) % 8]) table[item] |= static_cast<std::uint8_t>(1 << d);
    // A side neighbour connects the two corners next to it.
    std::array<bool, 8> arc = set;
    for (int d = 0; d < 8; d += 2)
      if (set[d]) arc[(d + 1) % 8] = arc[(d + 7) % 8] = true;
    int transitions = 0;
    for (int d = 0; d < 8; ++d)
      transitions += arc[d] != arc[(d + 1) % 8];
    if (transitions >= 4) table[item] = 0;
  }
  return table;
}

// Grows the seeds (255) level by level from the highest, at each level in passes of one
// direction each (diagonals first), a pixel joining when the growth table allows it; what a
// level leaves unreached passes to the next level down only at the background or the image
// edge. Unreached pixels stay below 255: the lines.
void grow_seeds(std::vector<std::uint8_t>& level, const Grid& g) {
  std::vector<std::vector<std::int32_t>> at(256);
  for (std::size_t i = 0; i < level.size(); ++i)
    if (level[i] > 0 && level[i] < 255) at[level[i]].push_back(static_cast<std::int32_t>(i));
  const auto table = growth_table();
  constexpr std::array<int, 8> passes = {7, 3, 1, 5, 0, 4, 2, 6};
  const auto set = [&](int x, int y) {
    return g.inside(x, y) && level[static_cast<std::size_t>(y) * g.width + x] == 255;
  };
  std::vector<std::int32_t> joining;
  for (int v = 254; v >= 1; --v) {
    std::vector<std::int32_t>& waiting = at[v];
    int idle = 0;
    for (int k = 0; !waiting.empty(); ++k) {
      const int pass = passes[k % 8];
      joining.clear();
      std::size_t kept = 0;
      for (const std::int32_t p : waiting) {
        const int x = p % g.width, y = p / g.width;
        int item = 0;
        for (int d = 0; d < 8; ++d)
          item |= set(x + dir_x[d], y + dir_y[d]) ? 1 << d : 0;
        if (table[item] & (1 << pass))
          joining.push_back(p);
        else
          waiting[kept++] = p;
      }
      waiting.resize(kept);
      for (const std::int32_t p : joining)
        level[p] = 255;
      if (!joining.empty()) idle = 0;
      if (idle++ >= 8) break;
    }
    if (waiting.empty() || v == 1) continue;
    int next = v - 1;
    while (next > 1 && at[next].empty())
      --next;
    for (const std::int32_t p : waiting) {
      const int x = p % g.width, y = p / g.width;
      bool border = g.on_edge(x, y);
      for (int d = 0; d < 8 && !border; ++d)
        border = level[static_cast<std::size_t>(y + dir_y[d]) * g.width + x + dir_x[d]] == 0;
      if (border) at[next].push_back(p);
    }
  }
}

}  // namespace

std::vector<float> imagej_distance_map(const std::vector<std::uint8_t>& mask, int width,
                                       int height) {
  std::vector<float> dist2(mask.size(), 0.0f);
  for (std::size_t i = 0; i < mask.size(); ++i)
    if (mask[i]) dist2[i] = std::numeric_limits<float>::max();
  std::vector<std::int32_t> right(width), left(width);
  std::fill(right.begin(), right.end(), -1);
  std::fill(left.begin(), left.end(), -1);
  for (int y = 0; y < height; ++y) {
    sweep_row(mask, dist2, right, width, y, 1);
    sweep_row(mask, dist2, left, width, y, -1);
  }
  std::fill(right.begin(), right.end(), -1);
  std::fill(left.begin(), left.end(), -1);
  for (int y = height - 1; y >= 0; --y) {
    sweep_row(mask, dist2, right, width, y, 1);
    sweep_row(mask, dist2, left, width, y, -1);
  }
  for (float& d : dist2)
    d = std::sqrt(d);
  return dist2;
}

std::vector<std::uint8_t> imagej_watershed(const std::vector<std::uint8_t>& mask, int width,
                                           int height, double tolerance) {
  const Grid g{width, height};
  const std::vector<float> edm = imagej_distance_map(mask, width, height);
  std::vector<float> ridge(edm.size());
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      ridge[static_cast<std::size_t>(y) * width + x] = ridge_height(edm, g, x, y);
  const auto [low, high] = std::minmax_element(edm.begin(), edm.end());
  std::vector<std::uint8_t> type(edm.size(), 0);
  std::vector<std::int32_t> maxima;
  if (*high > *low) maxima = sorted_maxima(edm, ridge, g, *low, *high);
  mark_seeds(edm, ridge, g, maxima, tolerance, type);
  if (maxima.empty()) std::fill(type.begin(), type.end(), processed | seed);
  std::vector<std::uint8_t> level = to_levels(edm, type, *high);
  level_off_minor_maxima(level, type, g, maxima);
  grow_seeds(level, g);
  for (std::uint8_t& v : level)
    v = v == 255 ? 255 : 0;
  return level;
}

}  // namespace shapepress::imaging
