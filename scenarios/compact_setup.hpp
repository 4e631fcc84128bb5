#pragma once
// From a compact config and a packing (read, generated, or a snapshot) to an engine ready to
// run: walls, time step, skin, settling of a generated bed, the punch program in metres.
#include <memory>
#include <optional>
#include "scenarios/namespaces.hpp"

#include "packing/body_packing.hpp"
#include "packing/pack.hpp"
#include "scenarios/compact.hpp"
#include "scenarios/config_io.hpp"
#include "simulate/snapshot.hpp"
#include "simulate/timestep.hpp"

namespace shapepress::scenarios {

struct PreparedCompaction {
  std::unique_ptr<Engine> engine;  // none: the settle was stopped (SettleCheckpoints)
  CompactionSetup setup;
  PunchState punch;  // the run's step and its bounds are setup.time_step
};

// `spheres` empty: generate from config.generate (InputError if absent) and settle, with
// checkpoints of the settle (its resume: the bed is generated again, then the snapshot's).
PreparedCompaction prepare_compaction(const CompactConfig& config,
                                      std::optional<SphereList> spheres,
                                      SettleCheckpoints settle_checkpoints = {});
// A bed of bodies made by `pack` (spheres, BMS bodies bonded by config.bond, CMS bodies as rigid
// clumps): the box and floor must be the packing's, the punch starts at box.punch or, without
// it, at the packing's top. Not settled again.
PreparedCompaction prepare_compaction(const CompactConfig& config, const BodyPacking& packing);
// Continues a run from a snapshot with the same config.
PreparedCompaction resume_compaction(const CompactConfig& config, LoadedSnapshot snapshot);

}  // namespace shapepress::scenarios
