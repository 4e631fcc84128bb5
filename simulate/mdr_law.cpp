#include "simulate/mdr_law.hpp"

#include <fmt/format.h>

#include "common/error.hpp"

namespace shapepress::simulate {

double mdr_yield_strain(double modulus, double yield_stress, double above) {
  const auto excess = [&](double s) {
    return 4.0 * modulus * std::sqrt(s) / (3.0 * std::numbers::pi) -
           mdr_yield_pressure(yield_stress, s);
  };
  double below = 0.0;  // excess(0) = -2.75 Y < 0 < excess(above)
  for (int k = 0; k < 200; ++k) {
    const double middle = 0.5 * (below + above);
    if (middle == below || middle == above) break;
    (excess(middle) > 0.0 ? above : below) = middle;
  }
  return above;
}

double mdr_indentation_energy(double modulus, const MdrSide& s, double displacement) {
  if (!(displacement > 0.0)) return 0.0;
  const double theta = 2.0 * std::asin(std::sqrt(displacement / s.height));
  // g(θ) = sin θ − θ cos θ − sin³θ / 3 = Σ_{k≥2} (−1)^k c_k θ^{2k+1} / (2k+1)!,
  // c_k = (3^{2k+1} − 3)/12 − 2k (sin³θ = (3 sin θ − sin 3θ)/4); θ ≤ π/2, so 3θ ≤ 4.8 and 24
  // terms leave less than 1e-17 of the sum.
  const double theta2 = theta * theta;
  double power = theta * theta2 * theta2 / 120.0;  // θ⁵/5!
  double three = 243.0;                            // 3^{2k+1}
  double sum = 0.0;
  for (int k = 2; k < 26; ++k) {
    const double c = (three - 3.0) / 12.0 - 2.0 * k;
    sum += (k % 2 == 0 ? c : -c) * power;
    power *= theta2 / ((2.0 * k + 2.0) * (2.0 * k + 3.0));
    three *= 9.0;
  }
  return s.scale * 0.125 * modulus * s.height * s.height * s.width * sum;
}

std::vector<OptionDoc> MdrLaw::options() {
  return {{"yield_stress", "Pa", "> 0", "required",
           "Y of the MDR law (Zunker & Kamrin 2024): the elastic–perfectly plastic solid's yield "
           "stress; E and ν are the materials'"}};
}

MdrLaw MdrLaw::read(const ConfigTable& t) {
  MdrLaw law;
  law.yield_stress = t.quantity("yield_stress", dim::pressure, std::nullopt, Range::positive());
  return law;
}

void MdrLaw::write_toml(std::string& out) const {
  out += fmt::format("yield_stress = {:.17g}\n", yield_stress);
}

void MdrLaw::check(const std::string& where) const {
  if (!(yield_stress > 0.0 && std::isfinite(yield_stress)))
    throw InputError(where + ": yield_stress must be > 0");
}

MdrLaw::Constants MdrLaw::constants(const Material& a, const Material& b) const {
  // ν of the deforming solid: the two Poisson ratios weighted by compliance 1/E, so it is the
  // particle's own between equal materials and against a far stiffer tool (as the multi-contact
  // law's ν).
  const double ca = 1.0 / a.youngs_modulus, cb = 1.0 / b.youngs_modulus;
  return {(a.poisson_ratio * ca + b.poisson_ratio * cb) / (ca + cb), yield_stress};
}

std::string MdrLaw::describe(const ElasticPair&, const Constants& k) {
  return fmt::format("mdr (Zunker & Kamrin 2024), Y = {:.6g} Pa, nu = {:.6g}", k.yield_stress,
                     k.poisson_ratio);
}

double MdrLaw::stiffness_ratio(const ElasticPair& p, const Constants& k, double) {
  // The tangent of a side unloading from its largest overlap s R is 2 E a_max / (1 + 2 ΔR / A)
  // (dF/dδe = 2 E a, a = a_max at δe = A/2), Hertz's at the same overlap 2 E √(R · s R); on the
  // elastic branch the ellipse is at most Hertz's. R = 1: every length scales with R. Over
  // s ≤ 0.5, the engine's default overlap limit (EngineSettings::max_overlap_fraction): the
  // tangent grows without bound as 1 + 2 ΔR / A falls towards 0 at s → 1.
  double ratio = 1.0;
  for (const double modulus : {2.0 * p.effective_modulus, p.effective_modulus}) {
    double yield_strain = 0.0;
    for (int step = 1; step <= 100; ++step) {
      const double strain = 0.005 * step;
      const MdrSide s =
          mdr_side(modulus, k.poisson_ratio, k.yield_stress, 1.0, strain, yield_strain);
      if (s.scale == 1.0 && s.plastic_overlap == 0.0) continue;
      ratio = std::max(ratio, 0.5 * s.width / std::sqrt(strain) / s.scale);
    }
  }
  return ratio;
}

double MdrLaw::elastic_energy(const ElasticPair& p, const Constants& k, double, double radius_first,
                              double radius_second, double overlap, const double* history) {
  const double largest = std::max(history[0], overlap);
  double yield_strain = history[1];
  if (!(largest > 0.0)) return 0.0;
  if (radius_second > 0.0) {
    const double modulus = 2.0 * p.effective_modulus;
    const Sides s =
        pair_sides(modulus, k, radius_first, radius_second, overlap, largest, yield_strain);
    // Each side's energy over dδi/dδ = (δpi − δgi) / (δp − δm), the interpolation of
    // pair_sides, and the pair's force the sides' mean.
    const double span = s.first.plastic_overlap + s.second.plastic_overlap - largest;
    const double first = mdr_indentation_energy(
        modulus, s.first, (s.overlap_first - s.first.plastic_overlap) / s.first.scale);
    const double second = mdr_indentation_energy(
        modulus, s.second, (s.overlap_second - s.second.plastic_overlap) / s.second.scale);
    const double energy = 0.5 * (first * span / (s.first.plastic_overlap - s.geometric_first) +
                                 second * span / (s.second.plastic_overlap - s.geometric_second));
    return energy;
  }
  const double modulus = p.effective_modulus;
  const MdrSide s =
      mdr_side(modulus, k.poisson_ratio, k.yield_stress, radius_first, largest, yield_strain);
  return mdr_indentation_energy(modulus, s, (overlap - s.plastic_overlap) / s.scale);
}

}  // namespace shapepress::simulate
