#include "imaging/synth.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "common/error.hpp"
#include "imaging/fourier.hpp"
#include "imaging/measure.hpp"

namespace shapepress::imaging {

void SynthOptions::check() const {
  auto fail = [](std::string_view field, auto value, std::string_view expected) {
    throw InputError(fmt::format("--{}: {} is not valid, expected {}", field, value, expected));
  };
  if (width < 64 || height < 64)
    fail("width/--height", fmt::format("{}x{}", width, height), ">= 64 px");
  if (particles < 1) fail("particles", particles, ">= 1");
  if (!(min_diameter_px >= 4 && max_diameter_px >= min_diameter_px))
    fail("min-diameter/--max-diameter", fmt::format("{}..{}", min_diameter_px, max_diameter_px),
         "4 px <= min <= max");
  if (!(median_diameter_px > 0)) fail("median-diameter", median_diameter_px, "> 0 px");
  if (!(diameter_spread >= 1)) fail("diameter-spread", diameter_spread, ">= 1 (geometric sd)");
  if (!(min_aspect_ratio > 0 && min_aspect_ratio <= max_aspect_ratio && max_aspect_ratio <= 1))
    fail("aspect-ratio", fmt::format("{}..{}", min_aspect_ratio, max_aspect_ratio),
         "0 < min <= max <= 1");
  if (!(D2 >= 0 && D3 >= 0 && D8 >= 0 && D2 + D3 * 6 + D8 * 25 < 0.9))
    fail("D2/--D3/--D8", fmt::format("{}/{}/{}", D2, D3, D8), "small non-negative amplitudes");
  if (!(touching_fraction >= 0 && touching_fraction <= 1))
    fail("touching-fraction", touching_fraction, "a fraction in [0, 1]");
  if (!(noise >= 0 && blur_px >= 0))
    fail("noise/--blur", fmt::format("{}/{}", noise, blur_px), ">= 0");
  if (info_bar_rows < 0 || info_bar_rows > height / 3)
    fail("info-bar", info_bar_rows, "0..height/3 rows");
  if (!(std::abs(foreground - background) > 0.1))
    fail("foreground/--background", fmt::format("{}/{}", foreground, background),
         "a contrast > 0.1");
}

SynthShape parse_synth_shape(const std::string& name) {
  if (name == "disc") return SynthShape::disc;
  if (name == "ellipse") return SynthShape::ellipse;
  if (name == "fourier") return SynthShape::fourier;
  if (name == "mixed") return SynthShape::mixed;
  throw InputError(
      fmt::format("--shape: '{}' is not a shape, expected disc, ellipse, fourier or mixed", name));
}

namespace {

constexpr int table_size = 1440;

// A star-shaped outline: radius at table_size equally spaced angles, unit scale.
struct StarShape {
  std::string kind;
  std::vector<double> radius;
  double max_radius() const { return *std::max_element(radius.begin(), radius.end()); }
  double at(double theta) const {  // linear interpolation, theta in radians (any value)
    double u = theta / (2 * std::numbers::pi) * table_size;
    u -= std::floor(u / table_size) * table_size;
    int i = static_cast<int>(u) % table_size;
    double t = u - std::floor(u);
    return radius[i] * (1 - t) + radius[(i + 1) % table_size] * t;
  }
};

double angle(int k) {
  return 2.0 * std::numbers::pi * k / table_size;
}

StarShape make_shape(SynthShape kind, const SynthOptions& o, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  StarShape s;
  s.radius.resize(table_size);
  if (kind == SynthShape::disc) {
    s.kind = "disc";
    std::fill(s.radius.begin(), s.radius.end(), 1.0);
  } else if (kind == SynthShape::ellipse) {
    s.kind = "ellipse";
    double b = o.min_aspect_ratio + (o.max_aspect_ratio - o.min_aspect_ratio) * uniform(rng);
    for (int k = 0; k < table_size; ++k)
      s.radius[k] = b / std::hypot(b * std::cos(angle(k)), std::sin(angle(k)));
  } else {
    // Mollon & Zhao 2012: D2 given; D3…D8 log-linear in n between D3 and D8; beyond 8 a power
    // law of exponent -decay; random phases.
    s.kind = "fourier";
    std::vector<double> amplitude(fourier_max_order + 1, 0.0), phase(fourier_max_order + 1);
    amplitude[2] = o.D2;
    for (int n = 3; n <= fourier_max_order; ++n) {
      amplitude[n] = n <= 8 ? std::exp(std::log(o.D3) + (std::log(o.D8) - std::log(o.D3)) *
                                                            std::log(n / 3.0) / std::log(8.0 / 3.0))
                            : o.D8 * std::pow(n / 8.0, -o.decay_exponent);
      if (o.D3 <= 0 || o.D8 <= 0) amplitude[n] = 0.0;
    }
    for (double& p : phase)
      p = 2 * std::numbers::pi * uniform(rng);
    for (int k = 0; k < table_size; ++k) {
      double r = 1.0;
      for (int n = 2; n <= fourier_max_order; ++n)
        r += amplitude[n] * std::cos(n * angle(k) + phase[n]);
      s.radius[k] = std::max(r, 0.2);
    }
  }
  return s;
}

double unit_area(const StarShape& s) {  // ½ ∮ r² dθ
  double sum = 0;
  for (double r : s.radius)
    sum += r * r;
  return 0.5 * sum * 2 * std::numbers::pi / table_size;
}

struct Placed {
  StarShape shape;
  Point2 centre;       // origin of the star shape (not its centroid)
  double scale = 1.0;  // px per unit radius
  double rotation = 0.0;
  int partner = 0;
  double bound() const { return shape.max_radius() * scale; }
  double radius_towards(double theta) const { return scale * shape.at(theta - rotation); }
};

bool fits(const Placed& p, const std::vector<Placed>& placed, const SynthOptions& o, int skip) {
  constexpr double gap = 6.0, margin = 3.0;  // px between particles and from the image edge
  const double r = p.bound();
  if (p.centre.x - r < margin || p.centre.y - r < margin || p.centre.x + r > o.width - margin ||
      p.centre.y + r > o.height - o.info_bar_rows - margin)
    return false;
  for (std::size_t i = 0; i < placed.size(); ++i) {
    if (static_cast<int>(i) == skip) continue;
    if (std::hypot(p.centre.x - placed[i].centre.x, p.centre.y - placed[i].centre.y) <
        r + placed[i].bound() + gap)
      return false;
  }
  return true;
}

// Coverage of each pixel by the union of the particles, 4×4 supersampled near outlines.
cv::Mat coverage_map(const std::vector<Placed>& placed, int width, int height) {
  cv::Mat cover = cv::Mat::zeros(height, width, CV_32F);
  constexpr int sub = 4;
  for (const Placed& p : placed) {
    const double bound = p.bound() + 1;
    int x0 = std::max(0, static_cast<int>(p.centre.x - bound)),
        x1 = std::min(width - 1, static_cast<int>(p.centre.x + bound));
    int y0 = std::max(0, static_cast<int>(p.centre.y - bound)),
        y1 = std::min(height - 1, static_cast<int>(p.centre.y + bound));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        double dx = x + 0.5 - p.centre.x, dy = y + 0.5 - p.centre.y;
        double r = std::hypot(dx, dy), edge = p.radius_towards(std::atan2(dy, dx));
        float c = 0.0f;
        if (r < edge - 1.0) {
          c = 1.0f;
        } else if (r < edge + 1.0) {
          int hits = 0;
          for (int j = 0; j < sub; ++j) {
            for (int i = 0; i < sub; ++i) {
              double sx = x + (i + 0.5) / sub - p.centre.x, sy = y + (j + 0.5) / sub - p.centre.y;
              hits += std::hypot(sx, sy) < p.radius_towards(std::atan2(sy, sx));
            }
          }
          c = static_cast<float>(hits) / (sub * sub);
        }
        float& cell = cover.at<float>(y, x);
        cell = std::max(cell, c);  // union of the two members of a touching pair
      }
    }
  }
  return cover;
}

SynthParticle truth_of(const Placed& p, int id) {
  SynthParticle t;
  t.id = id;
  t.kind = p.shape.kind;
  t.rotation_deg = p.rotation * 180.0 / std::numbers::pi;
  for (int k = 0; k < table_size; k += 2) {
    double theta = angle(k);
    double r = p.radius_towards(theta);
    t.outline.push_back({p.centre.x + r * std::cos(theta), p.centre.y + r * std::sin(theta)});
  }
  ParticleMeasurement m = measure_polygon(t.outline);
  t.centre = m.centroid;
  t.area_px = m.area;
  t.equivalent_diameter_px = m.equivalent_diameter;
  t.feret_max_px = m.feret.max;
  t.feret_min_px = m.feret.min;
  t.aspect_ratio = m.aspect_ratio;
  t.D2 = m.fourier[2];
  return t;
}

void draw_info_bar(cv::Mat& image, int rows, std::mt19937_64& rng) {
  if (rows == 0) return;
  cv::Rect bar(0, image.rows - rows, image.cols, rows);
  image(bar).setTo(0.0f);
  // White "text" blocks and a scale bar, as an instrument prints them: digital, noise-free.
  std::uniform_int_distribution<int> width(4, 12);
  int x = rows / 2, y = image.rows - rows + rows / 4, h = std::max(2, rows / 3);
  while (x < image.cols * 0.6) {
    int w = width(rng);
    cv::rectangle(image, cv::Rect(x, y, w, h), 1.0f, cv::FILLED);
    x += w + 6;
  }
  cv::rectangle(image,
                cv::Rect(static_cast<int>(image.cols * 0.7), image.rows - rows / 5, image.cols / 6,
                         std::max(1, rows / 10)),
                1.0f, cv::FILLED);
}

}  // namespace

SynthScene render_synthetic_scene(const SynthOptions& o) {
  o.check();
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::lognormal_distribution<double> size(std::log(o.median_diameter_px),
                                           std::log(o.diameter_spread));
  auto draw_shape = [&](int index) {
    SynthShape kind = o.shape == SynthShape::mixed ? static_cast<SynthShape>(index % 3) : o.shape;
    Placed p{make_shape(kind, o, rng), {}, 1.0, 2 * std::numbers::pi * uniform(rng), 0};
    double d = std::clamp(size(rng), o.min_diameter_px, o.max_diameter_px);
    p.scale = 0.5 * d * std::sqrt(std::numbers::pi / unit_area(p.shape));
    return p;
  };
  std::vector<Placed> placed;
  const int pairs = static_cast<int>(std::lround(o.particles * o.touching_fraction / 2));
  constexpr int attempts = 400;
  for (int index = 0; static_cast<int>(placed.size()) < o.particles && index < o.particles * 3;
       ++index) {
    bool pair = index < pairs && static_cast<int>(placed.size()) + 2 <= o.particles;
    Placed a = draw_shape(index), b = draw_shape(index + 1);
    for (int attempt = 0; attempt < attempts; ++attempt) {
      a.centre = {o.width * uniform(rng), (o.height - o.info_bar_rows) * uniform(rng)};
      if (!fits(a, placed, o, -1)) continue;
      if (!pair) {
        placed.push_back(a);
        break;
      }
      // Touching: outlines meet along the line of centres with 1 px of overlap, so the
      // union has a narrow neck.
      double phi = 2 * std::numbers::pi * uniform(rng);
      double distance = a.radius_towards(phi) + b.radius_towards(phi + std::numbers::pi) - 1.0;
      b.centre = {a.centre.x + distance * std::cos(phi), a.centre.y + distance * std::sin(phi)};
      placed.push_back(a);
      bool b_fits = fits(b, placed, o, static_cast<int>(placed.size()) - 1);
      placed.pop_back();
      if (!b_fits) continue;
      int id_a = static_cast<int>(placed.size()) + 1;
      a.partner = id_a + 1;
      b.partner = id_a;
      placed.push_back(a);
      placed.push_back(b);
      break;
    }
  }

  SynthScene scene;
  for (std::size_t i = 0; i < placed.size(); ++i) {
    scene.particles.push_back(truth_of(placed[i], static_cast<int>(i) + 1));
    scene.particles.back().partner = placed[i].partner;
  }
  cv::Mat cover = coverage_map(placed, o.width, o.height);
  cv::Mat image(o.height, o.width, CV_32F);
  for (int y = 0; y < o.height; ++y) {
    for (int x = 0; x < o.width; ++x) {
      double ramp = o.gradient * ((x + 0.5) / o.width - 0.5 + 0.5 * ((y + 0.5) / o.height - 0.5));
      double c = cover.at<float>(y, x);
      double value = (o.background + ramp) * (1 - c) + (o.foreground + 0.5 * ramp) * c;
      image.at<float>(y, x) = static_cast<float>(o.dark_particles ? 1.0 - value : value);
    }
  }
  if (o.blur_px > 0) cv::GaussianBlur(image, image, cv::Size(), o.blur_px);
  if (o.noise > 0) {
    cv::Mat noise(image.size(), CV_32F);
    std::normal_distribution<float> gauss(0.0f, static_cast<float>(o.noise));
    for (auto it = noise.begin<float>(); it != noise.end<float>(); ++it)
      *it = gauss(rng);
    image += noise;
  }
  draw_info_bar(image, o.info_bar_rows, rng);
  cv::min(cv::max(image, 0.0f), 1.0f, image);
  scene.image = GrayImage(o.width, o.height);
  for (int y = 0; y < o.height; ++y)
    std::copy_n(image.ptr<float>(y), o.width, &scene.image.at(0, y));
  return scene;
}

}  // namespace shapepress::imaging
