#pragma once
// Snapshots: one HDF5 file per snapshot with everything a restart needs (sphere state including
// the last forces, contact history, walls, the scenario's own state, list-build reference), plus an
// XDMF sidecar indexing all snapshots of a run so ParaView opens them as a time series (spheres
// as points with radius, velocity, force, contact count and body id; bonds as line cells; each
// rigid clump's principal axes as three line cells; each wall as a quad).
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "common/provenance.hpp"
#include "simulate/engine.hpp"

namespace shapepress::simulate {

// What a scenario keeps of its own controller (the punch program's phase, say) as named numbers:
// the engine saves and restores them without knowing what they mean.
using ScenarioState = std::vector<std::pair<std::string, double>>;

void write_snapshot(const std::filesystem::path& path, const Engine& engine,
                    const ScenarioState& scenario, const Provenance& provenance);

struct LoadedSnapshot {
  SphereState state;
  Box box;
  EngineCheckpoint checkpoint;
  ScenarioState scenario;
};
// InputError naming the file when it is not a shapepress snapshot.
LoadedSnapshot read_snapshot(const std::filesystem::path& path);

struct SnapshotIndexEntry {
  std::filesystem::path file;  // relative to the XDMF file
  double time = 0.0;
  std::size_t spheres = 0;
  std::size_t walls = 0;
  bool stress = false;     // /particles/stress and /particles/pressure are present
  std::size_t bonds = 0;   // drawn as line cells between sphere centres
  std::size_t clumps = 0;  // each body frame drawn as three line cells
};
// Writes the XDMF 3 sidecar atomically (rewritten after each snapshot).
void write_xdmf(const std::filesystem::path& path, const std::vector<SnapshotIndexEntry>& entries);

}  // namespace shapepress::simulate
