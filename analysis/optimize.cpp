#include "analysis/optimize.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <numeric>
#include <utility>

#include <fmt/format.h>
#include <nlopt.h>

#include "common/error.hpp"

namespace shapepress::analysis {
namespace {

using Point = std::vector<double>;

struct Box {
  const std::vector<double>& lower;
  const std::vector<double>& upper;
  void clamp(Point& x) const {
    for (std::size_t i = 0; i < lower.size(); ++i)
      x[i] = std::clamp(x[i], lower[i], upper[i]);
  }
};

Point combine(const Point& a, const Point& b, double t) {  // a + t (b − a)
  Point r(a.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    r[i] = a[i] + t * (b[i] - a[i]);
  return r;
}

void check_options(std::string_view search, const SearchOptions& options, std::size_t n) {
  if (n == 0) throw InputError(fmt::format("{}: no parameters to optimise", search));
  const bool bounded = !options.lower.empty() || !options.upper.empty();
  if (bounded && (options.lower.size() != n || options.upper.size() != n))
    throw InputError(fmt::format("{}: {} parameters but {} lower and {} upper bounds", search, n,
                                 options.lower.size(), options.upper.size()));
  for (std::size_t i = 0; i < options.lower.size(); ++i)
    if (!(options.lower[i] < options.upper[i]))
      throw InputError(fmt::format("{}: parameter {} has lower bound {} >= upper {}", search, i,
                                   options.lower[i], options.upper[i]));
  if (!options.initial_step.empty() && options.initial_step.size() != n)
    throw InputError(fmt::format("{}: {} parameters but {} initial steps", search, n,
                                 options.initial_step.size()));
}

double default_step(double x) {
  return x != 0.0 ? 0.1 * std::abs(x) : 0.1;
}

// The first simplex: the start and one step along each axis (stepping backwards when the
// forward step would leave the box).
std::vector<Point> initial_simplex(const Point& start, const SearchOptions& options) {
  const std::size_t n = start.size();
  std::vector<Point> simplex(n + 1, start);
  for (std::size_t i = 0; i < n; ++i) {
    double step = options.initial_step.empty() ? default_step(start[i]) : options.initial_step[i];
    if (!options.upper.empty() && start[i] + step > options.upper[i]) step = -step;
    simplex[i + 1][i] += step;
  }
  return simplex;
}

}  // namespace

MinimumResult minimize_nelder_mead(const Objective& objective, Point start,
                                   const SearchOptions& options) {
  const BatchObjective one_by_one = [&](const std::vector<Point>& points) {
    std::vector<double> values;
    for (const Point& x : points)
      values.push_back(objective(x));
    return values;
  };
  return minimize_nelder_mead_batched(one_by_one, std::move(start), options);
}

MinimumResult minimize_nelder_mead_batched(const BatchObjective& objective, Point start,
                                           const SearchOptions& options) {
  const std::size_t n = start.size();
  check_options("Nelder-Mead", options, n);
  const Box box{options.lower, options.upper};
  box.clamp(start);
  MinimumResult result;
  // Clamps the points into the box and evaluates them; a failed trial (NaN) is a bad point,
  // not a crash.
  auto evaluate_all = [&](std::vector<Point>& points) {
    for (Point& x : points)
      box.clamp(x);
    result.evaluations += static_cast<int>(points.size());
    std::vector<double> values = objective(points);
    if (values.size() != points.size())
      throw ComputationError(
          fmt::format("Nelder-Mead: {} values for {} points", values.size(), points.size()));
    for (double& v : values)
      if (std::isnan(v)) v = HUGE_VAL;
    return values;
  };
  auto evaluate = [&](Point& x) {
    std::vector<Point> one = {x};
    const double v = evaluate_all(one).front();
    x = one.front();
    return v;
  };
  std::vector<Point> simplex = initial_simplex(start, options);
  std::vector<double> values = evaluate_all(simplex);
  std::vector<std::size_t> order(n + 1);
  while (true) {
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
    const std::size_t best = order.front(), worst = order.back(), second = order[n - 1];
    double size = 0.0;
    for (std::size_t i = 0; i <= n; ++i)
      for (std::size_t k = 0; k < n; ++k)
        size = std::max(size, std::abs(simplex[i][k] - simplex[best][k]));
    if (values[worst] - values[best] <= options.value_tolerance &&
        size <= options.parameter_tolerance) {
      result.converged = true;
      break;
    }
    if (result.evaluations >= options.max_evaluations) break;
    if (options.progress && !options.progress(result.evaluations, values[best])) break;

    Point centroid(n, 0.0);
    for (std::size_t i = 0; i <= n; ++i)
      if (i != worst)
        for (std::size_t k = 0; k < n; ++k)
          centroid[k] += simplex[i][k] / static_cast<double>(n);
    Point reflected = combine(centroid, simplex[worst], -1.0);
    const double fr = evaluate(reflected);
    if (fr < values[best]) {
      Point expanded = combine(centroid, simplex[worst], -2.0);
      const double fe = evaluate(expanded);
      if (fe < fr) {
        simplex[worst] = expanded, values[worst] = fe;
      } else {
        simplex[worst] = reflected, values[worst] = fr;
      }
      continue;
    }
    if (fr < values[second]) {
      simplex[worst] = reflected, values[worst] = fr;
      continue;
    }
    // Contraction: outside when the reflection improved on the worst point, inside otherwise.
    const bool outside = fr < values[worst];
    Point contracted = combine(centroid, outside ? reflected : simplex[worst], 0.5);
    const double fc = evaluate(contracted);
    if (fc < (outside ? fr : values[worst])) {
      simplex[worst] = contracted, values[worst] = fc;
      continue;
    }
    std::vector<Point> shrunk;  // towards the best point, all at once
    for (std::size_t i = 0; i <= n; ++i)
      if (i != best) shrunk.push_back(combine(simplex[best], simplex[i], 0.5));
    const std::vector<double> shrunk_values = evaluate_all(shrunk);
    for (std::size_t i = 0, k = 0; i <= n; ++i)
      if (i != best) simplex[i] = shrunk[k], values[i] = shrunk_values[k], ++k;
  }
  const std::size_t best =
      static_cast<std::size_t>(std::min_element(values.begin(), values.end()) - values.begin());
  result.parameters = simplex[best];
  result.value = values[best];
  return result;
}

namespace {

// NLopt calls back through C: the state of one search, and any exception the objective threw,
// carried across it.
struct BobyqaSearch {
  const Objective& objective;
  const SearchOptions& options;
  nlopt_opt opt = nullptr;
  MinimumResult result;
  bool stopped = false;  // by the progress callback
  std::exception_ptr error;
};

double bobyqa_value(unsigned n, const double* x, double* /*gradient*/, void* data) {
  auto& search = *static_cast<BobyqaSearch*>(data);
  try {
    Point point(x, x + n);
    Box{search.options.lower, search.options.upper}.clamp(point);  // rounding at a bound
    double value = search.objective(point);
    if (std::isnan(value)) value = HUGE_VAL;
    MinimumResult& result = search.result;
    ++result.evaluations;
    if (result.parameters.empty() || value < result.value)
      result.parameters = point, result.value = value;
    if (search.options.progress && !search.options.progress(result.evaluations, result.value)) {
      search.stopped = true;
      nlopt_force_stop(search.opt);
    }
    return value;
  } catch (...) {
    search.error = std::current_exception();
    nlopt_force_stop(search.opt);
    return HUGE_VAL;
  }
}

}  // namespace

std::string_view search_method_name(SearchMethod method) {
  return method == SearchMethod::bobyqa ? "bobyqa" : "nelder-mead";
}

SearchMethod search_method_named(std::string_view name) {
  for (SearchMethod method : {SearchMethod::bobyqa, SearchMethod::nelder_mead})
    if (name == search_method_name(method)) return method;
  throw InputError(fmt::format("search method '{}': expected bobyqa or nelder-mead", name));
}

MinimumResult minimize_bobyqa(const Objective& objective, Point start,
                              const SearchOptions& options) {
  const std::size_t n = start.size();
  check_options("BOBYQA", options, n);
  if (options.lower.empty()) throw InputError("BOBYQA: needs lower and upper bounds");
  Box{options.lower, options.upper}.clamp(start);
  Point step = options.initial_step;
  if (step.empty())
    for (double x : start)
      step.push_back(default_step(x));
  const auto unsigned_n = static_cast<unsigned>(n);
  std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(
      nlopt_create(NLOPT_LN_BOBYQA, unsigned_n), &nlopt_destroy);
  if (!opt) throw ComputationError("BOBYQA: NLopt could not create the search");
  BobyqaSearch search{objective, options, opt.get(), {}, false, nullptr};
  const Point parameter_tolerance(n, options.parameter_tolerance);
  if (nlopt_set_lower_bounds(opt.get(), options.lower.data()) < 0 ||
      nlopt_set_upper_bounds(opt.get(), options.upper.data()) < 0 ||
      nlopt_set_min_objective(opt.get(), bobyqa_value, &search) < 0 ||
      nlopt_set_initial_step(opt.get(), step.data()) < 0 ||
      nlopt_set_xtol_abs(opt.get(), parameter_tolerance.data()) < 0 ||
      nlopt_set_maxeval(opt.get(), options.max_evaluations) < 0)
    throw InputError(fmt::format("BOBYQA: NLopt refused the options ({})",
                                 nlopt_get_errmsg(opt.get()) ? nlopt_get_errmsg(opt.get()) : "?"));
  double value = 0.0;
  const nlopt_result outcome = nlopt_optimize(opt.get(), start.data(), &value);
  if (search.error) std::rethrow_exception(search.error);
  if (outcome == NLOPT_INVALID_ARGS || outcome == NLOPT_OUT_OF_MEMORY ||
      (outcome == NLOPT_FAILURE && search.result.parameters.empty()))
    throw ComputationError(
        fmt::format("BOBYQA: NLopt failed ({}{}{})", nlopt_result_to_string(outcome),
                    nlopt_get_errmsg(opt.get()) ? ": " : "",
                    nlopt_get_errmsg(opt.get()) ? nlopt_get_errmsg(opt.get()) : ""));
  // The best point evaluated (NLopt's answer is one of them); converged when a tolerance ended
  // the search, not the budget, the progress callback or round-off.
  search.result.converged =
      !search.stopped &&
      (outcome == NLOPT_SUCCESS || outcome == NLOPT_FTOL_REACHED || outcome == NLOPT_XTOL_REACHED);
  return search.result;
}

MinimumResult minimize(SearchMethod method, const BatchObjective& objective, Point start,
                       const SearchOptions& options) {
  if (method == SearchMethod::nelder_mead)
    return minimize_nelder_mead_batched(objective, std::move(start), options);
  const Objective one = [&](const Point& x) {
    const std::vector<double> values = objective({x});
    if (values.size() != 1)
      throw ComputationError(fmt::format("BOBYQA: {} values for one point", values.size()));
    return values.front();
  };
  return minimize_bobyqa(one, std::move(start), options);
}

ScalarMinimum minimize_brent(const std::function<double(double)>& f, double lower, double upper,
                             double x_tolerance, int max_evaluations) {
  if (!(lower < upper))
    throw InputError(fmt::format("Brent minimisation: empty interval [{}, {}]", lower, upper));
  const double golden = 0.5 * (3.0 - std::sqrt(5.0));  // 0.381966…
  double a = lower, b = upper;
  double x = a + golden * (b - a), w = x, v = x;
  double fx = f(x), fw = fx, fv = fx;
  int evaluations = 1;
  double d = 0.0, e = 0.0;  // last step and the one before it
  while (evaluations < max_evaluations) {
    const double middle = 0.5 * (a + b);
    const double tol1 = 1e-12 * std::abs(x) + 0.5 * x_tolerance, tol2 = 2.0 * tol1;
    if (std::abs(x - middle) <= tol2 - 0.5 * (b - a)) break;
    bool parabolic = false;
    if (std::abs(e) > tol1) {  // try a parabola through x, w, v
      double r = (x - w) * (fx - fv), q = (x - v) * (fx - fw);
      double p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) p = -p;
      q = std::abs(q);
      if (std::abs(p) < std::abs(0.5 * q * e) && p > q * (a - x) && p < q * (b - x)) {
        e = d;
        d = p / q;
        const double u = x + d;
        if (u - a < tol2 || b - u < tol2) d = x < middle ? tol1 : -tol1;
        parabolic = true;
      }
    }
    if (!parabolic) {  // golden section into the larger part
      e = (x < middle ? b : a) - x;
      d = golden * e;
    }
    const double u = std::abs(d) >= tol1 ? x + d : x + (d > 0 ? tol1 : -tol1);
    const double fu = f(u);
    ++evaluations;
    if (fu <= fx) {
      (u < x ? b : a) = x;
      v = w, fv = fw, w = x, fw = fx, x = u, fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || w == x) {
        v = w, fv = fw, w = u, fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u, fv = fu;
      }
    }
  }
  return {x, fx, evaluations};
}

double find_root_brent(const std::function<double(double)>& f, double lower, double upper,
                       double x_tolerance, int max_evaluations) {
  double a = lower, b = upper, fa = f(a), fb = f(b);
  if (fa == 0.0) return a;
  if (fb == 0.0) return b;
  if ((fa > 0.0) == (fb > 0.0) || std::isnan(fa) || std::isnan(fb))
    throw ComputationError(
        fmt::format("root finder: f({}) = {} and f({}) = {} do not bracket a root", a, fa, b, fb));
  double c = a, fc = fa, d = b - a, e = d;
  for (int evaluations = 2; evaluations < max_evaluations; ++evaluations) {
    if ((fb > 0.0) == (fc > 0.0)) c = a, fc = fa, d = e = b - a;
    if (std::abs(fc) < std::abs(fb)) a = b, b = c, c = a, fa = fb, fb = fc, fc = fa;
    const double tol = 2e-16 * std::abs(b) + 0.5 * x_tolerance;
    const double m = 0.5 * (c - b);
    if (std::abs(m) <= tol || fb == 0.0) return b;
    if (std::abs(e) >= tol && std::abs(fa) > std::abs(fb)) {  // secant or inverse quadratic
      double p, q, s = fb / fa;
      if (a == c) {
        p = 2.0 * m * s, q = 1.0 - s;
      } else {
        const double qa = fa / fc, r = fb / fc;
        p = s * (2.0 * m * qa * (qa - r) - (b - a) * (r - 1.0));
        q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
      }
      if (p > 0.0) q = -q;
      p = std::abs(p);
      if (2.0 * p < std::min(3.0 * m * q - std::abs(tol * q), std::abs(e * q))) {
        e = d, d = p / q;
      } else {
        d = m, e = m;  // interpolation would leave the bracket: bisect
      }
    } else {
      d = m, e = m;
    }
    a = b, fa = fb;
    b += std::abs(d) > tol ? d : (m > 0.0 ? tol : -tol);
    fb = f(b);
  }
  throw ComputationError(fmt::format("root finder: no convergence in {} evaluations on [{}, {}]",
                                     max_evaluations, lower, upper));
}

}  // namespace shapepress::analysis
