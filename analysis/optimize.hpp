#pragma once
// Small derivative-free optimisers for calibration (fit model parameters so a run matches a
// reference curve): in n dimensions with box bounds, Powell's BOBYQA (NLopt's) and Nelder–Mead
// (ours, which hands independent points over together); golden/Brent minimisation and Brent root
// finding in one dimension. Free functions, plain inputs and outputs, an optional progress
// callback, so the caller owns logging and stopping.
#include <functional>
#include <string_view>
#include <vector>

namespace shapepress::analysis {

using Objective = std::function<double(const std::vector<double>&)>;
// Values of several independent points, one per point in order: the caller may compute them side
// by side (a calibration runs one simulation per point on its own thread).
using BatchObjective = std::function<std::vector<double>(const std::vector<std::vector<double>>&)>;

// How a bounded search in n dimensions is run.
//   bobyqa       Powell's BOBYQA (2009), NLopt's NLOPT_LN_BOBYQA: a quadratic model of the
//                objective from 2n + 1 points, minimised in a trust region that shrinks to the
//                parameter tolerance. Needs bounds. One point at a time.
//   nelder_mead  the simplex search below; its independent points (first simplex, shrinks) go
//                to a BatchObjective together.
enum class SearchMethod { bobyqa, nelder_mead };
// "bobyqa" or "nelder-mead", as the options and the config say them.
std::string_view search_method_name(SearchMethod method);
// InputError naming the text and the two names otherwise.
SearchMethod search_method_named(std::string_view name);

struct SearchOptions {
  std::vector<double> lower;         // bounds, empty = unbounded; else one per parameter
  std::vector<double> upper;         //
  std::vector<double> initial_step;  // first simplex edge / trust-region radius per parameter;
                                     // empty = 10 % of |x0| (or 0.1)
  // Nelder–Mead stops when the simplex values span less than value_tolerance and the simplex is
  // smaller than parameter_tolerance along every axis; BOBYQA when its trust region has shrunk
  // below parameter_tolerance along every axis (NLopt's value test would stop it at the first
  // trial within value_tolerance of the best, long before the model has settled on a rough
  // objective such as a DEM run's).
  double value_tolerance = 1e-10;
  double parameter_tolerance = 1e-10;
  int max_evaluations = 2000;
  // Called after each iteration (BOBYQA: each evaluation) with (evaluations so far, best value);
  // return false to stop.
  std::function<bool(int, double)> progress;
};

struct MinimumResult {
  std::vector<double> parameters;
  double value = 0.0;
  int evaluations = 0;
  bool converged = false;  // tolerances met (false: evaluation budget or progress stopped it)
};

// Nelder–Mead (Lagarias et al. 1998 coefficients: reflection 1, expansion 2, contraction ½,
// shrink ½). Bounds are honoured by clamping every trial point into the box, so the objective is
// never called outside it.
MinimumResult minimize_nelder_mead(const Objective& objective, std::vector<double> start,
                                   const SearchOptions& options = {});
// The same search, handing the points that do not depend on each other to `objective` together:
// the first simplex (n + 1 points) and a shrink (n points); a reflection, expansion or
// contraction depends on the last value and goes alone. The trial points and the result are
// those of minimize_nelder_mead.
MinimumResult minimize_nelder_mead_batched(const BatchObjective& objective,
                                           std::vector<double> start,
                                           const SearchOptions& options = {});

// BOBYQA through NLopt (bounds required). The objective is never called outside the box; a NaN
// value counts as +inf, as for Nelder–Mead.
MinimumResult minimize_bobyqa(const Objective& objective, std::vector<double> start,
                              const SearchOptions& options);

// The search `method` names; BOBYQA hands the batch objective one point at a time.
MinimumResult minimize(SearchMethod method, const BatchObjective& objective,
                       std::vector<double> start, const SearchOptions& options);

struct ScalarMinimum {
  double x = 0.0;
  double value = 0.0;
  int evaluations = 0;
};

// Brent's minimisation (golden section with parabolic steps) on [lower, upper]; absolute
// tolerance in x. Finds a local minimum; the global one when f is unimodal on the interval.
// f is flat at a minimum (f changes as δx²), so x cannot be located better than about
// √ε·|x| ≈ 1.5e-8·|x|: tolerances below that only cost evaluations.
ScalarMinimum minimize_brent(const std::function<double(double)>& f, double lower, double upper,
                             double x_tolerance = 1e-8, int max_evaluations = 200);

// Brent's root finder on a bracket [lower, upper] with f(lower)·f(upper) ≤ 0; ComputationError
// if the bracket does not straddle a root. Tolerance absolute in x.
double find_root_brent(const std::function<double(double)>& f, double lower, double upper,
                       double x_tolerance, int max_evaluations = 200);

}  // namespace shapepress::analysis
