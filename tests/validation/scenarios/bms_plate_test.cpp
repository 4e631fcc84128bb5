// Bonded multi-sphere (BMS) particles in the engine and the paper's rubber-sphere study
// (Giannis et al. 2023 §3.1–3.2; issue "BMS and the rubber-sphere study"): determinism with
// bonds (1 vs 2 threads, restart), a quasi-static balanced plate test, the classical Hertz
// sphere leaving Tatara's curve, and the calibrated agglomerate's accuracy and convergence.
// CI runs reduced sub-sphere counts; SHAPEPRESS_FULL_VALIDATION=1 runs the (calibrate at
// N = 545, evaluate 819 and 1322).
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "common/config.hpp"
#include "common/csv.hpp"
#include "scenarios/bms_particle.hpp"
#include "scenarios/calibrate.hpp"
#include "scenarios/plate_run.hpp"
#include "simulate/engine.hpp"
#include "simulate/snapshot.hpp"
#include "simulate/timestep.hpp"
#include "tests/support/files.hpp"
#include "tests/validation/scenarios/scenes.hpp"

namespace shapepress::scenarios {
namespace {

using testing::full_validation;

const std::filesystem::path repo = shapepress::testing::repository_root();

PlateConfig shipped_config() {
  const ConfigTable root = ConfigTable::load_file(repo / "pipelines/configs/rubber-sphere.toml");
  PlateConfig c = read_plate_config(root);
  root.check_unknown_keys();
  return c;
}

struct Reference {
  std::vector<double> deformation, tatara, hertz;
};
Reference tatara_reference() {
  const CsvTable t = read_csv(std::filesystem::path(SHAPEPRESS_TEST_DATA) / "analysis" /
                              "tatara_hertz_R10mm_E18.5MPa_nu0.46.csv");
  return {t.column("deformation"), t.column("F_tatara_N"), t.column("F_hertz_N")};
}

// An engine pressing a BMS sphere between plates, as run_plate sets it up.
Engine bms_engine(const PlateConfig& config, int count) {
  BmsConfig bms = *config.bms;
  bms.count = count;
  const MaterialTable table = config.materials.table();
  PlateParticle p = bms_sphere(table, config.setup.radius, bms, "rubber");
  double low = 1e9, high = -1e9;
  for (std::size_t i = 0; i < p.spheres.size(); ++i) {
    low = std::min(low, p.spheres.position.z[i] - p.spheres.radius[i]);
    high = std::max(high, p.spheres.position.z[i] + p.spheres.radius[i]);
  }
  const int wall = table.index_of("wall");
  const TimeStepChoice dt =
      select_time_step(p.spheres, table, {wall}, std::nullopt, 0.2, config.setup.speed, p.bonds);
  EngineSettings settings{dt.time_step, {0, 0, 0}, 0.1 * p.spheres.radius[0]};
  return Engine(std::move(p.spheres), Box{}, table,
                {PlaneWall{low, 1, 0.0, wall}, PlaneWall{high, -1, -config.setup.speed, wall}},
                settings, std::move(p.bonds));
}

PlateConfig stiff_bonds(PlateConfig c) {
  // Bonds and contacts of the FCC lattice's N = 545 calibration (rounded), so that
  // bond and contact forces both matter.
  set_parameter(c, "contact_modulus", 4.5e9);
  c.bms->bond.modulus = 2.2e6;
  c.bms->bond.shear_ratio = 0.08;
  return c;
}

TEST(BmsDeterminism, OneAndTwoThreadsGiveTheSameBits) {
  // 1200 sub-spheres: more than parallel_min_bonds bonds and parallel_min_pairs list pairs, so
  // both loops split
  // (the random fill bonds about 3.7 per sphere).
  const PlateConfig config = stiff_bonds(shipped_config());
  const auto run = [&](int threads) {
    omp_set_num_threads(threads);
    Engine engine = bms_engine(config, 1200);
    EXPECT_GT(engine.bonds().size(), static_cast<std::size_t>(parallel_min_bonds));
    for (int k = 0; k < 800; ++k)
      engine.step();
    return engine;
  };
  const Engine one = run(1), two = run(2);
  omp_set_num_threads(2);
  EXPECT_EQ(one.state().position, two.state().position);
  EXPECT_EQ(one.state().force, two.state().force);
  EXPECT_EQ(one.bonds().history, two.bonds().history);
  EXPECT_EQ(one.wall_force(1), two.wall_force(1));
  EXPECT_GT(one.wall_load(1), 0.0);  // the plate did press
}

TEST(BmsDeterminism, MultiContactLawWithBondedStressGivesTheSameBitsOnOneAndTwoThreads) {
  // The β term reads each sub-sphere's Love–Weber pressure with its bonds (forces.cpp's gather):
  // the same 1200-sub-sphere body, every interaction on the multi-contact law with β = 1.71.
  PlateConfig config = stiff_bonds(shipped_config());
  MulticontactParameters m;
  m.prefactor = 1.71;
  for (Interaction& interaction : config.materials.interactions)
    interaction.normal_law = MulticontactLaw{m};
  const auto run = [&](int threads) {
    omp_set_num_threads(threads);
    Engine engine = bms_engine(config, 1200);
    EXPECT_TRUE(engine.computes_particle_stress());
    for (int k = 0; k < 300; ++k)
      engine.step();
    return engine;
  };
  const Engine one = run(1), two = run(2);
  omp_set_num_threads(2);
  EXPECT_EQ(one.state().position, two.state().position);
  EXPECT_EQ(one.state().force, two.state().force);
  EXPECT_EQ(one.bonds().history, two.bonds().history);
  EXPECT_EQ(one.wall_force(1), two.wall_force(1));
  double largest = 0.0;
  for (std::size_t i = 0; i < one.state().size(); ++i) {
    EXPECT_EQ(one.particle_pressure(i), two.particle_pressure(i)) << "sub-sphere " << i;
    largest = std::max(largest, std::fabs(one.particle_pressure(i)));
  }
  EXPECT_GT(largest, 0.0);
  EXPECT_GT(one.wall_load(1), 0.0);
}

TEST(BmsDeterminism, RestartFromASnapshotContinuesBitIdentically) {
  const PlateConfig config = stiff_bonds(shipped_config());
  omp_set_num_threads(1);
  Engine continuous = bms_engine(config, 200);
  Engine first = bms_engine(config, 200);
  for (int k = 0; k < 1200; ++k)
    first.step();
  const std::filesystem::path file =
      shapepress::testing::fresh_directory("bms_restart") / "snapshot.h5";
  write_snapshot(file, first, ScenarioState{}, Provenance{"test", "", std::nullopt});
  LoadedSnapshot loaded = read_snapshot(file);
  std::filesystem::remove(file);
  ASSERT_EQ(loaded.checkpoint.bonds.size(), first.bonds().size());
  Engine resumed(std::move(loaded.state), loaded.box, config.materials.table(), first.settings(),
                 std::move(loaded.checkpoint));
  for (int k = 0; k < 2400; ++k)
    continuous.step();
  for (int k = 0; k < 1200; ++k)
    resumed.step();
  omp_set_num_threads(2);
  EXPECT_EQ(continuous.state().position, resumed.state().position);
  EXPECT_EQ(continuous.state().velocity, resumed.state().velocity);
  EXPECT_EQ(continuous.bonds().history, resumed.bonds().history);
  EXPECT_EQ(continuous.wall_force(1), resumed.wall_force(1));
}

TEST(BmsStack, TwoBodiesRestOnEachOtherAndAreBondedOnlyWithinThemselves) {
  // [plate] stack = 2: the second copy is dropped onto the first (touching, not overlapping),
  // each is its own body with the particle's radius, and Eq. 10 never bonds across them.
  PlateConfig config = shipped_config();
  config.bms->count = 80;
  const MaterialTable table = config.materials.table();
  BmsParticleInfo one;
  const PlateParticle single = bms_particle(table, config.setup.radius, *config.bms, "one", &one);
  const PlateParticle pair =
      bms_particle(table, config.setup.radius, *config.bms, "pair", nullptr, nullptr, 2);
  const SphereState& s = pair.spheres;
  ASSERT_EQ(s.size(), 2 * single.spheres.size());
  EXPECT_EQ(pair.bonds.size(), 2 * single.bonds.size());
  for (std::size_t b = 0; b < pair.bonds.size(); ++b)
    EXPECT_EQ(s.body[static_cast<std::size_t>(pair.bonds.first[b])],
              s.body[static_cast<std::size_t>(pair.bonds.second[b])]);
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.size(); ++i) {
    EXPECT_EQ(s.body[i], i < single.spheres.size() ? 0 : 1);
    EXPECT_EQ(s.body_radius[i], config.setup.radius);
    if (s.body[i] != 0) continue;
    for (std::size_t j = single.spheres.size(); j < s.size(); ++j) {
      const double d =
          std::hypot(s.position.x[j] - s.position.x[i], s.position.y[j] - s.position.y[i],
                     s.position.z[j] - s.position.z[i]);
      closest = std::min(closest, d - s.radius[i] - s.radius[j]);
    }
  }
  EXPECT_NEAR(closest, 0.0, 1e-9 * config.setup.radius);
}

TEST(BmsFills, EnsembleIsTheMeanOfItsFillsAndEachFillIsItsSeedsOwnRun) {
  // [bms] fills = 3 runs seeds 5, 6, 7 side by side on two threads: each fill's rows are the bits
  // of that seed's run alone, and the reported curve is their mean, with the spread.
  PlateConfig config = shipped_config();
  config.bms->count = 80;
  config.bms->seed = 5;
  config.setup.max_deformation = 0.08;
  config.setup.ramp = 0.02;
  config.setup.records = 8;
  config.bms->fills = 3;
  omp_set_num_threads(2);
  const PlateRunOutcome ensemble = run_plate_config(config, true);
  ASSERT_EQ(ensemble.fills(), 3);
  ASSERT_EQ(ensemble.fill_rows.size(), 3u);
  std::vector<std::vector<PlateRow>> alone;
  for (std::uint64_t seed : {5u, 6u, 7u}) {
    PlateConfig one = config;
    one.bms->fills = 1;
    one.bms->seed = seed;
    alone.push_back(run_plate_config(one, true).rows);
  }
  ASSERT_EQ(ensemble.rows.size(), 8u);
  for (std::size_t j = 0; j < ensemble.rows.size(); ++j) {
    double mean = 0.0, low = 1e300, high = -1e300;
    for (std::size_t f = 0; f < 3; ++f) {
      EXPECT_EQ(ensemble.fill_rows[f][j].top_force, alone[f][j].top_force) << "fill " << f;
      EXPECT_EQ(ensemble.fill_rows[f][j].approach, alone[f][j].approach) << "fill " << f;
      mean += alone[f][j].top_force / 3.0;
      low = std::min(low, alone[f][j].top_force);
      high = std::max(high, alone[f][j].top_force);
    }
    EXPECT_DOUBLE_EQ(ensemble.rows[j].top_force, mean) << "row " << j;
    EXPECT_EQ(ensemble.rows[j].top_force_min, low);
    EXPECT_EQ(ensemble.rows[j].top_force_max, high);
    EXPECT_GT(ensemble.rows[j].top_force_sd, 0.0);  // three different fills
    EXPECT_LE(ensemble.rows[j].top_force_sd, high - low);
  }
  // The fills differ: the seeds are not all the same fill.
  EXPECT_NE(alone[0].back().top_force, alone[1].back().top_force);
}

TEST(RubberSphere, ClassicalHertzSphereLeavesTataraBeyondTwentyPercent) {
  // The paper's point (§3.1): one Hertz sphere cannot follow a rubber sphere at large
  // deformation. The engine's sphere follows Hertz, which is > 10 % below Tatara's curve from
  // 20 % deformation on (27 % at 20 %, 37 % at 40 % in the reference table).
  const PlateConfig config = shipped_config();
  const PlateRunOutcome run = run_plate_config(config, false);
  const Reference ref = tatara_reference();
  int checked = 0;
  for (const PlateRow& row : run.rows) {
    if (row.deformation < 0.2) continue;
    const double x = std::min(row.deformation, ref.deformation.back());
    double tatara = 0.0;  // linear interpolation in the 1 % table
    for (std::size_t k = 1; k < ref.deformation.size(); ++k)
      if (ref.deformation[k] >= x) {
        const double t =
            (x - ref.deformation[k - 1]) / (ref.deformation[k] - ref.deformation[k - 1]);
        tatara = ref.tatara[k - 1] + t * (ref.tatara[k] - ref.tatara[k - 1]);
        break;
      }
    EXPECT_GT((tatara - row.top_force) / tatara, 0.10) << "at deformation " << row.deformation;
    ++checked;
  }
  EXPECT_GE(checked, 15);
}

TEST(RubberSphere, BmsCompressionIsQuasiStaticAndBalanced) {
  // The shipped config as it is (carved fill, the calibrated elastic network, both plates with
  // a sin² ramp over 10 % to 0.2 m/s, then rising to 1.6 m/s, bond damping ζ = 0.113) keeps the
  // kinetic energy below 1 % of the plates' work, and the two plates carry the same force within
  // 2 %, from 5 % deformation to 40 %, on one fill. CI runs N = 545 (about 10 s), the full
  // validation 1322, where the margin is thin (docs/measurements.md, "Rubber sphere: balance").
  PlateConfig config = shipped_config();
  ASSERT_GT(config.setup.ramp, 0.0);
  ASSERT_TRUE(config.setup.symmetric);
  config.bms->count = full_validation() ? 1322 : 545;
  config.bms->fills = 1;  // a mean would hide one fill's imbalance
  const PlateRunOutcome run = run_plate_config(config, true);
  ASSERT_EQ(run.rows.size(), static_cast<std::size_t>(config.setup.records));
  EXPECT_NEAR(run.rows.back().deformation, 0.40, 0.005);
  for (const PlateRow& row : run.rows) {
    EXPECT_EQ(row.intact_bonds, static_cast<std::int64_t>(run.bonds));  // unbreakable bonds
    if (row.deformation < 0.05) continue;
    EXPECT_LT(row.kinetic_energy, 0.01 * row.work) << "at deformation " << row.deformation;
    EXPECT_NEAR(row.bottom_force, row.top_force, 0.02 * row.top_force)
        << "at deformation " << row.deformation;
  }
}

// A mean curve's force and its standard error (sd/√K over K fills) at deformation x, linear
// between the rows, from (0, 0).
struct MeanForce {
  double force = 0.0, error = 0.0;
};
MeanForce mean_force_at(const PlateRunOutcome& run, double x) {
  const double k = std::sqrt(static_cast<double>(run.fills()));
  double d0 = 0.0, f0 = 0.0, s0 = 0.0;
  for (const PlateRow& row : run.rows) {
    if (row.deformation >= x) {
      const double w = (x - d0) / (row.deformation - d0);
      return {f0 + w * (row.top_force - f0), (s0 + w * (row.top_force_sd - s0)) / k};
    }
    d0 = row.deformation, f0 = row.top_force, s0 = row.top_force_sd;
  }
  ADD_FAILURE() << "the run did not reach deformation " << x;
  return {};
}

// The acceptance on the full study (SHAPEPRESS_FULL_VALIDATION=1; about 40 minutes on
// the 2-core machine): calibrate the shipped network at N = 545 against Tatara (the mean of 16
// fills, as pipelines/rubber-sphere/Makefile does), then with the same parameters compare the
// means of 32 fills of N = 819 and 1322 at every 1 % step from 5 % to 40 %. One fill is one
// sample (at N = 545 one carved fill's force varies by 17 % at 10 % deformation), so the
// issue's "< 2 % at every step" is asserted as far as 32 fills resolve 2 %: |difference| <
// 2 % + 2 standard errors at every step, and < 2 % from 21 % on: telling 2 % from zero at 10 %
// would need the standard error of the difference near 1 %, some 600 fills per N. The measured
// differences, with 32 and with 128 fills: docs/measurements.md, "The rubber-sphere study".
TEST(RubberSphere, CalibratedBmsMatchesTataraAndConverges) {
  if (!full_validation()) GTEST_SKIP() << "full study only (SHAPEPRESS_FULL_VALIDATION=1)";
  PlateConfig config = shipped_config();
  config.bms->count = 545;
  config.bms->fills = 16;
  const Reference ref = tatara_reference();
  CalibrationOptions options;
  // The Makefile's fit, from the shipped config's values (themselves a calibration at N = 545).
  options.parameters = {"modulus", "contact_modulus", "shear_ratio"};
  options.initial_factor = 1.2;
  options.method = analysis::SearchMethod::nelder_mead;  // the Makefile's METHOD
  options.reference_deformation = ref.deformation;
  options.reference_force = ref.tatara;
  options.max_evaluations = 40;
  const CalibrationResult calibrated = calibrate_plate(config, options);
  EXPECT_LT(calibrated.rms_relative, 0.05) << "N = 545 against Tatara over 5-40 %";
  std::vector<PlateRunOutcome> runs;
  for (int n : {819, 1322}) {
    PlateConfig c = calibrated.config;
    c.bms->count = n;
    c.bms->fills = 32;
    runs.push_back(run_plate_config(c, true));
  }
  int within = 0;
  for (int step = 5; step <= 40; ++step) {
    const double x = step / 100.0;
    const MeanForce coarse = mean_force_at(runs[0], x), fine = mean_force_at(runs[1], x);
    const double difference = coarse.force / fine.force - 1.0;
    const double error = std::hypot(coarse.error / fine.force,
                                    coarse.force * fine.error / (fine.force * fine.force));
    EXPECT_LT(std::abs(difference), 0.02 + 2.0 * error)
        << "N = 819 vs 1322 at deformation " << x << " (standard error " << error << ")";
    if (step >= 21) {
      EXPECT_LT(std::abs(difference), 0.02) << "at deformation " << x;
    }
    within += std::abs(difference) < 0.02;
  }
  std::printf("N = 819 vs 1322: %d of 36 steps within 2 %%\n", within);
}

}  // namespace
}  // namespace shapepress::scenarios
