#pragma once
// Fourier descriptors of a particle outline (Mollon & Zhao 2012): the radius from the centroid
// as a function of the polar angle, r(θ) = r0 (1 + Σ_n D_n cos(nθ + φ_n)). D2 measures
// elongation, D3–D7 irregularity, D8 and above roughness.
#include <array>
#include <vector>

#include "imaging/image.hpp"

namespace shapepress::imaging {

inline constexpr int fourier_max_order = 32;
using FourierSpectrum = std::array<double, fourier_max_order + 1>;  // D0 (= 1) … D32

// r(θ_k) at `samples` equally spaced angles θ_k = 2πk/samples (y down, as the image), the
// farthest crossing of the ray from `centre` with the closed polygon (so re-entrant outlines
// keep their outer envelope).
std::vector<double> radius_function(const std::vector<Point2>& polygon, Point2 centre,
                                    int samples = 256);

// D_n = |c_n| / r0 from the discrete Fourier transform of r(θ), with r0 = c_0 the mean radius
// (amplitude of cos(nθ + φ) is 2|c_n|/N against the mean Σr/N). D0 is 1 by this normalisation.
FourierSpectrum fourier_descriptors(const std::vector<double>& radius, double* mean_radius);

}  // namespace shapepress::imaging
