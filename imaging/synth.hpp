#pragma once
// Synthetic SEM-like images of particles whose shapes are known exactly: discs, ellipses and
// Fourier outlines (Mollon & Zhao spectra with random phases), log-normal sizes, random
// orientation, some particles in touching pairs, background gradient, blur, noise and an
// information bar. Every particle's true measurements come with the image.
#include <cstdint>
#include <string>
#include <vector>

#include "imaging/image.hpp"

namespace shapepress::imaging {

enum class SynthShape { disc, ellipse, fourier, mixed };

struct SynthOptions {
  int width = 1024;
  int height = 768;
  int particles = 60;  // target count (fewer if the image is too full)
  SynthShape shape = SynthShape::mixed;
  double median_diameter_px = 50.0;  // equivalent diameter, log-normal
  double diameter_spread = 1.3;      // geometric standard deviation
  double min_diameter_px = 30.0;
  double max_diameter_px = 120.0;
  double min_aspect_ratio = 0.45;  // ellipses: b/a uniform in [min, max]
  double max_aspect_ratio = 0.95;
  double D2 = 0.12, D3 = 0.05, D8 = 0.012, decay_exponent = 2.0;  // Fourier outlines
  double touching_fraction = 0.2;  // share of particles placed in touching pairs
  double background = 0.25, foreground = 0.75;
  double gradient = 0.15;  // background ramp across the image
  double noise = 0.03;     // Gaussian noise sigma (intensity units)
  double blur_px = 1.0;    // Gaussian blur sigma (optics)
  int info_bar_rows = 0;   // 0: no information bar
  bool dark_particles = false;
  std::uint64_t seed = 1;
  void check() const;  // throws InputError naming the bad field
};

struct SynthParticle {
  int id = 0;
  std::string kind;  // disc, ellipse or fourier
  Point2 centre;     // px, centroid of the exact outline
  double rotation_deg = 0.0;
  double area_px = 0.0;  // of the exact outline
  double equivalent_diameter_px = 0.0;
  double feret_max_px = 0.0, feret_min_px = 0.0;
  double aspect_ratio = 0.0;
  double D2 = 0.0;              // of the exact outline about its centroid
  int partner = 0;              // id of the particle it touches, 0 if none
  std::vector<Point2> outline;  // exact outline, densely sampled
};

struct SynthScene {
  GrayImage image;
  std::vector<SynthParticle> particles;
};

SynthScene render_synthetic_scene(const SynthOptions& options);

SynthShape parse_synth_shape(const std::string& name);  // throws InputError

}  // namespace shapepress::imaging
