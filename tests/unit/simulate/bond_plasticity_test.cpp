// Elastic–plastic bonds (bond_models.hpp, docs/models.md "Elastic–plastic bonds") in the engine:
// a yield stress no force reaches gives the elastic model's bits; a bonded pair stretched past
// yield and let go keeps its plastic elongation; a body of plastic bonds runs stably at the step
// the elastic bonds allow and yields; a snapshot taken while bonds yield restarts bit-identically
// on one and on two threads. The closed-form histories are bond_model_reference_test.cpp's.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <random>
#include <variant>
#include <vector>

#include "common/hdf5_file.hpp"
#include "simulate/bond_models.hpp"
#include "simulate/bonds.hpp"
#include "simulate/engine.hpp"
#include "simulate/snapshot.hpp"
#include "tests/support/files.hpp"
#include "tests/unit/simulate/random_motion.hpp"

namespace shapepress::simulate {
namespace {

constexpr double r = 1e-3;
constexpr double rho = 2000.0;
constexpr double kn_bar = 1e10;  // N/m^3
constexpr double ks_bar = 0.5e10;
const double area = std::numbers::pi * r * r;

BondParameters elastic() {
  BondParameters p;
  p.normal_stiffness = kn_bar;
  p.shear_stiffness = ks_bar;
  return p;
}

BondParameters plastic(double sigma_y, double tau_y, double hardening) {
  BondParameters p = elastic();
  p.model = ElasticPlasticBond{sigma_y, tau_y, hardening};
  return p;
}

const MaterialTable& table() {
  static const MaterialTable t({{"m", 1e3, 0.3, rho}}, {{"m", "m", 0.7, 0.5}});
  return t;
}

TEST(BondPlasticity, AYieldStressNoForceReachesGivesTheElasticModelsBits) {
  // A crooked chain with side bonds moved at random: the elastic bonds go through the
  // vectorized blocks, the plastic ones through the scalar loop with the return, which leaves a
  // force below its limit untouched.
  for (double damping_ratio : {0.0, 0.2}) {
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    SphereState s;
    for (int i = 0; i < 70; ++i)
      s.add_sphere(1.6 * r * i + 0.2 * r * unit(random), 0.4 * r * unit(random),
                   0.4 * r * unit(random), r * (1.0 + 0.1 * unit(random)), rho, 0);
    s.body.assign(s.size(), 0);
    BondParameters a = elastic(), b = plastic(1e300, 1e300, 0.5);
    a.damping_ratio = b.damping_ratio = damping_ratio;
    BondSet blocks = create_bonds(s, 1.6, a), returned = create_bonds(s, 1.6, b);
    ASSERT_FALSE(blocks.yields);
    ASSERT_TRUE(returned.yields);
    std::vector<double> motion(8 * s.size(), 0.0);
    for (int step = 0; step < 20; ++step) {
      testing::move_at_random(s, motion, r, random);
      compute_bond_forces(blocks, s, motion.data(), Box{}, 1e-7, step == 0);
      compute_bond_forces(returned, s, motion.data(), Box{}, 1e-7, step == 0);
    }
    EXPECT_TRUE(blocks.history == returned.history) << "damping " << damping_ratio;
    for (std::size_t k = 0; k < blocks.size(); ++k) {
      const BondSet::Results::Record x = blocks.result.at(k), y = returned.result.at(k);
      ASSERT_EQ(std::memcmp(&x, &y, sizeof x), 0) << "bond " << k;
    }
  }
}

TEST(BondPlasticity, APairStretchedPastYieldAndLetGoKeepsItsPlasticElongation) {
  // Two touching spheres pulled apart by u = 3 u_y with u_y = σy/k̄n, then left to the bond
  // with a damper: they settle where the bond carries no force, 2r + u_p, the closed form's
  // u_p = (u - u_y)/(1 + H) (each unit beyond the elastic reach is 1/(1 + H) plastic); the
  // elastic bond goes back to 2r.
  const double sigma_y = 1e5, hardening = 0.25;
  const double u_y = sigma_y / kn_bar, u = 3.0 * u_y;
  for (const bool yielding : {false, true}) {
    SphereState s;
    s.add_sphere(0.0, 0.0, 0.0, r, rho, 0);
    s.add_sphere(2.0 * r, 0.0, 0.0, r, rho, 0);
    s.body = {0, 0};
    BondParameters p = yielding ? plastic(sigma_y, 1e300, hardening) : elastic();
    p.damping_ratio = 0.5;
    p.contact_when_bonded = false;
    BondSet bonds = create_bonds(s, 1.1, p);
    const std::vector<double> motion(16, 0.0);
    s.position.x[1] += u;  // stretched in one evaluation: the straight path of the closed form
    compute_bond_forces(bonds, s, motion.data(), Box{}, 0.0, true);
    const double u_p = yielding ? (u - u_y) / (1.0 + hardening) : 0.0;
    const double kappa = bonds.history.model_fields[0][0];
    EXPECT_NEAR(kappa, u_p, 1e-12 * u_y);
    const double dt = 0.2 * bond_stability_step(bonds, s, Box{});
    Engine engine(std::move(s), Box{}, table(), {}, EngineSettings{dt, {0, 0, 0}, 0.2 * r},
                  std::move(bonds));
    for (int k = 0; k < 20000; ++k)
      engine.step();
    const SphereState& e = engine.state();
    const double elongation = e.position.x[1] - e.position.x[0] - 2.0 * r;
    EXPECT_NEAR(elongation, u_p, 1e-6 * u_y) << (yielding ? "plastic" : "elastic");
    EXPECT_NEAR(engine.bonds().history.normal_force[0], 0.0, 1e-6 * sigma_y * area);
    // Unloading is elastic (the rebound stays below the limit): κn did not grow on the way back.
    EXPECT_EQ(engine.bonds().history.model_fields[0][0], kappa);
  }
}

// A body of 27 sub-spheres on a jittered cubic lattice 2.05 r apart (bonds alone act), every
// sphere moving at random, as bonds_test.cpp's run_body: with plastic bonds at the step the
// elastic ones allow.
struct PlasticBody {
  double energy_growth = 0.0;  // largest (kinetic + elastic) over the first
  int yielded = 0;             // bonds with some plastic displacement in any mode
  std::size_t bonds = 0;
};

PlasticBody run_plastic_body(double step_over_elastic_step) {
  SphereState s = testing::moving_cube_body(r, rho);
  // Stresses of this motion reach some tens of Pa: σy, τy well inside them.
  BondParameters p = plastic(5.0, 5.0, 0.1);
  p.contact_when_bonded = false;
  BondSet bonds = create_bonds(s, 1.15, p);
  BondParameters q = elastic();
  q.contact_when_bonded = false;
  const double elastic_step = bond_stability_step(create_bonds(s, 1.15, q), s, Box{});
  EXPECT_EQ(bond_stability_step(bonds, s, Box{}), elastic_step);  // the springs' bound
  EngineSettings settings{step_over_elastic_step * elastic_step, {0, 0, 0}, 0.2 * r};
  settings.check_every = 1 << 30;  // judged by its energy, not stopped
  Engine engine(std::move(s), Box{}, table(), {}, settings, std::move(bonds));
  const double e0 = engine.energy().elastic + engine.energy().kinetic;
  PlasticBody out;
  for (int k = 0; k < 3000; ++k) {
    engine.step();
    const EnergySummary e = engine.energy();
    const double growth = (e.elastic + e.kinetic) / e0;
    if (!std::isfinite(growth) || growth > 1e6) return {1e6, 0, 0};
    out.energy_growth = std::max(out.energy_growth, growth);
  }
  const BondSet& b = engine.bonds();
  out.bonds = b.size();
  for (std::size_t k = 0; k < b.size(); ++k) {
    bool any = false;
    for (const SphereArray<double>& kappa : b.history.model_fields)
      any = any || kappa[k] > 0.0;
    out.yielded += any;
  }
  return out;
}

TEST(BondPlasticity, APlasticBodyIsStableAtTheElasticModelsStepAndYields) {
  // The plastic tangent k H/(1 + H) and the elastic unloading never exceed k: the elastic
  // bound (with its margin, and without it, 2/ω_max) holds. The energy only falls below its
  // start by the plastic work, and Verlet's shadow energy at the limit swings it a little.
  for (double fraction : {1.0, 0.97 / bond_stability_margin}) {
    const PlasticBody run = run_plastic_body(fraction);
    EXPECT_LT(run.energy_growth, 3.0) << "step " << fraction << " of the elastic one";
    EXPECT_GT(run.yielded, static_cast<int>(run.bonds / 2)) << "of " << run.bonds << " bonds";
  }
}

// A chain of eight sub-spheres flung apart and spun, its bonds yielding from the first steps and
// on: the ends' momentum outlasts the run against the capped bond forces.
Engine flung_chain() {
  SphereState s;
  for (int k = 0; k < 8; ++k)
    s.add_sphere(2.05 * r * k, 0.1 * r * (k % 2), 0.0, r, rho, 0);
  s.body.assign(8, 0);
  BondParameters p = plastic(500.0, 300.0, 0.05);
  p.contact_when_bonded = false;
  BondSet bonds = create_bonds(s, 1.15, p);
  for (std::size_t i = 0; i < 8; ++i) {
    const double side = static_cast<double>(i) - 3.5;
    s.velocity.x[i] = 0.2 * side, s.velocity.y[i] = 0.01 * (i % 3 == 0 ? 1.0 : -1.0);
    s.angular_velocity.z[i] = 20.0 * side, s.angular_velocity.x[i] = 10.0 * side;
  }
  const double dt = 0.2 * bond_stability_step(bonds, s, Box{});
  EngineSettings settings{dt, {0, 0, 0}, 0.2 * r};
  return Engine(std::move(s), Box{}, table(), {}, settings, std::move(bonds));
}

int yielding_bonds(const BondSet& b) {
  int n = 0;
  for (std::size_t k = 0; k < b.size(); ++k)
    n += b.history.model_fields[0][k] > 0.0 || b.history.model_fields[1][k] > 0.0 ||
         b.history.model_fields[2][k] > 0.0 || b.history.model_fields[3][k] > 0.0;
  return n;
}

TEST(BondPlasticity, ASnapshotTakenWhileBondsYieldRestartsBitIdentically) {
  omp_set_num_threads(1);
  Engine continuous = flung_chain(), first = flung_chain();
  for (int k = 0; k < 400; ++k)
    first.step();
  const auto plastic_paths = [](const Engine& e) {
    double sum = 0.0;
    for (const SphereArray<double>& kappa : e.bonds().history.model_fields)
      for (double v : kappa)
        sum += v;
    return sum;
  };
  const double paths_then = plastic_paths(first);
  ASSERT_GT(yielding_bonds(first.bonds()), 0) << "no bond has yielded at the snapshot";
  const std::filesystem::path file =
      shapepress::testing::fresh_directory("bond_plasticity") / "restart.h5";
  write_snapshot(file, first, ScenarioState{}, Provenance{"test", "", std::nullopt});
  LoadedSnapshot loaded = read_snapshot(file);
  std::filesystem::remove(file);
  EXPECT_TRUE(loaded.checkpoint.bonds.model == first.bonds().model);
  EXPECT_TRUE(loaded.checkpoint.bonds.history == first.bonds().history);
  Engine resumed(std::move(loaded.state), loaded.box, table(), first.settings(),
                 std::move(loaded.checkpoint));
  for (int k = 0; k < 800; ++k)
    continuous.step();
  for (int k = 0; k < 400; ++k)
    resumed.step();
  omp_set_num_threads(2);
  // Still yielding after the restart: the plastic paths grew on.
  EXPECT_GT(plastic_paths(continuous), paths_then);
  EXPECT_TRUE(continuous.bonds().history == resumed.bonds().history);
  EXPECT_EQ(continuous.state().position, resumed.state().position);
  EXPECT_EQ(continuous.state().velocity, resumed.state().velocity);
  EXPECT_EQ(continuous.state().angular_velocity, resumed.state().angular_velocity);
}

TEST(BondPlasticity, ASnapshotOfElasticBondsHoldsNoModelAndReadsBackElastic) {
  // The default model adds nothing to a snapshot (its files stay as they were); one without the
  // model's datasets reads back elastic with zero plastic paths.
  SphereState s;
  for (int k = 0; k < 3; ++k)
    s.add_sphere(2.0 * r * k, 0.0, 0.0, r, rho, 0);
  s.body.assign(3, 0);
  BondSet bonds = create_bonds(s, 1.15, elastic());
  Engine engine(std::move(s), Box{}, table(), {}, EngineSettings{1e-7, {0, 0, 0}, 0.2 * r},
                std::move(bonds));
  const std::filesystem::path file =
      shapepress::testing::fresh_directory("bond_plasticity") / "elastic.h5";
  write_snapshot(file, engine, ScenarioState{}, Provenance{"test", "", std::nullopt});
  {
    const H5Reader h5(file);
    EXPECT_FALSE(h5.has_attribute("/bonds", "model"));
    EXPECT_FALSE(h5.has("/bonds/normal_plastic_path"));
  }
  const LoadedSnapshot loaded = read_snapshot(file);
  std::filesystem::remove(file);
  EXPECT_TRUE(std::holds_alternative<ElasticBond>(loaded.checkpoint.bonds.model));
  EXPECT_TRUE(loaded.checkpoint.bonds.history == engine.bonds().history);
}

}  // namespace
}  // namespace shapepress::simulate
