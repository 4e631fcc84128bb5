#include "packing/deposition.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>

namespace shapepress::packing {

namespace {

// The bodies as the lay-down moves them: each body's sub-spheres as offsets from its centre in
// the box's axes (its turn applied), their radii, and the reach of its bounding sphere.
struct LaidBody {
  Vector3 centre = {0.0, 0.0, 0.0};
  std::vector<Vector3> offset;
  std::vector<double> radius;
  double reach = 0.0;
};

void turn_body(const BodyTemplate& shape, const PackedBody& body, LaidBody& laid) {
  laid.offset.resize(shape.radii.size());
  laid.radius.resize(shape.radii.size());
  laid.reach = 0.0;
  for (std::size_t i = 0; i < shape.radii.size(); ++i) {
    const Vector3& c = shape.centres[i];
    laid.offset[i] = rotate_to_world(body.orientation,
                                     {body.scale * c[0], body.scale * c[1], body.scale * c[2]});
    laid.radius[i] = body.scale * shape.radii[i];
    laid.reach =
        std::max(laid.reach, std::hypot(laid.offset[i][0], laid.offset[i][1], laid.offset[i][2]) +
                                 laid.radius[i]);
  }
}

double wrap(double x, double length) {
  return x - length * std::floor(x / length);
}

class Bed {
 public:
  Bed(std::vector<LaidBody> bodies, const Box& box, double floor, double clearance)
      : bodies_(std::move(bodies)), box_(box), floor_(floor), clearance_(clearance) {}

  std::vector<LaidBody>& bodies() { return bodies_; }

  // The periodic images of `o` whose bounding sphere reaches b's horizontally: (dx, dy) from b's
  // centre to the image's.
  template <class Visit>
  void images_near(const LaidBody& b, const LaidBody& o, Visit&& visit) const {
    const double dx0 = o.centre[0] - b.centre[0], dy0 = o.centre[1] - b.centre[1];
    const double base_x = dx0 - box_.length_x * std::nearbyint(dx0 / box_.length_x);
    const double base_y = dy0 - box_.length_y * std::nearbyint(dy0 / box_.length_y);
    const double reach = b.reach + o.reach;
    for (int ix = -1; ix <= 1; ++ix)
      for (int iy = -1; iy <= 1; ++iy) {
        const double dx = base_x + ix * box_.length_x, dy = base_y + iy * box_.length_y;
        if (dx * dx + dy * dy < reach * reach) visit(dx, dy);
      }
  }

  // How far body b may move straight down before a sub-sphere meets the floor or a sub-sphere of
  // another body: for spheres i, j of radii sum R at horizontal distance h < R, i above j by
  // Δz ≥ √(R² - h²) = v, the drop that makes them touch is Δz - v. Bodies are visited from the
  // highest top down, and the search stops at the first whose top is below b's lowest reach.
  double largest_drop(std::size_t b) const {
    const LaidBody& body = bodies_[b];
    double drop = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < body.radius.size(); ++i)
      drop = std::min(drop, body.centre[2] + body.offset[i][2] - body.radius[i] - floor_);
    std::vector<std::pair<double, std::size_t>> below;
    for (std::size_t o = 0; o < bodies_.size(); ++o) {
      if (o == b) continue;
      const LaidBody& other = bodies_[o];
      if (other.centre[2] - other.reach >= body.centre[2] + body.reach) continue;  // above
      below.emplace_back(-(other.centre[2] + other.reach), o);
    }
    std::sort(below.begin(), below.end());
    for (const auto& [negative_top, o] : below) {
      if (-negative_top <= body.centre[2] - body.reach - drop) break;
      const LaidBody& other = bodies_[o];
      images_near(body, other, [&](double dx, double dy) {
        for (std::size_t i = 0; i < body.radius.size(); ++i) {
          const Vector3& a = body.offset[i];
          // Sub-sphere i against the other's bounding cylinder first.
          const double cx = dx - a[0], cy = dy - a[1];
          const double near = body.radius[i] + other.reach;
          if (cx * cx + cy * cy >= near * near) continue;
          const double zi = body.centre[2] + a[2];
          for (std::size_t j = 0; j < other.radius.size(); ++j) {
            const Vector3& c = other.offset[j];
            const double hx = cx + c[0], hy = cy + c[1];
            const double sum = body.radius[i] + other.radius[j];
            const double h2 = hx * hx + hy * hy;
            if (h2 >= sum * sum) continue;
            const double v = std::sqrt(sum * sum - h2);
            const double dz = zi - (other.centre[2] + c[2]);
            if (dz <= -v) continue;  // j above i: moving down parts them
            drop = std::min(drop, std::max(0.0, dz - v));
          }
        }
      });
    }
    return drop;
  }

  // Moves body b down by its largest drop less the clearance.
  void drop(std::size_t b) {
    const double d = largest_drop(b);
    bodies_[b].centre[2] -= std::max(0.0, d - clearance_);
  }

  // The largest overlap of body b's sub-spheres with the floor or another body's (0: none).
  double overlap(std::size_t b) const {
    const LaidBody& body = bodies_[b];
    double worst = 0.0;
    for (std::size_t i = 0; i < body.radius.size(); ++i)
      worst = std::max(worst, floor_ - (body.centre[2] + body.offset[i][2] - body.radius[i]));
    for (std::size_t o = 0; o < bodies_.size(); ++o) {
      if (o == b) continue;
      const LaidBody& other = bodies_[o];
      const double dz0 = other.centre[2] - body.centre[2];
      if (std::fabs(dz0) >= body.reach + other.reach) continue;
      images_near(body, other, [&](double dx, double dy) {
        for (std::size_t i = 0; i < body.radius.size(); ++i) {
          const Vector3& a = body.offset[i];
          const double cx = dx - a[0], cy = dy - a[1], cz = dz0 - a[2];
          const double near = body.radius[i] + other.reach;
          if (cx * cx + cy * cy + cz * cz >= near * near) continue;
          for (std::size_t j = 0; j < other.radius.size(); ++j) {
            const Vector3& c = other.offset[j];
            const double hx = cx + c[0], hy = cy + c[1], hz = cz + c[2];
            const double sum = body.radius[i] + other.radius[j];
            const double d2 = hx * hx + hy * hy + hz * hz;
            if (d2 < sum * sum) worst = std::max(worst, sum - std::sqrt(d2));
          }
        }
      });
    }
    return worst;
  }

  void wrap_centre(std::size_t b) {
    bodies_[b].centre[0] = wrap(bodies_[b].centre[0], box_.length_x);
    bodies_[b].centre[1] = wrap(bodies_[b].centre[1], box_.length_y);
  }

 private:
  std::vector<LaidBody> bodies_;
  Box box_;
  double floor_ = 0.0;
  double clearance_ = 0.0;
};

std::vector<LaidBody> laid_bodies(const std::vector<BodyTemplate>& templates,
                                  const std::vector<PackedBody>& bodies) {
  std::vector<LaidBody> laid(bodies.size());
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    turn_body(templates[static_cast<std::size_t>(bodies[b].template_index)], bodies[b], laid[b]);
    laid[b].centre = bodies[b].centre;
  }
  return laid;
}

// A turn by an angle uniform in [-largest, largest] about an axis uniform on the sphere.
Quaternion small_turn(std::mt19937_64& random, double largest) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double ax = gauss(random), ay = gauss(random), az = gauss(random);
  const double norm = std::max(std::hypot(ax, ay, az), 1e-300);
  const double half = 0.5 * largest * unit(random);
  const double s = std::sin(half) / norm;
  return {std::cos(half), ax * s, ay * s, az * s};
}

}  // namespace

double deposit_bodies(const std::vector<BodyTemplate>& templates, std::vector<PackedBody>& bodies,
                      const Box& box, double floor, const DepositionMoves& moves) {
  std::vector<LaidBody> laid = laid_bodies(templates, bodies);
  double smallest = std::numeric_limits<double>::infinity();
  for (const LaidBody& b : laid)
    for (double r : b.radius)
      smallest = std::min(smallest, r);
  Bed bed(std::move(laid), box, floor, moves.clearance * smallest);
  std::mt19937_64 random(moves.seed ^ 0xd1b54a32d192ed03ULL);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::size_t> order(bodies.size());
  for (int sweep = 0; sweep < moves.sweeps; ++sweep) {
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return bed.bodies()[a].centre[2] < bed.bodies()[b].centre[2];
    });
    for (std::size_t b : order) {
      bed.drop(b);
      for (int trial = 0; trial < moves.trials; ++trial) {
        LaidBody& body = bed.bodies()[b];
        const LaidBody before = body;
        const Quaternion orientation = bodies[b].orientation;
        // A shift uniform in a disc of radius shift × reach, and a small turn.
        const double radius = moves.shift * body.reach * std::sqrt(unit(random));
        const double angle = 2.0 * std::numbers::pi * unit(random);
        body.centre[0] += radius * std::cos(angle);
        body.centre[1] += radius * std::sin(angle);
        const Quaternion turn = small_turn(random, moves.turn);
        bodies[b].orientation = normalized(multiply(turn, orientation));
        turn_body(templates[static_cast<std::size_t>(bodies[b].template_index)], bodies[b], body);
        if (bed.overlap(b) > 0.0) {
          body = before;
          bodies[b].orientation = orientation;
          continue;
        }
        bed.drop(b);
        if (body.centre[2] >= before.centre[2]) {  // not lower: the move is not kept
          body = before;
          bodies[b].orientation = orientation;
          continue;
        }
        bed.wrap_centre(b);
      }
    }
  }
  double top = floor;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    bodies[b].centre = bed.bodies()[b].centre;
    top = std::max(top, bed.bodies()[b].centre[2] + bed.bodies()[b].reach);
  }
  return top;
}

double largest_start_overlap(const std::vector<BodyTemplate>& templates,
                             const std::vector<PackedBody>& bodies, const Box& box, double floor) {
  Bed bed(laid_bodies(templates, bodies), box, floor, 0.0);
  double worst = 0.0;
  for (std::size_t b = 0; b < bodies.size(); ++b)
    worst = std::max(worst, bed.overlap(b));
  return worst;
}

}  // namespace shapepress::packing
