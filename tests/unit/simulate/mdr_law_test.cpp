// The MDR law (mdr_law.hpp) beyond its reference rows: its key read, refused and written back;
// Hertz in the elastic limit for a pair and a wall; the plastic branch below Hertz at large
// strain and its unloading stiffer than its loading; a contact that no longer presses once drawn
// back below its plastic overlap; the time step's stiffness ratio.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <variant>

#include "common/config.hpp"
#include "common/error.hpp"
#include "simulate/contact_law.hpp"
#include "simulate/contact_law_config.hpp"

namespace shapepress::simulate {
namespace {

std::string message_of(const std::string& toml) {
  try {
    read_normal_law(ConfigTable::parse(toml, "t.toml"), "interaction m–m");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MdrLaw, YieldStressIsReadRefusedAndWrittenBack) {
  const NormalLawChoice law =
      read_normal_law(ConfigTable::parse("normal_law = \"mdr\"\nyield_stress = \"160 MPa\"\n", "t"),
                      "interaction m–m");
  ASSERT_TRUE(std::holds_alternative<MdrLaw>(law));
  EXPECT_DOUBLE_EQ(std::get<MdrLaw>(law).yield_stress, 1.6e8);
  const NormalLawChoice again =
      read_normal_law(ConfigTable::parse(normal_law_toml(law), "written"), "interaction m–m");
  EXPECT_EQ(std::get<MdrLaw>(again).yield_stress, 1.6e8);
  // Missing, zero, negative or not a pressure: an InputError naming the key.
  for (const char* bad :
       {"", "yield_stress = 0\n", "yield_stress = \"-1 MPa\"\n", "yield_stress = \"1 mm\"\n"})
    EXPECT_NE(message_of(std::string("normal_law = \"mdr\"\n") + bad).find("yield_stress"),
              std::string::npos)
        << bad;
  // Another law's key under mdr names the law it belongs to.
  EXPECT_NE(message_of("normal_law = \"mdr\"\nyield_stress = 1e8\nplasticity_ratio = 0.5\n")
                .find("multicontact"),
            std::string::npos);
}

TEST(MdrLaw, BodiesContactRadiusIsRefused) {
  Interaction in{"m", "m", 0.5, 0.5, 0.0, MdrLaw{1e8}};
  in.body_contact_radius = true;
  EXPECT_THROW(MaterialTable({{"m", 8e9, 0.3, 1560.0}}, {in}), InputError);
}

struct AvicelPair {
  PairConstants pair;
  double modulus;  // E / (1 − ν²)
};
AvicelPair avicel() {
  const MaterialTable table({{"m", 8e9, 0.3, 1560.0}}, {{"m", "m", 1.0, 0.5, 0.0, MdrLaw{1.6e8}}});
  return {table.pair(0, 0), 8e9 / 0.91};
}

double force(const PairConstants& p, double overlap, double ri, double rj, double* history) {
  ContactKinematics c{};
  c.normal[2] = 1.0;
  c.overlap = overlap;
  c.effective_radius = rj > 0.0 ? ri * rj / (ri + rj) : ri;
  c.effective_mass = 1e-6;
  c.radius_first = ri;
  c.radius_second = rj;
  ContactHistory h;
  law_history<MdrLaw>(h)[0] = history[0];
  law_history<MdrLaw>(h)[1] = history[1];
  const double root = std::sqrt(c.effective_radius * overlap);
  const double f = normal_force_of<MdrLaw>(p, c, root, std::sqrt(root * 1e-6), 0.0, h).force;
  history[0] = law_history<MdrLaw>(h)[0];
  history[1] = law_history<MdrLaw>(h)[1];
  return f;
}

TEST(MdrLaw, IsHertzInTheElasticLimit) {
  const AvicelPair s = avicel();
  const double r = 1e-4, e_star = s.pair.effective_modulus;
  for (const double overlap : {1e-9, 1e-8, 1e-7}) {
    double h[2] = {0.0, 0.0};
    const double pair = force(s.pair, overlap, r, r, h);
    EXPECT_NEAR(pair / (4.0 / 3.0 * e_star * std::sqrt(0.5 * r) * std::pow(overlap, 1.5)), 1.0,
                overlap / r)
        << overlap;
    double w[2] = {0.0, 0.0};
    const double wall = force(s.pair, overlap, r, 0.0, w);
    EXPECT_NEAR(wall / (4.0 / 3.0 * e_star * std::sqrt(r) * std::pow(overlap, 1.5)), 1.0,
                overlap / r)
        << overlap;
    EXPECT_EQ(h[1], 0.0);  // not yielded
  }
}

TEST(MdrLaw, YieldsAndUnloadsStifferToAPlasticOverlap) {
  const AvicelPair s = avicel();
  const double r = 1e-4, e_star = s.pair.effective_modulus;
  double h[2] = {0.0, 0.0};
  double previous = 0.0, largest = 0.0;
  for (int k = 1; k <= 40; ++k) {  // loading to a side strain of 0.2
    largest = 0.01 * k * r;
    const double f = force(s.pair, largest, r, r, h);
    EXPECT_GT(f, previous);
    previous = f;
  }
  // Just past yield the contact area grows as 2πR dδ, twice Hertz's πR dδ, so the force first
  // rises above Hertz's; at a side strain of 0.2 the falling pY keeps it well below.
  EXPECT_LT(previous, 0.5 * 4.0 / 3.0 * e_star * std::sqrt(0.5 * r) * std::pow(largest, 1.5));
  EXPECT_GT(h[1], 0.0);               // yielded
  EXPECT_NEAR(h[1], 0.0129, 0.0002);  // Hertz's mean pressure meets pY at s ≈ 1.3 % (E/Y = 55)
  const double top = previous, step = 1e-3 * r;
  const double unloaded = force(s.pair, largest - step, r, r, h);
  double before[2] = {0.01 * 39 * r, h[1]};
  const double loading_slope = (top - force(s.pair, 0.01 * 39 * r, r, r, before)) / (0.01 * r);
  EXPECT_GT((top - unloaded) / step, 10.0 * loading_slope);  // elastic unloading
  EXPECT_EQ(force(s.pair, 0.35 * r, r, r, h), 0.0);          // below the plastic overlap
  EXPECT_EQ(force(s.pair, largest, r, r, h), top);           // reloading meets the peak
  EXPECT_EQ(h[0], largest);
}

TEST(MdrLaw, StiffnessRatioBoundsTheUnloadingTangent) {
  const AvicelPair s = avicel();
  const double ratio = MdrLaw::stiffness_ratio(s.pair, s.pair.constants_of<MdrLaw>(), 0.5e-4);
  EXPECT_GT(ratio, 1.0);
  // The pair's tangent just below δm over Hertz's 2 E* √(R* δ) at δm, for side strains to 0.5.
  const double r = 1e-4;
  for (const double strain : {0.05, 0.2, 0.45}) {
    const double overlap = 2.0 * strain * r, step = 1e-7 * overlap;
    double h[2] = {0.0, 0.0};
    const double top = force(s.pair, overlap, r, r, h);
    const double tangent = (top - force(s.pair, overlap - step, r, r, h)) / step;
    const double hertz = 2.0 * s.pair.effective_modulus * std::sqrt(0.5 * r * overlap);
    EXPECT_LE(tangent / hertz, ratio * (1 + 1e-3)) << strain;
  }
}

}  // namespace
}  // namespace shapepress::simulate
