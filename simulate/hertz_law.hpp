#pragma once
// Normal sub-model: Hertz, Fn = 4/3 E* √R* δ^{3/2} - γn vn (Johnson 1985 Eq. 4.22; damping as
// LIGGGHTS `gran model hertz`, models.md "Hertz–Mindlin with restitution damping"). No parameters
// beyond the pair's E*, no history.
#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "common/config.hpp"
#include "common/option_doc.hpp"
#include "simulate/law_types.hpp"

namespace shapepress::simulate {

struct HertzLaw {
  static constexpr std::string_view name = "hertz";
  static constexpr bool needs_pair_pressure = false;
  static constexpr std::array<HistoryField, 0> history_fields{};
  struct Constants {};

  // Its config keys under [[interaction]] (none), read, checked and written back.
  static std::vector<OptionDoc> options();
  static HertzLaw read(const ConfigTable& interaction);
  void write_toml(std::string& out) const;
  void check(const std::string& where) const;
  Constants constants(const Material& a, const Material& b) const;
  static std::string describe(const ElasticPair& p, const Constants& k);

  // Largest tangent stiffness dFn/dδ over the Hertz tangent 2 E* √(R* δ) of the same pair: the
  // time step's bound (timestep.cpp). Hertz itself.
  static double stiffness_ratio(const ElasticPair&, const Constants&, double /*effective_radius*/) {
    return 1.0;
  }

  // kn = 4/3 E* √(R* δ), Fn = kn δ - γn vn; `sqrt_r_overlap` = √(R* δ), `damping_root` =
  // √(√(R* δ) m*), so no pow is needed.
  [[gnu::always_inline]] static NormalForce force(const ElasticPair& p, const Constants&,
                                                  const ContactKinematics& c, double sqrt_r_overlap,
                                                  double damping_root, double vn,
                                                  double* /*history*/) {
    const double kn = 4.0 / 3.0 * p.effective_modulus * sqrt_r_overlap;
    const double gamma_n = p.normal_damping_scale * damping_root;
    const double normal_force = kn * c.overlap - gamma_n * vn;
    return {normal_force, normal_force};
  }

  // 8/15 E* √R* δ^{5/2}, the integral of the elastic force (energy checks).
  static double elastic_energy(const ElasticPair& p, const Constants&, double effective_radius,
                               double /*radius_first*/, double /*radius_second*/, double overlap,
                               const double* /*history*/) {
    return 8.0 / 15.0 * p.effective_modulus * std::sqrt(effective_radius * overlap) * overlap *
           overlap;
  }
};

}  // namespace shapepress::simulate
