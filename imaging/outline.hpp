#pragma once
// Outline geometry of a pixel region, with ImageJ's definitions: the outline runs along pixel
// edges (vertices at pixel corners), so the polygon's area equals the pixel count of a region
// without holes; the perimeter corrects the staircase at corners as ImageJ does; Feret
// diameters are calipers of the convex hull of that polygon.
#include <functional>
#include <vector>

#include "imaging/image.hpp"

namespace shapepress::imaging {

// Outer boundary of the 8-connected region containing `start` (the region's first pixel in
// raster order), traced along pixel edges as ImageJ's Wand does. Only the corners (direction
// changes) are returned, in ImageJ's order. `inside(x, y)` must be false outside the image.
std::vector<Point2> trace_outline(const std::function<bool(int, int)>& inside, int start_x,
                                  int start_y);

double polygon_area(const std::vector<Point2>& polygon);       // absolute, shoelace
double polygon_perimeter(const std::vector<Point2>& polygon);  // Euclidean, closed
// ImageJ's perimeter of a traced outline (ij.gui.PolygonRoi.getTracedPerimeter): edge lengths
// minus (2 - √2) per corner, which is unbiased for smooth shapes at any orientation.
double traced_perimeter(const std::vector<Point2>& corners);

std::vector<Point2> convex_hull(std::vector<Point2> points);  // counter-clockwise, no repeats

struct Feret {
  double max = 0.0;        // largest caliper width (longest chord of the hull)
  double min = 0.0;        // smallest caliper width
  double max_angle = 0.0;  // degrees in [0, 180), counter-clockwise from +x with y up (ImageJ)
  double min_angle = 0.0;
};
// Rotating calipers on a convex hull.
Feret feret_diameters(const std::vector<Point2>& hull);

}  // namespace shapepress::imaging
