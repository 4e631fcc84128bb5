#pragma once
// A plate run from a config: the particle (one sphere, a BMS agglomerate or a CMS clump), the
// time step (Rayleigh time and, with bonds, the bonded network's period), the run. Shared by
// `plate` and `calibrate`, which runs it many times with different bond parameters.
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>
#include "scenarios/namespaces.hpp"

#include "common/provenance.hpp"
#include "scenarios/config_io.hpp"
#include "scenarios/plate.hpp"
#include "simulate/timestep.hpp"

namespace shapepress::scenarios {

class BmsFillCache;
class PlateCheckpoints;

struct PlateRunOutcome {
  std::vector<PlateRow> rows;
  std::string description;  // "BMS sphere R = … m, 545 sub-spheres of r = … m, 2900 bonds"
  std::size_t spheres = 0;
  std::size_t bonds = 0;
  std::size_t requested_spheres = 0;  // CMS: the count asked of the filler
  double sub_sphere_radius = 0.0;
  double time_step = 0.0;
  std::shared_ptr<const Engine> final_snapshot;  // the engine at the last row (the first fill's)
  // [bms] fills > 1: rows are the fills' mean (plate.hpp PlateRow), fill_rows each fill's own.
  std::vector<std::vector<PlateRow>> fill_rows;
  bool interrupted = false;  // stopped by a signal after a checkpoint (PlateCheckpoints)
  int fills() const { return fill_rows.empty() ? 1 : static_cast<int>(fill_rows.size()); }
  // The run's counted work, the fills' summed (the last row's: a run ends at its last row).
  WorkCount work_count() const { return rows.empty() ? WorkCount{} : rows.back().work_count; }
};

// What `plate --particle` presses: one Hertz sphere, a BMS agglomerate ([bms], [bond]) or a
// rigid CMS clump ([cms]).
enum class PlateParticleKind { sphere, bms, cms };
const char* particle_name(PlateParticleKind kind);  // "sphere", "bms", "cms"

// The step of a plate run: select_time_step (Rayleigh time, bonds, clumps) and, for a clump,
// its contact period bound at the end of the compression (each plate Δ/2 into it).
TimeStepChoice plate_time_step(const PlateParticle& particle, const MaterialTable& table,
                               const PlateSetup& setup, const RunSettings& run);

// `log` (optional) receives one-line notes (time step, particle). BMS with [bms] fills = K > 1:
// runs the K fills (seeds seed … seed + K − 1) side by side on the OpenMP threads, one thread
// each (each fill's rows are the bits of its own single run), and returns their mean curve; its
// cpu_s is the fills' CPU summed, wall_s their wall seconds summed over the threads. CMS: the
// plates pass through the clump's outer sub-spheres by design (it cannot deform), so the run's
// overlap check is widened to the deepest overlap the compression can make (logged); a blow-up is
// still caught by the energy and non-finite checks.
// `fills` (optional) keeps the BMS fills made, for a caller that presses the same fills again
// with other bond parameters (calibrate). `checkpoints` (optional, plate --resume): each fill
// finished before is reused, an unfinished one continues from its checkpoint, and a signal stops
// the run with `interrupted` once every running fill has written a checkpoint.
PlateRunOutcome run_plate_config(const PlateConfig& config, PlateParticleKind kind,
                                 const std::function<void(const std::string&)>& log = {},
                                 BmsFillCache* fills = nullptr,
                                 const PlateCheckpoints* checkpoints = nullptr);
// bonded: --particle bms, else sphere.
inline PlateRunOutcome run_plate_config(const PlateConfig& config, bool bonded,
                                        const std::function<void(const std::string&)>& log = {}) {
  return run_plate_config(config, bonded ? PlateParticleKind::bms : PlateParticleKind::sphere, log);
}

// final.h5 + final.xdmf in `folder`: the engine at the last row, for ParaView (sub-spheres as
// points, bonds as lines, clump axes, plates as quads). Nothing when the run kept no engine.
void write_plate_snapshot(const std::filesystem::path& folder, const PlateRunOutcome& outcome,
                          const Provenance& provenance);

// force.csv (atomically): time_s, deformation, approach_m, top_force_N, bottom_force_N,
// hertz_force_N, contacts, intact_bonds, kinetic_energy_J, work_J, cpu_s, wall_s, and for an
// ensemble of fills top_force_sd_N, top_force_min_N, top_force_max_N; comment lines say what was
// pressed, for people (report reads the same facts from run.json, scenarios/run_facts.hpp).
void write_force_csv(const std::filesystem::path& path, const PlateRunOutcome& outcome,
                     const PlateConfig& config, PlateParticleKind kind);
inline void write_force_csv(const std::filesystem::path& path, const PlateRunOutcome& outcome,
                            const PlateConfig& config, bool bonded) {
  write_force_csv(path, outcome, config,
                  bonded ? PlateParticleKind::bms : PlateParticleKind::sphere);
}

}  // namespace shapepress::scenarios
