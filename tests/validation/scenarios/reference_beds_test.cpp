// Two small beds pressed and unloaded against their stored curves (tests/data/scenarios/
// reference-*.csv), and the invariants every step of them must keep: the mass, Newton's third
// law between the spheres and the walls, and the energy the walls and gravity put in against the
// energy held and dissipated. The stored curves catch a change of the physics that the wide
// windows of the other tests let through (a bond stiffness 5 % off moves the bonded bed's peak by
// several per cent; docs/measurements.md, "Reference beds").
//
// The curves are remade, after a change of the physics that is meant, by
//   SHAPEPRESS_WRITE_REFERENCE=1 build/tests/validation_scenarios --gtest_filter='ReferenceBeds.*'
// which writes them into tests/data/scenarios/ (the source line in each file says so).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "common/config.hpp"
#include "common/csv.hpp"
#include "common/provenance.hpp"
#include "scenarios/compact_setup.hpp"
#include "tests/support/body_beds.hpp"
#include "tests/support/files.hpp"
#include "tests/validation/scenarios/scenes.hpp"

namespace shapepress::scenarios {
namespace {

namespace fs = std::filesystem;

bool writing_reference() {
  const char* value = std::getenv("SHAPEPRESS_WRITE_REFERENCE");
  return value != nullptr && std::string(value) == "1";
}

fs::path reference_file(const std::string& name) {
  return fs::path(SHAPEPRESS_TEST_DATA) / "scenarios" / name;
}

// 12 clusters of 13 sub-spheres of 20 µm (156 sub-spheres, 432 bonds: tests/support/body_beds.hpp)
// touching on a lattice, 2 × 2 × 3 in a periodic 240 µm die, with Avicel's Table 3/4 parameters
// and Table 4's bonds (tests/data/scenarios/bonded-bed.toml), mass-scaled 100 times (ten times
// the time step), pressed by 10 % of the bed's height at 0.1 m/s, unloaded at the same speed and
// released.
PreparedCompaction bonded_bed() {
  const BodyPacking bed = shapepress::testing::cluster_bed(BodyKind::bms, 20e-6, 2, 3, 7, 0.0, 6.0);
  const ConfigTable root = ConfigTable::parse(
      shapepress::testing::test_data_text("scenarios/bonded-bed.toml") +
          "\n[box]\nx = \"240 um\"\ny = \"240 um\"\n\n[run]\nrecord_every = 50\ndensity_scale = "
          "100\n\n"
          "[punch]\nmode = \"displacement\"\nspeed = \"0.1 m/s\"\ntarget_strain = 0.1\n"
          "unload_speed = \"0.1 m/s\"\nrelease_time = \"0.05 ms\"\n",
      "reference bonded bed");
  return prepare_compaction(read_compact_config(root), bed);
}

// 100 spheres of 0.8–1.2 mm poured into a periodic 4 mm die and settled (Hertz–Mindlin, damped
// and frictional: tests/data/scenarios/reference-sphere-bed.toml), pressed by 20 % of the settled
// height, held, unloaded and released.
PreparedCompaction sphere_bed() {
  const ConfigTable root = ConfigTable::load_file(reference_file("reference-sphere-bed.toml"));
  return prepare_compaction(read_compact_config(root), std::nullopt);
}

// What the invariants found over a run: the largest departure of each, as a fraction of its
// scale.
struct InvariantLog {
  double mass_change = 0.0;  // |M - M0| / M0
  // |Σ F_z + Σ wall F_z - M g_z| / (|top| + |bottom| + M |g|), where the walls or gravity act
  double force_imbalance = 0.0;
  double energy_from_nowhere = 0.0;     // largest -(W - ΔE) / W: dissipation below zero
  double dissipation_drop = 0.0;        // largest fall of the dissipated energy / W
  double work = 0.0, dissipated = 0.0;  // J, at the last step
  std::int64_t steps = 0;
};

// The energy the walls and gravity put in since the start, W (Engine::work_in), against the
// change of the kinetic and elastic energy, ΔE (Engine::energy: Hertz or multi-contact normal,
// tangential springs, bonds); their difference is what damping, friction and plasticity
// dissipated, D = W - ΔE, which can only grow.
struct EnergyBooks {
  double start = 0.0;
  double dissipated = 0.0;
  static double held(const Engine& engine) {
    const EnergySummary e = engine.energy();
    return e.kinetic + e.elastic;
  }
};

void check_invariants(const Engine& engine, double mass0, EnergyBooks& books, InvariantLog& log) {
  const SphereState& s = engine.state();
  double mass = 0.0, force_z = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    mass += s.mass[i];
    force_z += s.force.z[i];
  }
  log.mass_change = std::max(log.mass_change, std::fabs(mass - mass0) / mass0);
  double walls = 0.0, wall_scale = 0.0;
  for (std::size_t k = 0; k < engine.walls().size(); ++k) {
    walls += engine.wall_force(k);
    wall_scale += std::fabs(engine.wall_force(k));
  }
  // Pair forces, bonds and damping act in equal and opposite pairs: what is left of the spheres'
  // total is gravity and the walls' reaction.
  const double gravity = mass * engine.settings().gravity[2];
  const double scale = wall_scale + std::fabs(gravity);
  if (scale > 0.0)
    log.force_imbalance =
        std::max(log.force_imbalance, std::fabs(force_z + walls - gravity) / scale);
  const double work = engine.work_in();
  const double dissipated = work - (EnergyBooks::held(engine) - books.start);
  if (work > 0.0) {
    log.energy_from_nowhere = std::max(log.energy_from_nowhere, -dissipated / work);
    log.dissipation_drop = std::max(log.dissipation_drop, (books.dissipated - dissipated) / work);
  }
  books.dissipated = std::max(books.dissipated, dissipated);
  log.work = work, log.dissipated = dissipated;
  ++log.steps;
}

struct CurveRow {
  double step, gap, top_force, bottom_force, phase;
};

struct PressedBed {
  std::vector<CurveRow> rows;
  InvariantLog invariants;
};

PressedBed press(PreparedCompaction prepared) {
  Engine& engine = *prepared.engine;
  PressedBed out;
  const SphereState& s = engine.state();
  double mass0 = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i)
    mass0 += s.mass[i];
  EnergyBooks books{EnergyBooks::held(engine) - engine.work_in(), 0.0};
  CompactionHooks hooks;
  hooks.record = [&](const PunchRecord& r) {
    out.rows.push_back({static_cast<double>(r.step), r.gap, r.top_force, r.bottom_force,
                        static_cast<double>(r.phase)});
  };
  hooks.after_step = [&](const Engine& e, const PunchState&, const CompactionHistory&) {
    check_invariants(e, mass0, books, out.invariants);
    return true;
  };
  run_compaction(engine, prepared.setup, prepared.punch, hooks);
  return out;
}

void write_reference(const fs::path& path, const PressedBed& bed, const std::string& what) {
  std::ofstream out(path);
  out << "# " << what << "\n"
      << "# source: SHAPEPRESS_WRITE_REFERENCE=1 build/tests/validation_scenarios "
         "--gtest_filter='ReferenceBeds.*' (tests/validation/scenarios/reference_beds_test.cpp), "
         "shapepress "
      << shapepress_git_revision() << "\n"
      << "step,phase,gap_m,top_force_N,bottom_force_N\n";
  for (const CurveRow& r : bed.rows)
    out << fmt::format("{},{},{:.17g},{:.17g},{:.17g}\n", r.step, r.phase, r.gap, r.top_force,
                       r.bottom_force);
}

bool pressed(double phase) {
  return phase == static_cast<double>(PunchPhase::load) ||
         phase == static_cast<double>(PunchPhase::hold) ||
         phase == static_cast<double>(PunchPhase::unload);
}

// The run against its stored curve while the punch presses, holds and unloads: the same steps
// and phases, the gaps and forces within `tolerance` of the punch's travel and of the stored peak
// force. The release after the unloading is left out: there the bed springs back freely and the
// step at which the punch leaves it depends on the last bits of every contact.
void expect_reference_curve(const PressedBed& bed, const fs::path& path, double tolerance) {
  const CsvTable stored = read_csv(path);
  const std::vector<double> step = stored.column("step"), phase = stored.column("phase"),
                            gap = stored.column("gap_m"), top = stored.column("top_force_N"),
                            bottom = stored.column("bottom_force_N");
  const double peak = *std::max_element(top.begin(), top.end());
  const double travel = gap.front() - *std::min_element(gap.begin(), gap.end());
  ASSERT_GT(peak, 0.0);
  ASSERT_GT(travel, 0.0);
  double worst = 0.0;
  std::size_t worst_row = 0, compared = 0;
  for (std::size_t i = 0; i < step.size() && pressed(phase[i]); ++i, ++compared) {
    ASSERT_LT(i, bed.rows.size()) << "the run ended before row " << i << " of " << path;
    const CurveRow& row = bed.rows[i];
    ASSERT_EQ(row.step, step[i]) << "row " << i;
    ASSERT_EQ(row.phase, phase[i]) << "row " << i << " at step " << step[i];
    const double off =
        std::max({std::fabs(row.gap - gap[i]) / travel, std::fabs(row.top_force - top[i]) / peak,
                  std::fabs(row.bottom_force - bottom[i]) / peak});
    if (off > worst) worst = off, worst_row = i;
  }
  std::printf(
      "%s: %zu rows compared, largest difference %.3g (of the peak force %.4g N or the "
      "travel %.4g m, row %zu)\n",
      path.filename().c_str(), compared, worst, peak, travel, worst_row);
  EXPECT_GT(compared, 20u);
  EXPECT_LE(worst, tolerance) << "row " << worst_row << " of " << path;
}

// The invariants' limits. Mass: the spheres' masses are never changed (exact). Forces: a sum of
// a few thousand forces in double precision, cancelling to the walls' load: 1e-9 of the load is
// a million times the rounding. Energy: the velocity Verlet step's energy error, measured on
// these beds as a fall of the dissipated energy of at most 7e-6 of the work put in and never as
// energy from nowhere (docs/measurements.md, "Reference beds"); 1 % leaves room for a larger
// step and still catches a force that does work the books do not see.
void expect_invariants(const InvariantLog& log) {
  EXPECT_GT(log.steps, 1000);
  EXPECT_EQ(log.mass_change, 0.0);
  EXPECT_LE(log.force_imbalance, 1e-9);
  EXPECT_LE(log.energy_from_nowhere, 0.01);
  EXPECT_LE(log.dissipation_drop, 0.01);
  std::printf(
      "invariants over %lld steps: mass %.3g, forces %.3g, energy from nowhere %.3g, "
      "dissipation fall %.3g (of the work); at the end %.3g J put in, %.3g J dissipated\n",
      static_cast<long long>(log.steps), log.mass_change, log.force_imbalance,
      log.energy_from_nowhere, log.dissipation_drop, log.work, log.dissipated);
}

// Tolerances of the stored curves, as fractions of the peak force and of the punch's travel
// (docs/measurements.md, "Reference beds"). One and two threads, and a second run, give the same
// bits: difference 0. What another compiler's rounding could do is bounded by moving one sphere by
// 1e-13 m (a thousand times the rounding of its position) before the run: the bonded bed's rows
// moved by 5e-8, the sphere bed's by 1.1e-3 (its unloading: a random bed's contacts slip at
// their friction limit). The bonded bed's tolerance, 1e-3, is 20000 times its rounding's effect
// and 1/57 of what a bond stiffness 5 % off does to it (5.8e-2, the normal stiffness alone; 0.11
// with the shear stiffness too); the sphere bed's, 1e-2, is ten times its rounding's.
constexpr double bonded_bed_tolerance = 1e-3;
constexpr double sphere_bed_tolerance = 1e-2;

TEST(ReferenceBeds, BondedBedFollowsItsStoredCurveAndKeepsItsInvariants) {
  const PressedBed bed = press(bonded_bed());
  const fs::path path = reference_file("reference-bonded-bed.csv");
  if (writing_reference())
    write_reference(path, bed,
                    "12 BMS clusters of 13 sub-spheres pressed by 10 % and unloaded "
                    "(reference_beds_test.cpp bonded_bed)");
  expect_reference_curve(bed, path, bonded_bed_tolerance);
  expect_invariants(bed.invariants);
}

TEST(ReferenceBeds, SphereBedFollowsItsStoredCurveAndKeepsItsInvariants) {
  const PressedBed bed = press(sphere_bed());
  const fs::path path = reference_file("reference-sphere-bed.csv");
  if (writing_reference())
    write_reference(path, bed,
                    "100 spheres poured, settled, pressed by 20 % and unloaded "
                    "(reference-sphere-bed.toml)");
  expect_reference_curve(bed, path, sphere_bed_tolerance);
  expect_invariants(bed.invariants);
}

}  // namespace
}  // namespace shapepress::scenarios
