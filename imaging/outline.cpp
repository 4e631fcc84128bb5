#include "imaging/outline.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace shapepress::imaging {

std::vector<Point2> trace_outline(const std::function<bool(int, int)>& inside, int start_x,
                                  int start_y) {
  // The walk of ImageJ's Wand (8-connected), so that the corner list — and with it the traced
  // perimeter, whose corner count depends on where the walk starts — is the same as ImageJ's.
  // Vertices sit between pixels (x-1, y-1), (x, y-1), (x-1, y), (x, y). Directions: 0 = +x,
  // 1 = -y, 2 = -x, 3 = +y; the pixel "in direction d" of a vertex is the one at d·90° − 45°.
  // Outside pixels stay on the left; at each vertex turn as far left as an inside pixel allows.
  auto inside_towards = [&](int x, int y, int direction) {
    switch (direction & 3) {
      case 0:
        return inside(x, y);
      case 1:
        return inside(x, y - 1);
      case 2:
        return inside(x - 1, y - 1);
      default:
        return inside(x - 1, y);
    }
  };
  int run_end = start_x;
  while (inside(run_end + 1, start_y))
    ++run_end;
  // Start on the right edge of the start pixel's run, heading down (+y).
  const int x0 = run_end + 1, y0 = start_y + 1, start_direction = 3;
  int x = x0, y = y0, direction = start_direction;
  std::vector<Point2> corners;
  do {
    int turn = direction + 1;
    while (turn >= direction && !inside_towards(x, y, turn))
      --turn;
    if (turn != direction) corners.push_back({static_cast<double>(x), static_cast<double>(y)});
    switch (turn & 3) {
      case 0:
        ++x;
        break;
      case 1:
        --y;
        break;
      case 2:
        --x;
        break;
      default:
        ++y;
        break;
    }
    direction = turn;
  } while (x != x0 || y != y0 || (direction & 3) != start_direction);
  // The walk started one step past the top-right corner of the run; ImageJ appends it here.
  if (corners.empty() || corners.front().x != x)
    corners.push_back({static_cast<double>(x), static_cast<double>(y)});
  return corners;
}

double polygon_area(const std::vector<Point2>& polygon) {
  double twice = 0.0;
  for (std::size_t i = 0, n = polygon.size(); i < n; ++i) {
    const Point2& a = polygon[i];
    const Point2& b = polygon[(i + 1) % n];
    twice += a.x * b.y - b.x * a.y;
  }
  return std::abs(twice) / 2.0;
}

double polygon_perimeter(const std::vector<Point2>& polygon) {
  double length = 0.0;
  for (std::size_t i = 0, n = polygon.size(); i < n; ++i)
    length +=
        std::hypot(polygon[(i + 1) % n].x - polygon[i].x, polygon[(i + 1) % n].y - polygon[i].y);
  return length;
}

double traced_perimeter(const std::vector<Point2>& corners) {
  const std::size_t n = corners.size();
  if (n < 3) return 0.0;
  double sum_dx = 0.0, sum_dy = 0.0;
  int n_corners = 0;
  double dx1 = corners[0].x - corners[n - 1].x, dy1 = corners[0].y - corners[n - 1].y;
  double side1 = std::abs(dx1) + std::abs(dy1);
  bool corner = false;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t next = (i + 1) % n;
    double dx2 = corners[next].x - corners[i].x, dy2 = corners[next].y - corners[i].y;
    sum_dx += std::abs(dx1);
    sum_dy += std::abs(dy1);
    double side2 = std::abs(dx2) + std::abs(dy2);
    // A one-pixel step between two corners is a diagonal: count one corner per such step.
    if (side1 > 1 || !corner) {
      corner = true;
      ++n_corners;
    } else {
      corner = false;
    }
    dx1 = dx2;
    dy1 = dy2;
    side1 = side2;
  }
  return sum_dx + sum_dy - n_corners * (2.0 - std::numbers::sqrt2);
}

std::vector<Point2> convex_hull(std::vector<Point2> points) {
  // Andrew's monotone chain.
  std::sort(points.begin(), points.end(), [](const Point2& a, const Point2& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  points.erase(
      std::unique(points.begin(), points.end(),
                  [](const Point2& a, const Point2& b) { return a.x == b.x && a.y == b.y; }),
      points.end());
  if (points.size() < 3) return points;
  auto cross = [](const Point2& o, const Point2& a, const Point2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  std::vector<Point2> hull(2 * points.size());
  std::size_t k = 0;
  for (const Point2& p : points) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0)
      --k;
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0)
      --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

namespace {

// Angle of a direction in degrees [0, 180), y pointing up as in ImageJ's reported angles.
double line_angle_degrees(double dx, double dy_down) {
  double angle = std::atan2(-dy_down, dx) * 180.0 / std::numbers::pi;
  if (angle < 0) angle += 180.0;
  if (angle >= 180.0) angle -= 180.0;
  return angle;
}

}  // namespace

Feret feret_diameters(const std::vector<Point2>& hull) {
  Feret feret;
  const std::size_t n = hull.size();
  if (n == 0) return feret;
  if (n < 3) {
    const Point2& a = hull.front();
    const Point2& b = hull.back();
    feret.max = std::hypot(b.x - a.x, b.y - a.y);
    feret.max_angle = line_angle_degrees(b.x - a.x, b.y - a.y);
    return feret;
  }
  auto cross = [&](std::size_t i, std::size_t j, std::size_t k) {
    return (hull[j].x - hull[i].x) * (hull[k].y - hull[i].y) -
           (hull[j].y - hull[i].y) * (hull[k].x - hull[i].x);
  };
  feret.min = std::numeric_limits<double>::infinity();
  // For each hull edge (i, i+1), advance the antipodal vertex j while the area (height over the
  // edge) grows: the edge's width is the min-Feret candidate, and (i, j), (i+1, j) are the
  // antipodal pairs whose distances include the max Feret.
  std::size_t j = 1;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t i1 = (i + 1) % n;
    while (std::abs(cross(i, i1, (j + 1) % n)) > std::abs(cross(i, i1, j)))
      j = (j + 1) % n;
    double edge = std::hypot(hull[i1].x - hull[i].x, hull[i1].y - hull[i].y);
    double width = std::abs(cross(i, i1, j)) / edge;
    if (width < feret.min) {
      feret.min = width;
      // The caliper direction is perpendicular to the edge.
      feret.min_angle = line_angle_degrees(-(hull[i1].y - hull[i].y), hull[i1].x - hull[i].x);
    }
    for (std::size_t a : {i, i1}) {
      double d = std::hypot(hull[j].x - hull[a].x, hull[j].y - hull[a].y);
      if (d > feret.max) {
        feret.max = d;
        feret.max_angle = line_angle_degrees(hull[j].x - hull[a].x, hull[j].y - hull[a].y);
      }
    }
  }
  return feret;
}

}  // namespace shapepress::imaging
