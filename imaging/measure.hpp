#pragma once
// Per-particle measurements of a label image, in pixel units (the CSV converts with the pixel
// size). Definitions follow ImageJ's Analyze Particles where both measure the same thing.
#include <vector>

#include "imaging/fourier.hpp"
#include "imaging/image.hpp"
#include "imaging/outline.hpp"

namespace shapepress::imaging {

struct ParticleMeasurement {
  int label = 0;
  Point2 centroid;         // px, pixel corners at integers (ImageJ)
  double area = 0.0;       // px², pixel count
  double perimeter = 0.0;  // px, ImageJ traced perimeter
  // Area inside the sub-pixel outline when measured with the intensity image, else the pixel
  // count; the equivalent diameter √(4A/π) is taken from it.
  double outline_area = 0.0;
  double equivalent_diameter = 0.0;  // px
  Feret feret;                       // px and degrees
  // ASR = Feret min / Feret max (QICPIC), with the calipers of the pixel-edge midpoints: free
  // of the pixel-corner bias of ImageJ's Feret (ratio of those in feret_imagej_ratio).
  double aspect_ratio = 0.0;
  double feret_imagej_ratio = 0.0;  // MinFeret / Feret as ImageJ reports them
  double circularity = 0.0;         // 4πA/P², at most 1 (ImageJ)
  double solidity = 0.0;            // A / convex hull area (ImageJ)
  double convexity = 0.0;           // convex hull perimeter / perimeter, at most 1
  double ellipse_major = 0.0;       // px, full axes of the moment ellipse of equal area
  double ellipse_minor = 0.0;
  double ellipse_angle = 0.0;        // degrees [0, 180), y up (ImageJ)
  double fourier_mean_radius = 0.0;  // px, r0
  FourierSpectrum fourier{};         // D0 … D32, of the pixel-edge-midpoint outline
  std::vector<Point2> outline;       // corners of the traced outline, px
};

// With `intensity` (the thresholded image, particles bright) and its threshold `level`, the
// outline used for ASR and Fourier descriptors crosses each boundary pixel edge where the
// intensity interpolated between the two pixel centres equals `level` (sub-pixel); without,
// at the edge midpoints.
std::vector<ParticleMeasurement> measure_particles(const LabelImage& labels,
                                                   const GrayImage* intensity = nullptr,
                                                   double level = 0.5);

// Measures one polygon (the outline of a known shape) with the same formulas; area is the
// polygon's area and the perimeter its Euclidean length. Used for ground truth.
ParticleMeasurement measure_polygon(const std::vector<Point2>& polygon);

}  // namespace shapepress::imaging
