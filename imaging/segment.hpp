#pragma once
// Segmentation of particles in a grayscale image: denoise, flatten the background, threshold,
// fill holes, split touching particles, drop particles on the edge or outside the size range.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "imaging/image.hpp"

namespace shapepress::imaging {

enum class Denoise { none, gaussian, median };
enum class Background { none, quadratic, rolling };
// isodata: ImageJ's "Default" (its variant of IsoData, on the 256-level histogram).
enum class ThresholdMethod { otsu, triangle, fixed, adaptive, isodata };
// neck: two maxima of the distance map stay apart where the neck between them is narrow
// compared with the smaller one; prominence: where the smaller maximum stands more than
// split_prominence_px above the saddle (ImageJ's "Watershed": ultimate eroded points of the
// Euclidean distance map with a tolerance of 0.5).
enum class SplitRule { neck, prominence };
enum class Polarity { automatic, bright, dark };  // bright: bright particles on a dark background

struct SegmentOptions {
  Denoise denoise = Denoise::gaussian;
  double denoise_radius_px = 1.0;  // Gaussian sigma, or median half-size
  Background background = Background::quadratic;
  double rolling_radius_px = 50.0;  // structuring radius of the rolling background
  // The quadratic background is fitted only when Otsu's background pixels cover at least this
  // fraction of the image. Below it the field is dense (scikit-image's gravel: 0.11; the other
  // real and synthetic images of the tests: 0.37-0.81), its dark pixels are the gaps and
  // shadows between touching particles, and a surface fitted through them cuts off the darker
  // particles (docs/imaging.md).
  double background_min_fraction = 0.25;
  ThresholdMethod threshold = ThresholdMethod::otsu;
  double fixed_level = 0.5;       // fraction of the flattened intensity range
  int adaptive_block_px = 51;     // odd window of the adaptive threshold
  double adaptive_offset = 0.02;  // particle must exceed the local mean by this fraction
  Polarity polarity = Polarity::automatic;
  bool fill_holes = true;
  bool split_touching = true;
  // Two touching particles are split where the neck's half-width is below split_neck times the
  // inscribed radius of the smaller one (distance-transform watershed with dynamics).
  double split_neck = 0.75;
  // prominence by default: closer to ImageJ's watershed than neck on every real image of
  // tests/data/imaging (docs/imaging.md).
  SplitRule split_rule = SplitRule::prominence;
  // ImageJ's tolerance is 0.5, but on the three real images of tests/data/imaging this
  // flooding matches ImageJ's counts best at 0.6 (0.5 splits 2–7 % more; docs/imaging.md).
  // With fill_holes_after_split it is the tolerance of ImageJ's own watershed, which the CLI
  // sets to ImageJ's 0.5 for --split imagej.
  double split_prominence_px = 0.6;
  // A piece the split cuts off whose area is below this fraction of the median piece is joined
  // back to its neighbour (a sliver shaved off a large particle, not a particle; 0: never).
  double split_fragment_fraction = 0.1;
  // Clear a line between split particles so that no two touch, even diagonally (ImageJ's
  // watershed draws such lines; its areas leave them out).
  bool split_lines = true;
  // Split the mask as thresholded with ImageJ's own watershed (imagej_watershed.hpp) and fill
  // each piece's holes afterwards, as ImageJ's Watershed then Analyze Particles' "include
  // holes" do (else holes are filled first, and the split is split_rule's).
  bool fill_holes_after_split = false;
  // Split along the gaps of the image before smoothing, which closes gaps of 1–2 px between
  // touching particles: in concave blobs (below relief_solidity) the distance map is that of the
  // pixels that are particle both before and after the smoothing, and the pieces are grown back
  // over the smoothed mask, whose outlines are measured. Convex blobs are split as smoothed
  // (their dark pixels are relief). Only with smoothing and a single threshold level.
  bool split_gaps_unsmoothed = true;
  // A convex blob with holes is also split with its holes open, maxima kept apart only behind a
  // neck narrower than this times the smaller inscribed radius; when that gives three pieces or
  // more, the blob is a cluster of touching particles around pores and takes them
  // (segment.cpp, split_pores_of_clusters). Only with split_gaps_unsmoothed in effect: without
  // smoothing, the ragged relief of scikit-image's coins splits them into three or more.
  double cluster_split_neck = 0.6;
  // With fill_holes and the default order, holes are filled before the split only in blobs at
  // least this convex (area / convex hull area): in them a hole is the particle's own relief;
  // in more concave blobs (touching particles) it is a gap between them, split along first.
  double relief_solidity = 0.75;
  bool exclude_edges = true;  // like ImageJ's "exclude on edges"
  int min_area_px = 20;
  int max_area_px = 0;  // 0: no upper limit
  void check() const;   // throws InputError naming the bad field
};

struct Segmentation {
  LabelImage labels;
  bool bright_particles = true;  // polarity used (detected or imposed)
  double threshold = 0.0;  // level used, as a fraction of the flattened range (global methods)
  // The image as thresholded: particles bright, flattened, scaled to [0, 1]; with `threshold`
  // it places outlines between pixels (empty for the adaptive threshold: no single level).
  GrayImage flattened;
  int excluded_on_edge = 0;
  int excluded_by_size = 0;
  // The background flattening applied: none where a quadratic one was asked for on a dense
  // field; background_fraction is the share of Otsu's background pixels it was judged by (the
  // quadratic background only, else -1).
  Background background = Background::none;
  double background_fraction = -1.0;
};

Segmentation segment_particles(const GrayImage& image, const SegmentOptions& options);

// The split on its own, for tests: labels of a binary mask (non-zero = particle) after the
// distance-transform watershed; every 8-connected blob gets at least one label.
LabelImage split_touching_particles(const std::vector<std::uint8_t>& mask, int width, int height,
                                    double split_neck);
LabelImage split_touching_particles(const std::vector<std::uint8_t>& mask, int width, int height,
                                    const SegmentOptions& options);
// Split along the gaps of `gaps_open` (non-zero where open for the split), pieces grown back over
// `mask`; where `narrow_only` is non-zero, two maxima stay apart only if the neck rule
// (split_neck) also says so.
LabelImage split_touching_particles(const std::vector<std::uint8_t>& mask, int width, int height,
                                    const SegmentOptions& options,
                                    const std::vector<std::uint8_t>& gaps_open,
                                    const std::vector<std::uint8_t>& narrow_only);

// ImageJ's "Default" threshold of a 256-bin histogram: the level t (objects on one side: > t
// or <= t) of its IsoData variant, which leaves the first and last bins out.
int imagej_default_threshold(std::array<long, 256> histogram);

std::string to_string(ThresholdMethod method);
std::string to_string(Background background);

}  // namespace shapepress::imaging
