#pragma once
// ImageJ's Process > Binary > Watershed (ImageJ 1.53t: ij.plugin.filter.EDM.toWatershed with
// ij.plugin.filter.MaximumFinder), step for step, so that `--split imagej` cuts where ImageJ cuts
// and leaves the pixels ImageJ leaves. ImageJ floods the distance map at whole-pixel levels (its
// 8-bit conversion) from maxima found on the float map, and clears only the pixels where two
// growing particles would meet; a flood of the float map with a line cleared on either side of
// every border between labels cuts elsewhere and clears more (docs/imaging.md, "Dense fields").
#include <cstdint>
#include <vector>

namespace shapepress::imaging {

// Euclidean distance of each particle pixel (mask non-zero) to the nearest background pixel, as
// ImageJ's EDM computes it: nearest-point propagation in four passes, which is exact but for rare
// pixels behind a corner; pixels outside the image are not background. 0 on the background.
std::vector<float> imagej_distance_map(const std::vector<std::uint8_t>& mask, int width,
                                       int height);

// The mask after ImageJ's watershed: non-zero where a particle pixel is kept, 0 on the background
// and on the segmentation lines. `tolerance` is the height (px) by which a maximum of the
// distance map must stand above the saddle to a higher one to seed a particle (ImageJ: 0.5).
std::vector<std::uint8_t> imagej_watershed(const std::vector<std::uint8_t>& mask, int width,
                                           int height, double tolerance = 0.5);

}  // namespace shapepress::imaging
