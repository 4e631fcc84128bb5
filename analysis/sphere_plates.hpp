#pragma once
// An elastic sphere pressed between two rigid plates: the force on the plates as a function of
// their total approach Δ, by Hertz and by Tatara's large-deformation correction (models.md,
// "Elastic sphere between plates at large deformation: Tatara").
#include <vector>

namespace shapepress::analysis {

struct ElasticSphere {
  double radius = 0.0;          // R [m]
  double youngs_modulus = 0.0;  // E [Pa]
  double poisson_ratio = 0.0;   // ν
  // E* = E/(1−ν²): sphere against a rigid plate.
  double effective_modulus() const;
  void check() const;  // InputError naming the field when R, E are not positive or ν ∉ [0, 0.5)
};

// Hertz, both plate contacts in series: F(Δ) = (√2/3) E* √R Δ^{3/2} (models.md).
double hertz_plate_force(const ElasticSphere& sphere, double total_approach);

// Hertz for one contact of a body whose principal radii of curvature there are R1 and R2 with a
// rigid plane (Johnson 1985, §4.2, elliptical contact): the eccentricity e of the contact ellipse
// solves R1/R2 = [E(e)/(1 − e²) − K(e)] / [K(e) − E(e)], then a² = δ (K − E)/(K e²) · 2R1,
// b = a √(1 − e²), p0 = δ E*/(b K), F = (2/3) π a b p0 ∝ δ^{3/2}. R1 = R2 = R gives
// (4/3) E* √R δ^{3/2}. `effective_modulus`: E* = E/(1 − ν²).
double hertz_elliptic_contact_force(double effective_modulus, double r1, double r2,
                                    double approach);

// Tatara (1989): approach of ONE plate contact under force F, Hertz minus the Boussinesq
// displacement of the opposite pole, w(F) = (3F/(4E*√R))^{2/3} − F(1+ν)/(πE)·[(1−ν)/√(a²+4R²)
// + 2R²/(a²+4R²)^{3/2}], a = (3FR/(4E*))^{1/3}.
double tatara_contact_approach(const ElasticSphere& sphere, double force);
// Total plate approach Δ(F) = 2 w(F).
double tatara_plate_approach(const ElasticSphere& sphere, double force);
// F(Δ): Δ(F) inverted with a bracketing root finder (the Hertz force is a lower bound, the
// bracket grows by doubling). Relative accuracy 1e-12 in F.
double tatara_plate_force(const ElasticSphere& sphere, double total_approach);

// Convenience for charts: forces on a list of approaches.
std::vector<double> hertz_plate_forces(const ElasticSphere& sphere,
                                       const std::vector<double>& approaches);
std::vector<double> tatara_plate_forces(const ElasticSphere& sphere,
                                        const std::vector<double>& approaches);

}  // namespace shapepress::analysis
