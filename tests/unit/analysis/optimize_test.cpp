#include "analysis/optimize.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/error.hpp"

namespace shapepress::analysis {
namespace {

double rosenbrock(const std::vector<double>& p) {
  const double x = p[0], y = p[1];
  return (1 - x) * (1 - x) + 100 * (y - x * x) * (y - x * x);
}

TEST(NelderMead, FindsTheRosenbrockMinimum) {
  SearchOptions options;
  options.max_evaluations = 5000;
  const MinimumResult r = minimize_nelder_mead(rosenbrock, {-1.2, 1.0}, options);
  EXPECT_TRUE(r.converged);
  // The tolerances (1e-10 on values and parameters) leave the point within ~1e-5 of (1, 1)
  // along Rosenbrock's flat valley.
  EXPECT_NEAR(r.parameters[0], 1.0, 1e-4);
  EXPECT_NEAR(r.parameters[1], 1.0, 1e-4);
  EXPECT_LT(r.value, 1e-8);
  EXPECT_LE(r.evaluations, 5000);
}

TEST(NelderMead, QuadraticInFourDimensions) {
  const std::vector<double> centre = {1.0, -2.0, 3.0, 0.5};
  auto bowl = [&](const std::vector<double>& p) {
    double s = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      s += (i + 1.0) * (p[i] - centre[i]) * (p[i] - centre[i]);
    return s;
  };
  const MinimumResult r = minimize_nelder_mead(bowl, {0.0, 0.0, 0.0, 0.0});
  ASSERT_TRUE(r.converged);
  for (std::size_t i = 0; i < centre.size(); ++i)
    EXPECT_NEAR(r.parameters[i], centre[i], 1e-4);  // parameter tolerance 1e-10, value 1e-10
}

TEST(BothSearches, HoldTheOptimumOnTheBoxEdgeWithoutLeavingTheBox) {
  // Unconstrained minimum at (1, 1) lies outside the box x ≤ 0.5: the answer is x = 0.5, and the
  // objective is never called outside the box.
  for (SearchMethod method : {SearchMethod::nelder_mead, SearchMethod::bobyqa}) {
    SCOPED_TRACE(search_method_name(method));
    SearchOptions options;
    options.lower = {-2.0, -2.0};
    options.upper = {0.5, 2.0};
    options.max_evaluations = 5000;
    // Nelder–Mead's default 1e-10 on values and parameters; BOBYQA's trust region to 1e-8.
    if (method == SearchMethod::bobyqa) options.parameter_tolerance = 1e-8;
    bool left_box = false;
    auto watched = [&](const std::vector<double>& p) {
      if (p[0] > 0.5 || p[0] < -2.0 || p[1] > 2.0 || p[1] < -2.0) left_box = true;
      return rosenbrock(p);
    };
    const MinimumResult r = method == SearchMethod::bobyqa
                                ? minimize_bobyqa(watched, {-1.0, 1.0}, options)
                                : minimize_nelder_mead(watched, {-1.0, 1.0}, options);
    EXPECT_TRUE(r.converged);
    EXPECT_FALSE(left_box);
    EXPECT_NEAR(r.parameters[0], 0.5, 1e-4);
    EXPECT_NEAR(r.parameters[1], 0.25, 1e-3);  // on x = 0.5 the minimum is y = x²
    EXPECT_DOUBLE_EQ(r.value, rosenbrock(r.parameters));
  }
}

TEST(NelderMead, ProgressCanStopTheSearchAndBudgetIsHonoured) {
  int calls = 0;
  SearchOptions options;
  options.progress = [&](int, double) { return ++calls < 5; };
  MinimumResult r = minimize_nelder_mead(rosenbrock, {-1.2, 1.0}, options);
  EXPECT_EQ(calls, 5);
  EXPECT_FALSE(r.converged);
  options.progress = nullptr;
  options.max_evaluations = 30;
  r = minimize_nelder_mead(rosenbrock, {-1.2, 1.0}, options);
  EXPECT_FALSE(r.converged);
  EXPECT_LE(r.evaluations, 30 + 3);  // checked per iteration; one costs at most n + 2 = 4
  options.lower = {0.0};
  options.upper = {1.0};
  EXPECT_THROW(minimize_nelder_mead(rosenbrock, {0.5, 0.5}, options), InputError);
}

TEST(NelderMead, BatchedSearchAsksTheSamePointsAndGroupsTheIndependentOnes) {
  // The batched search is the one search: the same trial points in the same order, the first
  // simplex (n + 1 points) handed over at once, and every batch but the shrinks one point.
  SearchOptions options;
  options.lower = {-2.0, -2.0};
  options.upper = {2.0, 2.0};
  options.max_evaluations = 300;
  std::vector<std::vector<double>> plain_points, batched_points;
  const MinimumResult plain = minimize_nelder_mead(
      [&](const std::vector<double>& p) {
        plain_points.push_back(p);
        return rosenbrock(p);
      },
      {-1.2, 1.0}, options);
  std::vector<std::size_t> batch_sizes;
  const MinimumResult batched = minimize_nelder_mead_batched(
      [&](const std::vector<std::vector<double>>& points) {
        batch_sizes.push_back(points.size());
        std::vector<double> values;
        for (const auto& p : points) {
          batched_points.push_back(p);
          values.push_back(rosenbrock(p));
        }
        return values;
      },
      {-1.2, 1.0}, options);
  EXPECT_EQ(batched_points, plain_points);
  EXPECT_EQ(batched.parameters, plain.parameters);
  EXPECT_EQ(batched.evaluations, plain.evaluations);
  ASSERT_FALSE(batch_sizes.empty());
  EXPECT_EQ(batch_sizes.front(), 3u);
  for (std::size_t k = 1; k < batch_sizes.size(); ++k)
    EXPECT_TRUE(batch_sizes[k] == 1u || batch_sizes[k] == 2u) << k;  // one trial, or a shrink
}

// BOBYQA (NLopt) under the options calibrate gives it: box bounds, a first step per parameter,
// the tolerances, the budget, the progress callback.
TEST(Bobyqa, NeedsFewerEvaluationsThanNelderMeadOnASmoothBowl) {
  // A quadratic is BOBYQA's own model: it needs about its 2n + 1 first points and a few steps,
  // where the simplex crawls; both to the same parameter tolerance.
  const std::vector<double> centre = {1.0, -2.0, 3.0, 0.5};
  int calls = 0;
  auto bowl = [&](const std::vector<double>& p) {
    ++calls;
    double s = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      s += (i + 1.0) * (p[i] - centre[i]) * (p[i] - centre[i]);
    return s;
  };
  SearchOptions options;
  options.lower = std::vector<double>(4, -10.0);
  options.upper = std::vector<double>(4, 10.0);
  options.initial_step = std::vector<double>(4, 1.0);
  options.parameter_tolerance = 1e-6;
  options.value_tolerance = 1e-12;
  const MinimumResult quadratic = minimize_bobyqa(bowl, {0.0, 0.0, 0.0, 0.0}, options);
  EXPECT_EQ(quadratic.evaluations, calls);
  const MinimumResult simplex = minimize_nelder_mead(bowl, {0.0, 0.0, 0.0, 0.0}, options);
  ASSERT_TRUE(quadratic.converged);
  ASSERT_TRUE(simplex.converged);
  for (std::size_t i = 0; i < centre.size(); ++i) {
    EXPECT_NEAR(quadratic.parameters[i], centre[i], 1e-5);
    EXPECT_NEAR(simplex.parameters[i], centre[i], 1e-5);
  }
  EXPECT_LT(2 * quadratic.evaluations, simplex.evaluations)
      << "BOBYQA " << quadratic.evaluations << ", Nelder-Mead " << simplex.evaluations;
}

TEST(Bobyqa, BudgetProgressErrorsAndBadOptions) {
  SearchOptions options;
  options.lower = {-2.0, -2.0};
  options.upper = {2.0, 2.0};
  options.max_evaluations = 12;
  MinimumResult r = minimize_bobyqa(rosenbrock, {-1.2, 1.0}, options);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.evaluations, 12);  // NLopt counts every call: the budget is exact
  int calls = 0;
  options.max_evaluations = 2000;
  options.progress = [&](int, double) { return ++calls < 7; };
  r = minimize_bobyqa(rosenbrock, {-1.2, 1.0}, options);
  EXPECT_EQ(calls, 7);
  EXPECT_EQ(r.evaluations, 7);
  EXPECT_FALSE(r.converged);
  options.progress = nullptr;
  // An exception in the objective crosses NLopt's C code and reaches the caller.
  EXPECT_THROW(minimize_bobyqa(
                   [](const std::vector<double>&) -> double { throw ComputationError("diverged"); },
                   {0.0, 0.0}, options),
               ComputationError);
  EXPECT_THROW(minimize_bobyqa(rosenbrock, {0.0, 0.0}, SearchOptions{}), InputError);  // no box
  EXPECT_THROW(search_method_named("simplex"), InputError);
  EXPECT_EQ(search_method_named("nelder-mead"), SearchMethod::nelder_mead);
  EXPECT_EQ(search_method_name(search_method_named("bobyqa")), "bobyqa");
}

TEST(Bobyqa, TheBatchedEntryHandsItOnePointAtATime) {
  SearchOptions options;
  options.lower = {-2.0, -2.0};
  options.upper = {2.0, 2.0};
  options.max_evaluations = 60;
  std::vector<std::size_t> batch_sizes;
  const MinimumResult r = minimize(
      SearchMethod::bobyqa,
      [&](const std::vector<std::vector<double>>& points) {
        batch_sizes.push_back(points.size());
        std::vector<double> values;
        for (const auto& p : points)
          values.push_back(rosenbrock(p));
        return values;
      },
      {-1.2, 1.0}, options);
  EXPECT_EQ(batch_sizes, std::vector<std::size_t>(static_cast<std::size_t>(r.evaluations), 1u));
}

TEST(Brent, MinimisesAParabolaAndACosine) {
  ScalarMinimum m = minimize_brent([](double x) { return (x - 0.3) * (x - 0.3) + 2; }, -1, 4);
  // x tolerance 1e-8 (default), and √ε·|x| is the floor at a flat minimum.
  EXPECT_NEAR(m.x, 0.3, 2e-8);
  EXPECT_NEAR(m.value, 2.0, 1e-14);
  // Golden section alone needs log(5/4e-8)/log(1.618) ≈ 39 evaluations to close the bracket.
  EXPECT_LT(m.evaluations, 30);
  m = minimize_brent([](double x) { return std::cos(x); }, 2.0, 5.0);
  EXPECT_NEAR(m.x, std::numbers::pi, 1e-7);  // √ε·π ≈ 5e-8 floor
}

TEST(Brent, FindsRootsInABracketAndRejectsABadOne) {
  const double root = find_root_brent([](double x) { return x * x * x - 2.0; }, 0.0, 3.0, 1e-14);
  EXPECT_NEAR(root, std::cbrt(2.0), 1e-13);
  EXPECT_THROW(find_root_brent([](double x) { return x * x + 1.0; }, -1.0, 1.0, 1e-12),
               ComputationError);
}

}  // namespace
}  // namespace shapepress::analysis
