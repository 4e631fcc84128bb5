#include "imaging/segment.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "common/error.hpp"
#include "imaging/imagej_watershed.hpp"

namespace shapepress::imaging {

void SegmentOptions::check() const {
  auto fail = [](std::string_view field, auto value, std::string_view expected) {
    throw InputError(fmt::format("--{}: {} is not valid, expected {}", field, value, expected));
  };
  if (denoise_radius_px < 0) fail("denoise-radius", denoise_radius_px, "a radius >= 0 px");
  if (rolling_radius_px < 2) fail("background-radius", rolling_radius_px, "a radius >= 2 px");
  if (!(background_min_fraction >= 0 && background_min_fraction <= 1))
    fail("background-min-fraction", background_min_fraction, "0 <= fraction <= 1");
  if (!(fixed_level > 0 && fixed_level < 1)) fail("threshold-level", fixed_level, "0 < level < 1");
  if (adaptive_block_px < 3 || adaptive_block_px % 2 == 0)
    fail("adaptive-block", adaptive_block_px, "an odd window >= 3 px");
  if (!(split_neck > 0 && split_neck < 1)) fail("split-neck", split_neck, "0 < ratio < 1");
  if (!(cluster_split_neck > 0 && cluster_split_neck < 1))
    fail("cluster-split-neck", cluster_split_neck, "0 < ratio < 1");
  if (!(split_fragment_fraction >= 0 && split_fragment_fraction < 1))
    fail("split-fragment", split_fragment_fraction, "0 <= fraction < 1");
  if (!(relief_solidity >= 0 && relief_solidity <= 1))
    fail("relief-solidity", relief_solidity, "0 <= solidity <= 1");
  if (!(split_prominence_px >= 0))
    fail("split-prominence", split_prominence_px, "a height >= 0 px");
  if (min_area_px < 1) fail("min-area", min_area_px, "an area >= 1 px");
  if (max_area_px != 0 && max_area_px < min_area_px)
    fail("max-area", max_area_px, "0 (no limit) or an area >= --min-area");
}

std::string to_string(ThresholdMethod method) {
  switch (method) {
    case ThresholdMethod::otsu:
      return "otsu";
    case ThresholdMethod::triangle:
      return "triangle";
    case ThresholdMethod::fixed:
      return "fixed";
    case ThresholdMethod::adaptive:
      return "adaptive";
    case ThresholdMethod::isodata:
      return "isodata";
  }
  return "otsu";
}

std::string to_string(Background background) {
  switch (background) {
    case Background::none:
      return "none";
    case Background::quadratic:
      return "quadratic";
    case Background::rolling:
      return "rolling";
  }
  return "none";
}

namespace {

cv::Mat to_mat(const GrayImage& image) {
  return cv::Mat(image.height, image.width, CV_32F, const_cast<float*>(image.pixels.data()))
      .clone();
}

cv::Mat to_8bit(const cv::Mat& image) {
  cv::Mat out;
  cv::normalize(image, out, 0, 255, cv::NORM_MINMAX, CV_8U);
  return out;
}

cv::Mat denoise(const cv::Mat& image, const SegmentOptions& options) {
  cv::Mat out;
  if (options.denoise == Denoise::gaussian && options.denoise_radius_px > 0) {
    cv::GaussianBlur(image, out, cv::Size(), options.denoise_radius_px);
  } else if (options.denoise == Denoise::median && options.denoise_radius_px >= 1) {
    int size = 2 * static_cast<int>(std::lround(options.denoise_radius_px)) + 1;
    cv::medianBlur(image, out, std::min(size, 5));  // float median supports windows up to 5
  } else {
    out = image.clone();
  }
  return out;
}

double median_of_border(const cv::Mat& image8) {
  cv::Mat image;
  image8.convertTo(image, CV_32F);
  std::vector<float> values;
  for (int x = 0; x < image.cols; ++x) {
    values.push_back(image.at<float>(0, x));
    values.push_back(image.at<float>(image.rows - 1, x));
  }
  for (int y = 0; y < image.rows; ++y) {
    values.push_back(image.at<float>(y, 0));
    values.push_back(image.at<float>(y, image.cols - 1));
  }
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

// Least-squares quadratic surface through the samples of `background` (non-zero), taken on a
// 4 px grid; empty when there are too few samples to fit.
std::optional<std::array<double, 6>> fit_quadratic(const cv::Mat& image,
                                                   const cv::Mat& background) {
  constexpr int stride = 4;
  cv::Mat normal = cv::Mat::zeros(6, 6, CV_64F), rhs = cv::Mat::zeros(6, 1, CV_64F);
  const double sx = 2.0 / std::max(1, image.cols - 1), sy = 2.0 / std::max(1, image.rows - 1);
  int samples = 0;
  for (int y = 0; y < image.rows; y += stride) {
    for (int x = 0; x < image.cols; x += stride) {
      if (!background.at<std::uint8_t>(y, x)) continue;
      double u = x * sx - 1, v = y * sy - 1;
      std::array<double, 6> basis{1, u, v, u * u, u * v, v * v};
      for (int i = 0; i < 6; ++i) {
        rhs.at<double>(i) += basis[i] * image.at<float>(y, x);
        for (int j = 0; j < 6; ++j)
          normal.at<double>(i, j) += basis[i] * basis[j];
      }
      ++samples;
    }
  }
  if (samples < 50) return std::nullopt;  // almost no background: nothing to fit
  cv::Mat c;
  if (!cv::solve(normal, rhs, c, cv::DECOMP_CHOLESKY)) return std::nullopt;
  std::array<double, 6> coefficients{};
  for (int i = 0; i < 6; ++i)
    coefficients[i] = c.at<double>(i);
  return coefficients;
}

cv::Mat quadratic_surface(const std::array<double, 6>& c, cv::Size size) {
  cv::Mat surface(size, CV_32F);
  const double sx = 2.0 / std::max(1, size.width - 1), sy = 2.0 / std::max(1, size.height - 1);
  for (int y = 0; y < size.height; ++y) {
    double v = y * sy - 1;
    for (int x = 0; x < size.width; ++x) {
      double u = x * sx - 1;
      surface.at<float>(y, x) = static_cast<float>(c[0] + c[1] * u + c[2] * v + c[3] * u * u +
                                                   c[4] * u * v + c[5] * v * v);
    }
  }
  return surface;
}

// Pixels that Otsu's split of `image` leaves out of the particles, with a 2 px margin.
cv::Mat otsu_background(const cv::Mat& image) {
  cv::Mat particle;
  cv::threshold(to_8bit(image), particle, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  cv::dilate(particle, particle, cv::Mat(), cv::Point(-1, -1), 2);
  return particle == 0;
}

// The scan background (uneven SEM illumination, detector shading, a lamp's fall-off) is fitted
// with a quadratic surface and removed. Its pixels are where Otsu's split says "not particle";
// under uneven light that split also calls the particles in the dark part of the image
// background, and a surface fitted through them rises under them and cuts them into pieces
// (a dark coin on scikit-image's coins). So the split is redone on the flattened image and the
// surface refitted until the background pixels stop changing (at most 4 rounds).
// In a dense field (background pixels below `min_fraction` of the image) there is no background
// to model: the dark pixels are the gaps and shadows between touching particles, whose level
// follows the particles around them, and each refit moves them: on scikit-image's gravel (11 %
// of the pixels) the surface grew from 0.14 to 0.36 of the range in four rounds, against a
// contrast of 0.23 between stones and gaps, and lifted the level over the darker stones in two
// corners. Such an image is left as it is.
struct Flattened {
  cv::Mat image;
  bool fitted = false;
  double background_fraction = 0.0;  // of Otsu's background pixels in the image as given
};

Flattened subtract_quadratic_background(const cv::Mat& image, double min_fraction) {
  cv::Mat background = otsu_background(image), flat = image.clone();
  const double fraction =
      cv::countNonZero(background) / static_cast<double>(std::max<std::size_t>(image.total(), 1));
  if (fraction < min_fraction) return {flat, false, fraction};
  for (int round = 0; round < 4; ++round) {
    auto c = fit_quadratic(image, background);
    if (!c) break;
    flat = image - quadratic_surface(*c, image.size());
    cv::Mat next = otsu_background(flat);
    const bool settled = cv::countNonZero(next != background) == 0;
    background = next;
    if (settled) break;
  }
  return {flat, true, fraction};
}

// Rolling background: a grey opening (erosion then dilation) removes everything narrower than
// the structuring disc; done on a reduced image so that large radii stay cheap.
cv::Mat subtract_rolling_background(const cv::Mat& image, double radius_px) {
  const double shrink = std::max(1.0, radius_px / 10.0);
  cv::Mat small, opened, background;
  cv::resize(image, small, cv::Size(), 1.0 / shrink, 1.0 / shrink, cv::INTER_AREA);
  int r = std::max(1, static_cast<int>(std::lround(radius_px / shrink)));
  cv::Mat disc = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1));
  cv::morphologyEx(small, opened, cv::MORPH_OPEN, disc);
  cv::resize(opened, background, image.size(), 0, 0, cv::INTER_LINEAR);
  cv::GaussianBlur(background, background, cv::Size(), shrink);
  return image - background;
}

void fill_holes(cv::Mat& mask) {
  cv::Mat padded;
  cv::copyMakeBorder(mask, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, 0);
  cv::floodFill(padded, cv::Point(0, 0), 128);
  cv::Mat outside = padded(cv::Rect(1, 1, mask.cols, mask.rows)) == 128;
  mask = ~outside;
}

struct UnionFind {
  std::vector<std::int32_t> parent;
  std::int32_t root(std::int32_t i) {
    while (parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  }
};

// A piece that the split cuts off is joined back to the neighbour it shares the longest border
// with when its area is below `fraction` of the median piece (pieces of at least min_area_px).
// Distance-map maxima also stand in a large particle's bumps and in the concavities that its
// dark relief leaves on the outline; the split then shaves slivers off it (21–192 px off
// 1000–2600 px coins) that are no particles. A real particle touching another is rarely a
// tenth of the median, and one standing alone is never joined. Smallest pieces go first; rounds
// repeat until none is left to join.
void join_fragments(UnionFind& sets, const std::vector<std::uint8_t>& mask, int width, int height,
                    double fraction, int min_area_px) {
  const auto n = static_cast<std::size_t>(width) * height;
  std::vector<int> area(n, 0);
  for (int round = 0; round < 8; ++round) {
    std::fill(area.begin(), area.end(), 0);
    for (std::size_t i = 0; i < n; ++i)
      if (mask[i]) ++area[sets.root(static_cast<std::int32_t>(i))];
    std::vector<int> pieces;
    for (std::size_t i = 0; i < n; ++i)
      if (area[i] >= min_area_px) pieces.push_back(area[i]);
    if (pieces.empty()) return;
    std::nth_element(pieces.begin(), pieces.begin() + pieces.size() / 2, pieces.end());
    const double limit = fraction * pieces[pieces.size() / 2];
    // Border length (4-neighbour pixel pairs) of every small piece with each neighbour.
    std::map<std::pair<std::int32_t, std::int32_t>, int> border;
    auto count = [&](std::int32_t a, std::int32_t b) {
      if (a != b && area[a] < limit) ++border[{a, b}];
    };
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const std::int32_t p = y * width + x;
        if (!mask[p]) continue;
        const std::int32_t rp = sets.root(p);
        if (x + 1 < width && mask[p + 1]) {
          const std::int32_t rq = sets.root(p + 1);
          count(rp, rq);
          count(rq, rp);
        }
        if (y + 1 < height && mask[p + width]) {
          const std::int32_t rq = sets.root(p + width);
          count(rp, rq);
          count(rq, rp);
        }
      }
    }
    std::map<std::int32_t, std::pair<int, std::int32_t>> longest;  // piece -> (border, neighbour)
    for (const auto& [pair, length] : border) {
      auto& best = longest[pair.first];
      if (length > best.first) best = {length, pair.second};
    }
    std::vector<std::int32_t> fragments;
    for (const auto& entry : longest)
      fragments.push_back(entry.first);
    std::sort(fragments.begin(), fragments.end(),
              [&](auto a, auto b) { return area[a] < area[b] || (area[a] == area[b] && a < b); });
    std::vector<char> touched(n, 0);
    bool joined = false;
    for (std::int32_t f : fragments) {
      const std::int32_t target = longest[f].second;
      if (touched[f] || touched[target]) continue;  // areas changed: next round
      sets.parent[f] = target;
      touched[f] = touched[target] = 1;
      joined = true;
    }
    if (!joined) return;
  }
}

}  // namespace

LabelImage split_touching_particles(const std::vector<std::uint8_t>& mask, int width, int height,
                                    double split_neck) {
  SegmentOptions options;
  options.split_rule = SplitRule::neck;
  options.split_lines = false;
  options.split_neck = split_neck;
  return split_touching_particles(mask, width, height, options);
}

namespace {

cv::Mat distance_map(const std::vector<std::uint8_t>& mask, int width, int height) {
  cv::Mat m(height, width, CV_8U, const_cast<std::uint8_t*>(mask.data()));
  cv::Mat binary = m != 0, dist;
  cv::distanceTransform(binary, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return dist;
}

// Labels of the basins of the mask's distance map (split rule, fragments joined), no line
// between them yet.
LabelImage flood_distance_map(const std::vector<std::uint8_t>& mask, int width, int height,
                              const SegmentOptions& options,
                              const std::vector<std::uint8_t>* narrow_only = nullptr) {
  cv::Mat m(height, width, CV_8U, const_cast<std::uint8_t*>(mask.data()));
  cv::Mat binary = m != 0, dist;
  cv::distanceTransform(binary, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const auto n = static_cast<std::size_t>(width) * height;
  const float* d = dist.ptr<float>(0);
  std::vector<std::int32_t> order;
  for (std::size_t i = 0; i < n; ++i)
    if (mask[i]) order.push_back(static_cast<std::int32_t>(i));
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return d[a] > d[b]; });

  // Flooding the inverted distance map from its maxima: a pixel joins the basin of its highest
  // processed neighbour (steepest ascent); two basins meeting at a saddle merge when the neck
  // there is wide compared with the smaller basin's inscribed radius, or within a pixel of it
  // (digital noise on the distance map). The prominence rule merges them when the smaller
  // peak stands no more than split_prominence_px above the saddle: ImageJ's maxima finder
  // with its tolerance, which keeps each ultimate eroded point that stands out by more.
  constexpr double noise_px = 1.0;
  const bool by_prominence = options.split_rule == SplitRule::prominence;
  UnionFind sets{std::vector<std::int32_t>(n, -1)};
  std::vector<float> peak(n, 0.0f);
  std::array<std::int32_t, 8> roots{};
  for (std::int32_t p : order) {
    const int x = p % width, y = p / width;
    int found = 0;
    std::int32_t uphill = -1;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        int nx = x + dx, ny = y + dy;
        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
        std::int32_t q = ny * width + nx;
        if (sets.parent[q] < 0) continue;
        if (uphill < 0 || d[q] > d[uphill]) uphill = q;
        std::int32_t r = sets.root(q);
        if (std::find(roots.begin(), roots.begin() + found, r) == roots.begin() + found)
          roots[found++] = r;
      }
    }
    if (found == 0) {
      sets.parent[p] = p;
      peak[p] = d[p];
      continue;
    }
    std::int32_t deepest = roots[0];
    for (int k = 1; k < found; ++k) {
      std::int32_t r = roots[k];
      if (peak[r] > peak[deepest] || (peak[r] == peak[deepest] && r < deepest)) deepest = r;
    }
    for (int k = 0; k < found; ++k) {
      std::int32_t other = roots[k];
      if (other == deepest) continue;
      double smaller = peak[other];
      const bool wide = d[p] >= options.split_neck * smaller || smaller - d[p] < noise_px;
      bool merge = by_prominence ? smaller - d[p] <= options.split_prominence_px : wide;
      if (narrow_only && (*narrow_only)[p]) merge = merge || wide;
      if (merge) sets.parent[other] = deepest;
    }
    sets.parent[p] = sets.root(uphill);
  }

  if (options.split_fragment_fraction > 0)
    join_fragments(sets, mask, width, height, options.split_fragment_fraction, options.min_area_px);

  LabelImage labels{width, height, 0, std::vector<std::int32_t>(n, 0)};
  std::vector<std::int32_t> label_of_root(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!mask[i]) continue;
    std::int32_t r = sets.root(static_cast<std::int32_t>(i));
    if (label_of_root[r] == 0) label_of_root[r] = ++labels.count;
    labels.labels[i] = label_of_root[r];
  }
  return labels;
}

// Of every two 8-neighbours with different labels, the one nearer the background (lower
// distance; on a tie, the later in raster order) is cleared: afterwards no two particles
// touch even diagonally, as after ImageJ's watershed lines, and the line is about one pixel
// wide. The pieces are then counted as 8-connected blobs, as ImageJ counts them.
LabelImage separate_by_lines(const LabelImage& labels, const std::vector<std::uint8_t>& mask) {
  const int width = labels.width, height = labels.height;
  const cv::Mat dist = distance_map(mask, width, height);
  const float* d = dist.ptr<float>(0);
  std::vector<std::uint8_t> kept(mask.begin(), mask.end());
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::int32_t p = y * width + x, lp = labels.labels[p];
      if (lp == 0) continue;
      for (int dy = -1; dy <= 1 && kept[p]; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
          const std::int32_t q = ny * width + nx, lq = labels.labels[q];
          if (lq == 0 || lq == lp) continue;
          if (d[p] < d[q] || (d[p] == d[q] && p > q)) {
            kept[p] = 0;
            break;
          }
        }
      }
    }
  }
  cv::Mat lab, kept_mat(height, width, CV_8U, kept.data());
  LabelImage separated{width, height, 0, {}};
  separated.count = cv::connectedComponents(kept_mat, lab, 8, CV_32S) - 1;
  separated.labels.assign(lab.ptr<std::int32_t>(0), lab.ptr<std::int32_t>(0) + lab.total());
  return separated;
}

// Labels grown from the pieces of `core` over the rest of `mask` (core ⊆ mask), one 8-neighbour
// ring per round, so each pixel takes the label of the nearest piece along the mask; blobs of
// the mask without core get labels of their own.
LabelImage grow_labels(LabelImage labels, const std::vector<std::uint8_t>& mask) {
  const int width = labels.width, height = labels.height;
  std::vector<std::int32_t>& l = labels.labels;
  std::vector<std::int32_t> front;
  for (std::size_t i = 0; i < l.size(); ++i)
    if (l[i] != 0) front.push_back(static_cast<std::int32_t>(i));
  while (!front.empty()) {
    std::vector<std::pair<std::int32_t, std::int32_t>> claimed;  // pixel, label
    for (std::int32_t p : front) {
      const int x = p % width, y = p / width;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
          const std::int32_t q = ny * width + nx;
          if (mask[q] && l[q] == 0) claimed.emplace_back(q, l[p]);
        }
      }
    }
    front.clear();
    for (const auto& [q, label] : claimed) {
      if (l[q] != 0) continue;  // claimed twice this round: the first piece keeps it
      l[q] = label;
      front.push_back(q);
    }
  }
  std::vector<std::uint8_t> rest(mask.size(), 0);
  for (std::size_t i = 0; i < l.size(); ++i)
    rest[i] = mask[i] && l[i] == 0 ? 255 : 0;
  cv::Mat lab, rest_mat(height, width, CV_8U, rest.data());
  const int extra = cv::connectedComponents(rest_mat, lab, 8, CV_32S) - 1;
  for (std::size_t i = 0; i < l.size(); ++i)
    if (const std::int32_t r = lab.ptr<std::int32_t>(0)[i]; r > 0) l[i] = labels.count + r;
  labels.count += extra;
  return labels;
}

}  // namespace

LabelImage split_touching_particles(const std::vector<std::uint8_t>& mask, int width, int height,
                                    const SegmentOptions& options,
                                    const std::vector<std::uint8_t>& gaps_open,
                                    const std::vector<std::uint8_t>& narrow_only) {
  std::vector<std::uint8_t> core(mask.size());
  for (std::size_t i = 0; i < mask.size(); ++i)
    core[i] = mask[i] && gaps_open[i] ? 255 : 0;
  LabelImage labels =
      grow_labels(flood_distance_map(core, width, height, options, &narrow_only), mask);
  return options.split_lines ? separate_by_lines(labels, mask) : labels;
}

LabelImage split_touching_particles(const std::vector<std::uint8_t>& mask, int width, int height,
                                    const SegmentOptions& options) {
  LabelImage labels = flood_distance_map(mask, width, height, options);
  return options.split_lines ? separate_by_lines(labels, mask) : labels;
}

int imagej_default_threshold(std::array<long, 256> data) {
  // As ImageJ 1.53's AutoThresholder "Default" (ij.process.ImageProcessor's IJ_IsoData):
  // the extreme bins are ignored (saturated or erased areas), then the level moves up from
  // the lowest occupied bin until it passes the mean of the two classes' means.
  data[0] = 0;
  data[255] = 0;
  int min = 0, max = 255;
  while (data[min] == 0 && min < 255)
    ++min;
  while (data[max] == 0 && max > 0)
    --max;
  if (min >= max) return 128;
  int moving = min;
  double result = 0.0;
  do {
    double sum1 = 0, sum2 = 0, sum3 = 0, sum4 = 0;
    for (int i = min; i <= moving; ++i) {
      sum1 += static_cast<double>(i) * data[i];
      sum2 += static_cast<double>(data[i]);
    }
    for (int i = moving + 1; i <= max; ++i) {
      sum3 += static_cast<double>(i) * data[i];
      sum4 += static_cast<double>(data[i]);
    }
    result = (sum1 / sum2 + sum3 / sum4) / 2.0;
    ++moving;
  } while ((moving + 1) <= result && moving < max - 1);
  return static_cast<int>(std::lround(result));
}

namespace {

LabelImage connected_particles(const cv::Mat& mask) {
  cv::Mat lab;
  int count = cv::connectedComponents(mask, lab, 8, CV_32S);
  LabelImage labels{mask.cols, mask.rows, count - 1, {}};
  labels.labels.assign(lab.ptr<std::int32_t>(0), lab.ptr<std::int32_t>(0) + lab.total());
  return labels;
}

// Each particle's holes filled with its label, in raster order of the particles' first pixels
// (ImageJ's scan order): a particle lying in another's hole becomes part of it, as with
// ImageJ's "include holes", which fills the traced outline. Labels left unused are dropped.
void fill_holes_per_particle(LabelImage& labels) {
  const int n = labels.count;
  std::vector<int> x0(n + 1, labels.width), y0(n + 1, labels.height), x1(n + 1, -1), y1(n + 1, -1);
  for (int y = 0; y < labels.height; ++y) {
    for (int x = 0; x < labels.width; ++x) {
      const int l = labels.at(x, y);
      if (l == 0) continue;
      x0[l] = std::min(x0[l], x);
      y0[l] = std::min(y0[l], y);
      x1[l] = std::max(x1[l], x);
      y1[l] = std::max(y1[l], y);
    }
  }
  std::vector<char> alive(n + 1, 0);
  for (int l = 1; l <= n; ++l)
    alive[l] = x1[l] >= 0;
  for (int l = 1; l <= n; ++l) {
    if (!alive[l]) continue;
    const cv::Rect box(x0[l], y0[l], x1[l] - x0[l] + 1, y1[l] - y0[l] + 1);
    cv::Mat piece(box.size(), CV_8U);
    for (int y = 0; y < box.height; ++y)
      for (int x = 0; x < box.width; ++x)
        piece.at<std::uint8_t>(y, x) = labels.at(box.x + x, box.y + y) == l ? 255 : 0;
    fill_holes(piece);
    for (int y = 0; y < box.height; ++y) {
      for (int x = 0; x < box.width; ++x) {
        if (!piece.at<std::uint8_t>(y, x)) continue;
        auto& v = labels.labels[static_cast<std::size_t>(box.y + y) * labels.width + box.x + x];
        if (v != l && v != 0) alive[v] = 0;  // swallowed (ImageJ erases it with the fill)
        v = l;
      }
    }
  }
  std::vector<std::int32_t> renumber(n + 1, 0);
  int kept = 0;
  for (int l = 1; l <= n; ++l)
    if (alive[l]) renumber[l] = ++kept;
  for (auto& v : labels.labels)
    v = renumber[v];
  labels.count = kept;
}

// Fills the holes of each 8-connected blob whose filled area is at least `solidity` of its
// convex hull's; holes of more concave blobs are kept. A hole inside a convex outline is the
// particle's own relief (a coin's dark design, an SEM particle's shadowed pit). A concave blob
// is touching particles, and a hole in it is mostly a gap that they close around: filling it
// would join them across it, leaving the split no saddle there (scikit-image's gravel: 99
// particles with every hole filled, 224 in ImageJ's watershed, which splits before it fills).
// Returns the pixels of the blobs so filled.
cv::Mat fill_holes_of_convex_blobs(cv::Mat& mask, double solidity) {
  cv::Mat filled = mask.clone();
  fill_holes(filled);
  cv::Mat lab;
  const int count = cv::connectedComponents(filled, lab, 8, CV_32S);
  std::vector<std::vector<cv::Point>> points(count);
  for (int y = 0; y < lab.rows; ++y)
    for (int x = 0; x < lab.cols; ++x)
      if (const int l = lab.at<std::int32_t>(y, x); l > 0) points[l].emplace_back(x, y);
  std::vector<char> convex(count, 0);
  for (int l = 1; l < count; ++l) {
    // Hull of the pixel squares' corners, so that a blob of one pixel has a hull of area 1.
    std::vector<cv::Point> corners;
    corners.reserve(4 * points[l].size());
    for (const cv::Point& p : points[l]) {
      corners.emplace_back(p.x, p.y);
      corners.emplace_back(p.x + 1, p.y);
      corners.emplace_back(p.x, p.y + 1);
      corners.emplace_back(p.x + 1, p.y + 1);
    }
    std::vector<cv::Point> hull;
    cv::convexHull(corners, hull);
    convex[l] = static_cast<double>(points[l].size()) >= solidity * cv::contourArea(hull);
  }
  cv::Mat convex_blobs = cv::Mat::zeros(mask.size(), CV_8U);
  for (int y = 0; y < lab.rows; ++y) {
    for (int x = 0; x < lab.cols; ++x) {
      if (!convex[lab.at<std::int32_t>(y, x)]) continue;
      mask.at<std::uint8_t>(y, x) = 255;
      convex_blobs.at<std::uint8_t>(y, x) = 255;
    }
  }
  return convex_blobs;
}

// The blobs of `convex_blobs` (8-connected, labelled from 1) and which of them had holes in
// `thresholded`, the mask before its holes were filled.
struct HoledBlobs {
  cv::Mat blob;             // CV_32S blob label per pixel, 0 outside
  std::vector<char> holed;  // per blob label
};

HoledBlobs convex_blobs_with_holes(const cv::Mat& convex_blobs, const cv::Mat& thresholded) {
  HoledBlobs result;
  const int count = cv::connectedComponents(convex_blobs, result.blob, 8, CV_32S);
  result.holed.assign(count, 0);
  for (int y = 0; y < result.blob.rows; ++y)
    for (int x = 0; x < result.blob.cols; ++x)
      if (const int l = result.blob.at<std::int32_t>(y, x);
          l > 0 && !thresholded.at<std::uint8_t>(y, x))
        result.holed[l] = 1;
  return result;
}

// A convex blob with holes is either one particle with its relief (a coin's design) or a compact
// cluster of touching particles around the pores between them (OpenCV's water_coins: 24 coins
// whose filled outline is convex). Filling the holes first, as for relief, leaves the cluster no
// saddle. So such a blob is also split with its holes open, keeping two maxima apart only where
// they stand out (prominence) and the neck between them is narrow (cluster_split_neck, 0.6, of
// the smaller inscribed radius; relief makes maxima behind wide necks). An enclosed pore needs
// at least three particles around it: when this split gives three pieces or more, they replace
// the blob's labels; the pores stay out of the pieces. From 0.45 to 0.7 the counts on the five
// real images of tests/data/imaging are the same; at 0.4 water_coins' cluster stays whole, at
// 0.75 one of scikit-image's coins is cut up.
void split_pores_of_clusters(LabelImage& labels, std::vector<std::uint8_t> bits,
                             const cv::Mat& thresholded, const cv::Mat& convex_blobs,
                             std::vector<std::uint8_t> gaps_open, SegmentOptions options) {
  const HoledBlobs blobs = convex_blobs_with_holes(convex_blobs, thresholded);
  std::vector<std::uint8_t> holed(bits.size(), 0);
  bool any = false;
  for (std::size_t i = 0; i < bits.size(); ++i) {
    const int b = blobs.blob.ptr<std::int32_t>(0)[i];
    if (b == 0 || !blobs.holed[b]) continue;
    holed[i] = 1;
    any = true;
    bits[i] = gaps_open[i] = thresholded.ptr<std::uint8_t>(0)[i];
  }
  if (!any) return;
  options.split_neck = options.cluster_split_neck;
  const LabelImage open =
      split_touching_particles(bits, labels.width, labels.height, options, gaps_open, holed);
  std::vector<std::vector<std::int32_t>> pieces(blobs.holed.size());
  for (std::size_t i = 0; i < bits.size(); ++i) {
    const int b = blobs.blob.ptr<std::int32_t>(0)[i];
    if (holed[i] && open.labels[i] != 0 &&
        std::find(pieces[b].begin(), pieces[b].end(), open.labels[i]) == pieces[b].end())
      pieces[b].push_back(open.labels[i]);
  }
  const std::int32_t offset = labels.count;
  for (std::size_t i = 0; i < bits.size(); ++i) {
    const int b = blobs.blob.ptr<std::int32_t>(0)[i];
    if (holed[i] && pieces[b].size() >= 3)
      labels.labels[i] = open.labels[i] == 0 ? 0 : offset + open.labels[i];
  }
  labels.count += open.count;
}

// Drops particles on the image edge and outside the size range; renumbers the rest 1..n.
void filter_particles(Segmentation& result, const SegmentOptions& options) {
  LabelImage& labels = result.labels;
  std::vector<int> area(labels.count + 1, 0);
  std::vector<char> on_edge(labels.count + 1, 0);
  for (int y = 0; y < labels.height; ++y) {
    for (int x = 0; x < labels.width; ++x) {
      int l = labels.at(x, y);
      if (l == 0) continue;
      ++area[l];
      if (x == 0 || y == 0 || x == labels.width - 1 || y == labels.height - 1) on_edge[l] = 1;
    }
  }
  std::vector<std::int32_t> renumber(labels.count + 1, 0);
  int kept = 0;
  for (int l = 1; l <= labels.count; ++l) {
    if (options.exclude_edges && on_edge[l]) {
      ++result.excluded_on_edge;
    } else if (area[l] < options.min_area_px ||
               (options.max_area_px > 0 && area[l] > options.max_area_px)) {
      ++result.excluded_by_size;
    } else {
      renumber[l] = ++kept;
    }
  }
  for (auto& l : labels.labels)
    l = renumber[l];
  labels.count = kept;
}

// Whether the particles are the bright side of the level: as options say, or (automatic) when
// the image's border, mostly background, lies at or below Otsu's level.
bool bright_particles(const cv::Mat& smooth, const SegmentOptions& options) {
  cv::Mat smooth8 = to_8bit(smooth), ignored;
  double otsu = cv::threshold(smooth8, ignored, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  return options.polarity == Polarity::automatic
             ? median_of_border(smooth8) <= otsu  // THRESH_BINARY keeps values > otsu
             : options.polarity == Polarity::bright;
}

// The image with its background removed as options say (the image itself without); result
// states the background that was fitted.
cv::Mat flatten_background(const cv::Mat& smooth, const SegmentOptions& options,
                           Segmentation& result) {
  if (options.background == Background::quadratic) {
    Flattened flattened = subtract_quadratic_background(smooth, options.background_min_fraction);
    result.background = flattened.fitted ? Background::quadratic : Background::none;
    result.background_fraction = flattened.background_fraction;
    return flattened.image;
  }
  if (options.background == Background::rolling) {
    result.background = Background::rolling;
    return subtract_rolling_background(smooth, options.rolling_radius_px);
  }
  return smooth;
}

// The particle pixels of the flattened image by options.threshold (255 inside). result.threshold
// becomes the level on the flattened image scaled to [0, 1], with that image in
// result.flattened, or -1 when no single level separates the particles.
cv::Mat threshold_particles(const cv::Mat& flat, const cv::Mat& smooth,
                            const SegmentOptions& options, Segmentation& result) {
  cv::Mat flat8 = to_8bit(flat), mask, unit;
  cv::normalize(flat, unit, 0.0, 1.0, cv::NORM_MINMAX, CV_32F);
  switch (options.threshold) {
    case ThresholdMethod::otsu: {
      // Otsu's split decides which pixels are particle; the level is then set half-way
      // between the two classes' mean intensities, where a blurred step edge truly lies (a
      // level off the mid-contrast moves every outline in or out and biases sizes).
      double split = cv::threshold(flat8, mask, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
      double particle_mean = cv::mean(unit, mask)[0];
      double background_mean = cv::mean(unit, flat8 <= split)[0];
      double level = 0.5 * (particle_mean + background_mean);
      mask = unit > level;
      result.threshold = level * 255.0 - 0.5;  // as an 8-bit level, converted back below
      break;
    }
    case ThresholdMethod::triangle:
      result.threshold =
          cv::threshold(flat8, mask, 0, 255, cv::THRESH_BINARY | cv::THRESH_TRIANGLE);
      break;
    case ThresholdMethod::fixed:
      result.threshold =
          cv::threshold(flat8, mask, options.fixed_level * 255.0, 255, cv::THRESH_BINARY);
      break;
    case ThresholdMethod::isodata: {
      // Without background flattening, the histogram is the image's own 256 levels (the input
      // holds them / 255, see imagej_8bit_levels) in the file's orientation, and the side is
      // chosen as ImageJ's "Dark background" box does: bright particles above the level, dark
      // ones at or below it. Flattened images are thresholded on their 8-bit rescaling.
      const bool own_levels = options.background == Background::none;
      cv::Mat levels;
      if (own_levels) {
        cv::Mat original = result.bright_particles ? smooth : 1.0 - smooth;
        original.convertTo(levels, CV_8U, 255.0);  // rounds to the nearest level
      } else {
        levels = flat8;
      }
      std::array<long, 256> histogram{};
      for (int y = 0; y < levels.rows; ++y)
        for (int x = 0; x < levels.cols; ++x)
          ++histogram[levels.at<std::uint8_t>(y, x)];
      const int t = imagej_default_threshold(histogram);
      mask = own_levels && !result.bright_particles ? levels <= t : levels > t;
      // No single level of the rescaled image matches in general: outlines at pixel edges.
      result.threshold = -1.0;
      break;
    }
    case ThresholdMethod::adaptive:
      cv::adaptiveThreshold(flat8, mask, 255, cv::ADAPTIVE_THRESH_GAUSSIAN_C, cv::THRESH_BINARY,
                            options.adaptive_block_px, -options.adaptive_offset * 255.0);
      result.threshold = -1.0;
      break;
  }
  if (result.threshold >= 0) {
    // 8-bit values above t are inside: the continuous level lies between t and t + 1.
    result.threshold = (result.threshold + 0.5) / 255.0;
    result.flattened = GrayImage(unit.cols, unit.rows);
    for (int y = 0; y < unit.rows; ++y)
      std::copy_n(unit.ptr<float>(y), unit.cols, &result.flattened.at(0, y));
  }
  return mask;
}

// The same background and level applied to the image before smoothing: pixels that are
// particle there. The smoothing lifts a gap of one or two pixels between touching particles
// above the level; before it, the gap is below. Only in concave blobs (touching particles): in
// a convex one, the dark pixels of the unsmoothed image are the particle's relief (a coin's
// design), not gaps.
std::vector<std::uint8_t> open_before_smoothing(const GrayImage& image, const cv::Mat& smooth,
                                                const cv::Mat& flat, const cv::Mat& convex_blobs,
                                                const Segmentation& result) {
  cv::Mat raw = to_mat(image);
  if (!result.bright_particles) raw = 1.0 - raw;
  double low = 0, high = 1;
  cv::minMaxLoc(flat, &low, &high);
  cv::Mat raw_unit = (raw - (smooth - flat) - low) / std::max(high - low, 1e-12);
  cv::Mat open = (raw_unit > result.threshold) | convex_blobs;
  return std::vector<std::uint8_t>(open.ptr<std::uint8_t>(0),
                                   open.ptr<std::uint8_t>(0) + open.total());
}

// One label per particle of the mask: split where particles touch when options say, holes
// filled before or after the split.
LabelImage label_particles(cv::Mat mask, const GrayImage& image, const cv::Mat& smooth,
                           const cv::Mat& flat, const SegmentOptions& options,
                           const Segmentation& result) {
  // ImageJ's order for its watershed: split the mask as thresholded, then fill each piece's
  // holes ("include holes" of Analyze Particles). Otherwise a blob's holes are filled first
  // when the blob is convex (a bright coin's dark relief makes no distance-map maxima to split
  // at), and left to the split when it is not (the gaps that touching stones close around).
  const bool imagej_order = options.split_touching && options.fill_holes_after_split;
  const bool by_convexity = options.split_touching && options.fill_holes && !imagej_order;
  const cv::Mat thresholded = mask.clone();
  cv::Mat convex_blobs = cv::Mat::zeros(mask.size(), CV_8U);
  if (by_convexity) {
    convex_blobs = fill_holes_of_convex_blobs(mask, options.relief_solidity);
  } else if (options.fill_holes && !imagej_order) {
    fill_holes(mask);
  }
  if (!options.split_touching) return connected_particles(mask);

  std::vector<std::uint8_t> bits(mask.ptr<std::uint8_t>(0),
                                 mask.ptr<std::uint8_t>(0) + mask.total());
  const bool unsmoothed_gaps = options.split_gaps_unsmoothed && options.denoise != Denoise::none &&
                               result.threshold >= 0 && !imagej_order;
  LabelImage labels;
  if (unsmoothed_gaps) {
    const std::vector<std::uint8_t> gaps_open =
        open_before_smoothing(image, smooth, flat, convex_blobs, result);
    const std::vector<std::uint8_t> none(bits.size(), 0);
    labels = split_touching_particles(bits, mask.cols, mask.rows, options, gaps_open, none);
    split_pores_of_clusters(labels, bits, thresholded, convex_blobs, gaps_open, options);
  } else if (imagej_order) {
    // ImageJ's own watershed, not the prominence flood: that flood cuts elsewhere and clears
    // a line on either side of a border, and on gravel its pieces differ from ImageJ's in
    // 5 % of the particle pixels (docs/imaging.md, "Dense fields").
    std::vector<std::uint8_t> kept =
        imagej_watershed(bits, mask.cols, mask.rows, options.split_prominence_px);
    labels = connected_particles(cv::Mat(mask.rows, mask.cols, CV_8U, kept.data()));
  } else {
    labels = split_touching_particles(bits, mask.cols, mask.rows, options);
  }
  if (options.fill_holes && (imagej_order || by_convexity)) fill_holes_per_particle(labels);
  return labels;
}

}  // namespace

Segmentation segment_particles(const GrayImage& image, const SegmentOptions& options) {
  options.check();
  Segmentation result;
  cv::Mat smooth = denoise(to_mat(image), options);
  result.bright_particles = bright_particles(smooth, options);
  if (!result.bright_particles) smooth = 1.0 - smooth;  // particles are bright from here on
  const cv::Mat flat = flatten_background(smooth, options, result);
  cv::Mat mask = threshold_particles(flat, smooth, options, result);
  result.labels = label_particles(mask, image, smooth, flat, options, result);
  filter_particles(result, options);
  return result;
}

}  // namespace shapepress::imaging
