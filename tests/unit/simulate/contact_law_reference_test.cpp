// Every registered normal law (normal_laws.hpp) against reference values kept as data, one file
// per law: tests/data/contact_laws/<name>.csv (after LAMMPS' unittest/force-styles: one driver,
// the references in files). The values come from the closed-form equations written at the top of
// each file (tests/data/contact_laws/make_reference.py), not from this code.
//
// Columns: overlap, radius_i, radius_j (R* = ri rj / (ri + rj); radius_j = 0: a wall, R* = ri),
// effective_modulus (E* of the pair), poisson_ratio (of the one material), pair_pressure (P_ij),
// every key of the law's options() (an empty cell: the key is absent, its default applies), every
// history field <name> before the contact and <name>_after it, then the expected force (N, > 0
// repulsive) and the elastic energy (J) after the step. Contacts are at rest (vn = 0): no damping.
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
#include "simulate/contact_law.hpp"
#include "simulate/materials.hpp"
#include "tests/support/reference_rows.hpp"

namespace shapepress::simulate {
namespace {

using Row = shapepress::testing::ReferenceRow;
using shapepress::testing::read_reference_rows;

double relative(double a, double b) {
  const double scale = std::max(std::fabs(a), std::fabs(b));
  return scale > 0.0 ? std::fabs(a - b) / scale : 0.0;
}

template <class Law>
void replay(const std::filesystem::path& path) {
  SCOPED_TRACE(std::string(Law::name));
  const std::vector<Row> rows = read_reference_rows(path);
  ASSERT_FALSE(rows.empty()) << path << " holds no reference rows";
  for (const Row& row : rows) {
    SCOPED_TRACE("line " + std::to_string(row.line));
    // The law's parameters through its own config reader, as an [[interaction]] states them.
    std::string toml;
    for (const OptionDoc& o : Law::options()) {
      const auto it = row.cells.find(o.key);
      ASSERT_NE(it, row.cells.end()) << "no column for the law's key " << o.key;
      if (!it->second.empty()) toml += o.key + " = " + it->second + "\n";
    }
    const Law law = Law::read(ConfigTable::parse(toml, path.string()));
    Interaction in{"m", "m", 1.0, 0.0, 0.0, law};  // e = 1: no damping
    in.effective_modulus = row.number("effective_modulus");
    const Material material{"m", 1e9, row.number("poisson_ratio"), 1000.0};
    const PairConstants pc = MaterialTable({material}, {in}).pair(0, 0);

    const double ri = row.number("radius_i"), rj = row.number("radius_j");
    ContactKinematics c{};
    c.normal[2] = 1.0;
    c.overlap = row.number("overlap");
    // radius_j = 0: a wall (R* = ri), as the pair loop states it.
    c.effective_radius = rj > 0.0 ? ri * rj / (ri + rj) : ri;
    c.radius_first = ri;
    c.radius_second = rj;
    c.effective_mass = 1e-6;
    c.inverse_inertia_sum = 1e12;
    c.pair_pressure = row.number("pair_pressure");
    ContactHistory history;
    for (std::size_t k = 0; k < Law::history_fields.size(); ++k)
      law_history<Law>(history)[k] = row.number(Law::history_fields[k].name);
    const double sqrt_r_overlap = std::sqrt(c.effective_radius * c.overlap);
    const NormalForce f = normal_force_of<Law>(
        pc, c, sqrt_r_overlap, std::sqrt(sqrt_r_overlap * c.effective_mass), 0.0, history);
    EXPECT_LE(relative(f.force, row.number("force")), 1e-12)
        << f.force << " against " << row.cells.at("force");
    // The pair's own law through the run-time dispatch gives the same bits.
    ContactHistory again;
    for (std::size_t k = 0; k < Law::history_fields.size(); ++k)
      law_history<Law>(again)[k] = row.number(Law::history_fields[k].name);
    EXPECT_EQ(normal_force_of<AnyNormalLaw>(
                  pc, c, sqrt_r_overlap, std::sqrt(sqrt_r_overlap * c.effective_mass), 0.0, again)
                  .force,
              f.force);
    for (std::size_t k = 0; k < Law::history_fields.size(); ++k) {
      const std::string after = std::string(Law::history_fields[k].name) + "_after";
      EXPECT_LE(relative(law_history<Law>(history)[k], row.number(after)), 1e-12) << after;
    }
    EXPECT_LE(relative(normal_elastic_energy(pc, c.effective_radius, ri, rj, c.overlap, history),
                       row.number("energy")),
              1e-12)
        << "energy";
  }
}

TEST(ContactLawReference, EveryRegisteredLawReplaysItsReferenceFile) {
  const std::filesystem::path folder = std::filesystem::path(SHAPEPRESS_TEST_DATA) / "contact_laws";
  int laws = 0;
  for_each_normal_law([&]<class Law>() {
    ++laws;
    const std::filesystem::path path = folder / (std::string(Law::name) + ".csv");
    if (!std::filesystem::exists(path)) {
      ADD_FAILURE() << "normal law '" << Law::name << "' is registered but has no reference file "
                    << path;
      return;
    }
    replay<Law>(path);
  });
  EXPECT_EQ(laws, static_cast<int>(normal_law_count));
}

}  // namespace
}  // namespace shapepress::simulate
