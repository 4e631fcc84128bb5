#pragma once
// Numbers of a punch (compaction) curve: peak stress, solid fraction at the peak, minimum gap,
// elastic recovery, Heckel and Kawakita fits, work of compaction and of unloading (models.md,
// "Compaction analysis"). Plain vectors in, plain structs out; reading punch.csv is in runs.hpp.
#include <cmath>
#include <vector>

namespace shapepress::analysis {

// punch.csv's phase column (scenarios/punch.hpp): the run goes load, hold, unload, release,
// done; release (the punch following the bed's spring-back at near-zero stress) came later.
enum class PunchPhase : int { load = 0, hold = 1, unload = 2, done = 3, release = 4 };

// One record per row of punch.csv, SI units.
struct PunchCurve {
  std::vector<double> time;            // s
  std::vector<double> gap;             // H, punch-to-bottom distance [m]
  std::vector<double> top_force;       // N, on the punch
  std::vector<double> stress;          // P = F_top / A_die [Pa]
  std::vector<double> solid_fraction;  // D = V_solid/(A_die H)
  std::vector<int> phase;              // PunchPhase
  double reference_gap = 0.0;          // H0 of the strain [m]
  double die_area = 0.0;               // m²
  // From the run's run.json, where the run states them (compact since mass scaling).
  double density_scale = 1.0;         // run.density_scale: particle mass × this
  double max_kinetic_to_work = NAN;   // the quasi-static figures (QuasiStaticCheck)
  double mean_force_imbalance = NAN;  // mean |top − bottom| / top over the loading
  void check() const;                 // InputError on sizes, H0 ≤ 0, no loading rows
};

struct LinearFit {
  double slope = 0.0;
  double intercept = 0.0;
  double r_squared = 0.0;
  int points = 0;
};
// Least squares y = slope·x + intercept; ComputationError with fewer than 2 distinct x.
LinearFit fit_line(const std::vector<double>& x, const std::vector<double>& y);

// Which part of the loading branch the fits use, as fractions of the peak stress. Heckel's plot
// is curved at low pressure (rearrangement) and straight once particles deform, so by default
// the fit takes the upper part of the loading branch; Kawakita's P/C is linear from low pressure
// on, so its window starts low (C → 0 at P → 0 makes P/C noisy below ~5 % of the peak).
struct FitWindows {
  double heckel_lower = 0.3, heckel_upper = 1.0;
  double kawakita_lower = 0.05, kawakita_upper = 1.0;
  void check() const;  // InputError unless 0 ≤ lower < upper ≤ 1
};

struct HeckelFit {              // ln(1/(1−D)) = K P + A
  double k = 0.0;               // 1/Pa
  double a = 0.0;               // −
  double yield_pressure = 0.0;  // Py = 1/K [Pa]
  double r_squared = 0.0;
  int points = 0;
  double stress_lower = 0.0, stress_upper = 0.0;  // the window used [Pa]
};

// C = (V0 − V)/V0 with V0 the gap of the first row, where loading starts (the powder's apparent
// volume as the punch meets it).
struct KawakitaFit {  // P/C = P/a + 1/(a b), C = (V0 − V)/V0
  double a = 0.0;     // limiting volume reduction, −
  double b = 0.0;     // 1/Pa
  double r_squared = 0.0;
  int points = 0;
  double stress_lower = 0.0, stress_upper = 0.0;
};

struct CompactionMetrics {
  double reference_gap = 0.0;           // H0 [m]
  double peak_stress = 0.0;             // Pa
  double peak_force = 0.0;              // N
  double solid_fraction_at_peak = 0.0;  //
  double strain_at_peak = 0.0;          // (H0 − H)/H0 at the peak
  double minimum_gap = 0.0;             // H_min [m]
  bool unloaded = false;                // an unload phase was recorded
  double unloaded_gap = 0.0;            // H at the end of unloading [m]
  double elastic_recovery = 0.0;        // (H_unloaded − H_min)/H_min
  double work_of_compaction = 0.0;      // ∫F dh over loading (and hold) [J]
  double work_of_unloading = 0.0;       // ∫F dh over unloading [J] (energy given back)
  double density_scale = 1.0;           // the run's mass scaling
  double max_kinetic_to_work = NAN;     // the run's quasi-static figures
  double mean_force_imbalance = NAN;
  HeckelFit heckel;
  KawakitaFit kawakita;
};

// Rows of the loading phase (before the first hold/unload row), where the fits are made.
std::vector<std::size_t> loading_rows(const PunchCurve& curve);

HeckelFit fit_heckel(const PunchCurve& curve, double stress_lower, double stress_upper);
KawakitaFit fit_kawakita(const PunchCurve& curve, double stress_lower, double stress_upper);

// Work done on the powder by the punch, ∫F d(−H) by trapezoids over rows [first, last]:
// positive while the gap closes, negative while it opens (the powder pushing the punch back).
double punch_work(const PunchCurve& curve, std::size_t first, std::size_t last);

CompactionMetrics analyse_compaction(const PunchCurve& curve, const FitWindows& windows = {});

}  // namespace shapepress::analysis
