// Every registered bond model (bond_models.hpp) against reference values kept as data, one file
// per model: tests/data/bond_models/<name>.csv, written by tests/data/bond_models/make_reference.py
// from the closed form of a bonded pair under a prescribed displacement history, not from this
// code (as contact_law_reference_test.cpp does for the normal laws).
//
// Columns: mode (normal, shear, twist, bending), step (0: a bond at rest; each row moves on from
// the one before), displacement (m or rad), radius (both spheres', λ̄ = 1), normal_stiffness and
// shear_stiffness (k̄n, k̄s), every key of the model's options(), the expected force (or moment)
// F on the second sphere along the mode's axis, the plastic displacement u_p of F = -k (u - u_p),
// and every history field of the model.
//
// The pair is driven through compute_bond_forces, the engine's bond loop: the normal mode by the
// centre distance 2r + u, the other modes by the relative motion over a step of dt = 1 s, a slip
// velocity of the second sphere normal to the bond (shear), or spins -Δθ/2 and +Δθ/2 about the
// bond (twist) or normal to it (bending), which move the bond's centre on neither sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/config.hpp"
#include "simulate/bond_models.hpp"
#include "simulate/bonds.hpp"
#include "tests/support/reference_rows.hpp"

namespace shapepress::simulate {
namespace {

using Row = shapepress::testing::ReferenceRow;
using shapepress::testing::read_reference_rows;

// A bonded pair of spheres of radius r along z, touching, the first at the origin.
struct Pair {
  SphereState state;
  BondSet bonds;
  double rest = 0.0;  // 2r
  std::vector<double> motion = std::vector<double>(16, 0.0);
};

Pair make_pair(const BondParameters& p, double r) {
  Pair pair;
  pair.state.add_sphere(0.0, 0.0, 0.0, r, 1000.0, 0);
  pair.state.add_sphere(0.0, 0.0, 2.0 * r, r, 1000.0, 0);
  pair.state.body.assign(2, 0);
  pair.rest = 2.0 * r;
  pair.bonds = create_bonds(pair.state, 1.1, p);
  return pair;
}

enum Mode { normal, shear, twist, bending };
Mode mode_of(const std::string& name) {
  if (name == "normal") return normal;
  if (name == "shear") return shear;
  if (name == "twist") return twist;
  if (name == "bending") return bending;
  throw std::runtime_error("unknown mode " + name);
}

// Moves the pair's mode from displacement `from` to `to` in one evaluation.
void drive(Pair& pair, Mode mode, double from, double to) {
  SphereState& s = pair.state;
  const double step = to - from;
  s.velocity.x[1] = 0.0;
  for (std::size_t i = 0; i < 2; ++i)
    s.angular_velocity.x[i] = s.angular_velocity.z[i] = 0.0;
  switch (mode) {
    case normal:
      s.position.z[1] = pair.rest + to;
      break;
    case shear:
      s.velocity.x[1] = step;
      break;
    case twist:
      s.angular_velocity.z[0] = -0.5 * step, s.angular_velocity.z[1] = 0.5 * step;
      break;
    case bending:
      s.angular_velocity.x[0] = -0.5 * step, s.angular_velocity.x[1] = 0.5 * step;
      break;
  }
  compute_bond_forces(pair.bonds, s, pair.motion.data(), Box{}, 1.0, false);
}

// The mode's force (moment) on the second sphere along its axis, and its spring.
double force_of(const BondSet& b, Mode mode) {
  const BondSet::History& h = b.history;
  switch (mode) {
    case normal:
      return h.normal_force[0];
    case shear:
      return h.shear_force.x[0];
    case twist:
      return h.twist_moment[0];
    case bending:
      return h.bend_moment.x[0];
  }
  return 0.0;
}
double spring_of(const BondSet& b, Mode mode) {
  const double k[4] = {b.normal_spring[0], b.shear_spring[0], b.twist_spring[0], b.bend_spring[0]};
  return k[mode];
}

template <class Model>
void replay(const std::filesystem::path& path) {
  SCOPED_TRACE(std::string(Model::name));
  const std::vector<Row> rows = read_reference_rows(path);
  ASSERT_FALSE(rows.empty()) << path << " holds no reference rows";
  Pair pair;
  Mode mode = normal;
  double previous = 0.0, scale = 0.0;
  int unloaded = 0;
  for (std::size_t index = 0; index < rows.size(); ++index) {
    const Row& row = rows[index];
    SCOPED_TRACE("line " + std::to_string(row.line));
    const double u = row.number("displacement");
    if (row.text("step") == "0") {
      // A new bond at rest, with the model's parameters through its own config reader.
      std::string toml;
      for (const OptionDoc& o : Model::options()) {
        const auto it = row.cells.find(o.key);
        ASSERT_NE(it, row.cells.end()) << "no column for the model's key " << o.key;
        if (!it->second.empty()) toml += o.key + " = " + it->second + "\n";
      }
      BondParameters p;
      p.normal_stiffness = row.number("normal_stiffness");
      p.shear_stiffness = row.number("shear_stiffness");
      p.model = Model::read(ConfigTable::parse(toml, path.string()));
      pair = make_pair(p, row.number("radius"));
      mode = mode_of(row.text("mode"));
      previous = 0.0;
      ASSERT_EQ(u, 0.0);
      // The scale of the errors: the largest force of this history.
      scale = 0.0;
      for (std::size_t next = index; next < rows.size(); ++next) {
        if (next > index && rows[next].text("step") == "0") break;
        scale = std::max(scale, std::fabs(rows[next].number("force")));
      }
    }
    drive(pair, mode, previous, u);
    previous = u;
    const double k = spring_of(pair.bonds, mode);
    const double f = force_of(pair.bonds, mode);
    const double expected = row.number("force");
    EXPECT_LE(std::fabs(f - expected), 1e-9 * scale) << f << " against " << expected;
    // F = -k (u - u_p): what the bond keeps of the displacement at zero force.
    const double plastic = row.number("plastic_displacement");
    const double displacement_scale = scale / k;
    const double displacement =
        mode == normal ? pair.state.position.z[1] - pair.state.position.z[0] - pair.rest : u;
    EXPECT_LE(std::fabs(displacement + f / k - plastic), 1e-9 * displacement_scale)
        << displacement + f / k << " against " << plastic;
    for (std::size_t field = 0; field < Model::history_fields.size(); ++field) {
      const std::string name = Model::history_fields[field].name;
      const double kappa = pair.bonds.history.model_fields[field][0];
      EXPECT_LE(std::fabs(kappa - row.number(name)), 1e-9 * displacement_scale)
          << name << " " << kappa << " against " << row.cells.at(name);
    }
    // The other modes stay at rest.
    for (Mode other : {normal, shear, twist, bending})
      if (other != mode) {
        EXPECT_EQ(force_of(pair.bonds, other), 0.0);
      }
    // Unloaded to zero force after yielding: the bond sits at its plastic displacement.
    if (std::fabs(expected) <= 1e-9 * scale && std::fabs(plastic) > 1e-3 * displacement_scale) {
      ++unloaded;
      EXPECT_LE(std::fabs(f), 1e-9 * scale);
      EXPECT_LE(std::fabs(displacement - plastic), 1e-9 * displacement_scale);
    }
  }
  if constexpr (Model::yields) {
    EXPECT_GT(unloaded, 0) << "no row unloads a yielded bond to zero force";
  }
}

TEST(BondModelReference, EveryRegisteredModelReplaysItsReferenceFile) {
  const std::filesystem::path folder = std::filesystem::path(SHAPEPRESS_TEST_DATA) / "bond_models";
  int models = 0;
  for_each_bond_model([&]<class Model>() {
    ++models;
    const std::filesystem::path path = folder / (std::string(Model::name) + ".csv");
    if (!std::filesystem::exists(path)) {
      ADD_FAILURE() << "bond model '" << Model::name << "' is registered but has no reference file "
                    << path;
      return;
    }
    replay<Model>(path);
  });
  EXPECT_EQ(models, static_cast<int>(bond_model_count));
}

}  // namespace
}  // namespace shapepress::simulate
