#pragma once
// Normal sub-model: the mechanically-derived contact (MDR) law of Zunker & Kamrin 2024 for
// elastic–perfectly plastic spheres (Part I, JMPS 183, 105492), the single-contact law without
// adhesion and without the particle's bulk response (Part II). Equations, their numbers and the
// choices made: models.md "MDR: elastic–perfectly plastic spheres (Zunker & Kamrin 2024)".
//
// Each side of a contact is a sphere of radius R pressed by a flat: the pair's overlap δ is split
// between the two sides by the plane of the spheres' intersection circle at the largest overlap
// δm (the "rigid flat placement", Part I §5), each side's force is that of its sphere against the
// flat through the method of dimensionality reduction (MDR) with an elliptical 1D indenter of
// height A/2 and half-width B/2, and the pair's force is the mean of the two sides'. Against a
// wall there is one side with the whole overlap.
//   elastic (the side's Hertz mean pressure below the yield pressure): A = 4R, B = 2R, δe = δs;
//   plastic: a_max² = 2 δms R − δms² + (sY² − sY) R², A = 4 pY a_max / E, B = 2 a_max, with the
//   displacement correction ΔR of the particle centre and δe = (δs − δp) / (1 + 2 ΔR / A),
//   δp = δms − A/2 − ΔR (unloading and reloading along the indenter of the largest overlap);
//   F = E A B / 4 (θ − sin θ cos θ), θ = 2 asin √(δe / A), 0 for δe ≤ 0.
// Everything on a side is a function of the contact's largest overlap δm, so the history is δm
// and the yield strain sY = δY / R (0 until a side first yields), the root of the side's Hertz
// mean pressure against the yield pressure pY(s) = Y (1.75 e^{−4.4 s} + 1).
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "common/config.hpp"
#include "common/option_doc.hpp"
#include "simulate/law_types.hpp"

namespace shapepress::simulate {

// One side of an MDR contact at its largest overlap: the elliptical indenter (height A/2,
// half-width B/2), the side's overlap δp at zero force and the compliance 1 + 2 ΔR / A that maps
// the side's overlap to the indenter's displacement δe = (δs − δp) / scale.
struct MdrSide {
  double height;           // A
  double width;            // B
  double plastic_overlap;  // δp (0 on the elastic branch)
  double scale;            // 1 + 2 ΔR / A (1 on the elastic branch)
};

// The mean contact pressure along the yield surface (Part I's fit to its finite-element sphere
// against a flat), at the side's largest overlap over its radius, s.
[[gnu::always_inline]] inline double mdr_yield_pressure(double yield_stress, double strain) {
  return yield_stress * (1.75 * std::exp(-4.4 * strain) + 1.0);
}

// sY in (0, `above`]: the strain at which the Hertz mean pressure 4 E √s / (3π) of a sphere
// against a flat reaches the yield pressure. The one root (the first rises, the second falls),
// by bisection to the last bit; `above` is a strain already past it.
double mdr_yield_strain(double modulus, double yield_stress, double above);

// The side of radius R at its largest overlap `largest` (δms). `yield_strain` is the contact's
// sY, set here the first time a side yields. `modulus` is the side's plane-strain modulus E.
[[gnu::always_inline]] inline MdrSide mdr_side(double modulus, double poisson_ratio,
                                               double yield_stress, double radius, double largest,
                                               double& yield_strain) {
  const double strain = largest / radius;
  const double yield_pressure = mdr_yield_pressure(yield_stress, strain);
  // The side yields once its Hertz mean pressure 4 E √δ / (3π √R) passes pY (Part I).
  const double hertz_pressure = 4.0 * modulus * std::sqrt(strain) / (3.0 * std::numbers::pi);
  if (!(hertz_pressure > yield_pressure)) return {4.0 * radius, 2.0 * radius, 0.0, 1.0};
  if (yield_strain == 0.0) yield_strain = mdr_yield_strain(modulus, yield_stress, strain);
  // The contact area π (2 δ R − δ²) of the sphere cut by the flat, shifted by
  // cA = π (δY² − δY R) so that it meets the elastic π δ R at the yield point.
  const double ys = yield_strain;
  const double area_radius2 =
      2.0 * largest * radius - largest * largest + (ys * ys - ys) * radius * radius;
  const double area_radius = std::sqrt(area_radius2);
  // The indenter whose full depth A/2 carries pY over the contact area: Fmax = π a² pY.
  const double height = 4.0 * yield_pressure * area_radius / modulus;
  // The elastic displacement of the sphere's centre under pY on the cap (Part I): ΔR = Fmax [2 a²
  // (ν − 1) − (2ν − 1) zR (√(a² + zR²) − zR)] / (2π a² G √(a² + zR²)), Fmax = π a² pY, zR = R −
  // (δms − A/2), G = E (1 − ν) / 2.
  const double centre_depth = radius - (largest - 0.5 * height);
  const double root = std::sqrt(area_radius2 + centre_depth * centre_depth);
  const double shear_modulus = 0.5 * modulus * (1.0 - poisson_ratio);
  const double correction = yield_pressure *
                            (2.0 * area_radius2 * (poisson_ratio - 1.0) -
                             (2.0 * poisson_ratio - 1.0) * centre_depth * (root - centre_depth)) /
                            (2.0 * shear_modulus * root);
  return {height, 2.0 * area_radius, largest - 0.5 * height - correction,
          1.0 + 2.0 * correction / height};
}

// The MDR force of an elliptical indenter (A, B) at displacement δe and its contact radius
// (MDR, Popov & Heß 2015, for the ellipse of Part I): F = E A B / 4 (θ − sin θ cos θ), a = B/2 sin
// θ, θ = 2 asin √(δe/A), so cos θ = 1 − 2u and sin θ = 2 √(u (1 − u)) with u = δe/A. θ − sin θ cos
// θ = (x − sin x)/2 with x = 2θ loses its digits for small θ (both terms ≈ θ); there its series is
// taken.
struct MdrIndentation {
  double force;
  double contact_radius;
};
[[gnu::always_inline]] inline MdrIndentation mdr_indentation(double modulus, const MdrSide& s,
                                                             double displacement) {
  if (!(displacement > 0.0)) return {0.0, 0.0};
  const double u = displacement / s.height;
  const double root_u = std::sqrt(u);
  const double sine = 2.0 * std::sqrt(u * (1.0 - u));
  const double theta = 2.0 * std::asin(root_u);
  double shape;  // θ − sin θ cos θ
  if (u < 0.004) {
    const double x = 2.0 * theta, x2 = x * x;
    // (x − sin x)/2 = x³/12 − x⁵/240 + x⁷/10080 − x⁹/725760 + x¹¹/79833600 − x¹³/12454041600
    shape =
        x * x2 *
        (1.0 / 12.0 +
         x2 * (-1.0 / 240.0 +
               x2 * (1.0 / 10080.0 + x2 * (-1.0 / 725760.0 + x2 * (1.0 / 79833600.0 +
                                                                   x2 * (-1.0 / 12454041600.0))))));
  } else {
    shape = theta - sine * (1.0 - 2.0 * u);
  }
  return {0.25 * modulus * s.height * s.width * shape, 0.5 * s.width * sine};
}

// The energy the indenter gives back from δe to 0: ∫ F dδe = E A² B / 8 g(θ),
// g = sin θ − θ cos θ − sin³θ / 3, by its alternating series (g loses its digits for small θ).
double mdr_indentation_energy(double modulus, const MdrSide& s, double displacement);

struct MdrLaw {
  double yield_stress = 0.0;  // Y, Pa

  static constexpr std::string_view name = "mdr";
  static constexpr bool needs_pair_pressure = false;
  static constexpr std::array<HistoryField, 2> history_fields{
      {{"max_overlap", "m",
        "δm, the largest overlap of the contact: the flat's place and both "
        "sides' indenters"},
       {"yield_strain", "",
        "sY = δY / R, the strain at which the contact's sides yield (0: "
        "no side has yielded)"}}};

  struct Constants {
    double poisson_ratio = 0.0;  // ν of the solid (compliance-weighted between two materials)
    double yield_stress = 0.0;   // Y
  };

  static std::vector<OptionDoc> options();
  static MdrLaw read(const ConfigTable& interaction);
  void write_toml(std::string& out) const;
  void check(const std::string& where) const;
  Constants constants(const Material& a, const Material& b) const;
  static std::string describe(const ElasticPair& p, const Constants& k);

  // The stiffest unloading tangent over Hertz's at the same overlap, over a side's strains up to
  // 0.5 (timestep.cpp). Scale-free: a function of E/Y and ν only.
  static double stiffness_ratio(const ElasticPair& p, const Constants& k, double effective_radius);

  // The side overlaps at the pair's overlap δ: the geometric split at δm (the plane of the
  // intersection circle, δgi = δm (2 rj − δm) / (2 (ri + rj − δm)), capped at 0.95 of a radius
  // as LAMMPS does) moved linearly to the plastic overlaps (δpi, δpj) at δ = δpi + δpj.
  struct Sides {
    MdrSide first, second;
    double geometric_first, geometric_second;  // δgi at δm
    double overlap_first, overlap_second;      // δi at δ
  };
  [[gnu::always_inline]] static Sides pair_sides(double modulus, const Constants& k, double ri,
                                                 double rj, double overlap, double largest,
                                                 double& yield_strain) {
    double geometric_first = largest * (2.0 * rj - largest) / (2.0 * (ri + rj - largest));
    if (geometric_first > 0.95 * ri)
      geometric_first = 0.95 * ri;
    else if (largest - geometric_first > 0.95 * rj)
      geometric_first = largest - 0.95 * rj;
    const double geometric_second = largest - geometric_first;
    Sides s;
    s.geometric_first = geometric_first;
    s.geometric_second = geometric_second;
    s.first = mdr_side(modulus, k.poisson_ratio, k.yield_stress, ri, geometric_first, yield_strain);
    s.second =
        mdr_side(modulus, k.poisson_ratio, k.yield_stress, rj, geometric_second, yield_strain);
    const double travel =
        (overlap - largest) / (s.first.plastic_overlap + s.second.plastic_overlap - largest);
    s.overlap_first = geometric_first + (s.first.plastic_overlap - geometric_first) * travel;
    s.overlap_second = geometric_second + (s.second.plastic_overlap - geometric_second) * travel;
    return s;
  }

  // history = {δm, sY}, updated. A sphere pair (c.radius_second > 0) has two sides of modulus
  // 2 E* each (E/(1 − ν²) between equal materials); a wall (c.radius_second == 0) one side of
  // modulus E*. Damping on the stiffness S = 2 E* ā of the contact radius ā (the sides' mean),
  // which is the Hertz tangent 2 E* √(R* δ) while elastic; friction from the whole force.
  [[gnu::always_inline]] static NormalForce force(const ElasticPair& p, const Constants& k,
                                                  const ContactKinematics& c,
                                                  double /*sqrt_r_overlap*/,
                                                  double /*damping_root*/, double vn,
                                                  double* history) {
    if (c.overlap > history[0]) history[0] = c.overlap;
    const double largest = history[0];
    double force, radius;
    if (c.radius_second > 0.0) {
      const double modulus = 2.0 * p.effective_modulus;
      const Sides s =
          pair_sides(modulus, k, c.radius_first, c.radius_second, c.overlap, largest, history[1]);
      const MdrIndentation f = mdr_indentation(
          modulus, s.first, (s.overlap_first - s.first.plastic_overlap) / s.first.scale);
      const MdrIndentation g = mdr_indentation(
          modulus, s.second, (s.overlap_second - s.second.plastic_overlap) / s.second.scale);
      force = 0.5 * (f.force + g.force);
      radius = 0.5 * (f.contact_radius + g.contact_radius);
    } else {
      const double modulus = p.effective_modulus;
      const MdrSide s =
          mdr_side(modulus, k.poisson_ratio, k.yield_stress, c.radius_first, largest, history[1]);
      const MdrIndentation f =
          mdr_indentation(modulus, s, (c.overlap - s.plastic_overlap) / s.scale);
      force = f.force;
      radius = f.contact_radius;
    }
    const double gamma_n =
        p.damping_factor * std::sqrt(2.0 * p.effective_modulus * radius * c.effective_mass);
    const double normal_force = force - gamma_n * vn;
    return {normal_force, normal_force};
  }

  // The energy the contact gives back unloading to zero force at δ = δpi + δpj:
  // ½ Σ (1/ci) scale_i ∫ F_na dδe, ci = dδi/dδ = (δpi − δgi) / (δp − δm); a wall's one side whole.
  static double elastic_energy(const ElasticPair& p, const Constants& k, double effective_radius,
                               double radius_first, double radius_second, double overlap,
                               const double* history);
};

}  // namespace shapepress::simulate
