#pragma once
// Settling a poured bed: the spheres (and rigid clumps) fall under gravity onto the die floor
// with the punch parked above them, then are left at rest, so the compaction starts from a
// bed and not from a cloud.
#include <array>
#include <functional>
#include <optional>
#include <vector>

#include "simulate/engine.hpp"
#include "simulate/snapshot.hpp"

namespace shapepress::packing {

using namespace simulate;

struct SettleRequest {
  Box box;
  std::vector<PlaneWall> walls;  // the die floor and the parked punch
  EngineSettings settings;       // gravity zero: 9.81 m/s² down
  double settle_time = 0.2;      // s
  // Sliding and rolling friction of every interaction while settling (a denser fill, as DEM
  // fills are usually made to reach a target density); absent: the interactions' own.
  std::optional<double> friction;
};

// Checkpoints of a settle (docs/stages.md, "Checkpoints and --resume"): `after_step` after every
// step; returning false stops the settle there (a signal asked for it). `resume`: a snapshot of
// the same settle's engine to continue from.
struct SettleCheckpoints {
  std::function<bool(const Engine&)> after_step;
  std::optional<LoadedSnapshot> resume;
};

// The settled spheres and clumps, with no velocity and no angular momentum; none when
// checkpoints.after_step stopped the settle.
std::optional<SphereState> settle(SphereState state, ClumpSet& clumps,
                                  std::vector<Material> materials,
                                  std::vector<Interaction> interactions,
                                  const SettleRequest& request, SettleCheckpoints checkpoints = {});

// The highest point of any sphere, at least `floor`.
double bed_top(const SphereState& state, double floor);

}  // namespace shapepress::packing
