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
  Point2 centroid;                   // px, pixel corners at integers (ImageJ)
  double area = 0.0;                 // px², pixel count
  double perimeter = 0.0;            // px, ImageJ traced perimeter
  double equivalent_diameter = 0.0;  // px, √(4A/π)
  Feret feret;                       // px and degrees
  double aspect_ratio = 0.0;         // Feret min / Feret max (QICPIC's ASR)
  double circularity = 0.0;          // 4πA/P², at most 1 (ImageJ)
  double solidity = 0.0;             // A / convex hull area (ImageJ)
  double convexity = 0.0;            // convex hull perimeter / perimeter, at most 1
  double ellipse_major = 0.0;        // px, full axes of the moment ellipse of equal area
  double ellipse_minor = 0.0;
  double ellipse_angle = 0.0;        // degrees [0, 180), y up (ImageJ)
  double fourier_mean_radius = 0.0;  // px, r0
  FourierSpectrum fourier{};         // D0 … D32
  std::vector<Point2> outline;       // corners of the traced outline, px
};

std::vector<ParticleMeasurement> measure_particles(const LabelImage& labels);

// Measures one polygon (the outline of a known shape) with the same formulas; area is the
// polygon's area and the perimeter its Euclidean length. Used for ground truth.
ParticleMeasurement measure_polygon(const std::vector<Point2>& polygon);

}  // namespace shapepress::imaging
