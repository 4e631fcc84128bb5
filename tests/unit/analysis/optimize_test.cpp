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
  NelderMeadOptions options;
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

TEST(NelderMead, BoundsHoldTheOptimumOnTheBoxEdge) {
  // Unconstrained minimum at (1, 1) lies outside the box x ≤ 0.5: the answer is x = 0.5, and the
  // objective is never called outside the box.
  NelderMeadOptions options;
  options.lower = {-2.0, -2.0};
  options.upper = {0.5, 2.0};
  options.max_evaluations = 5000;
  bool left_box = false;
  auto watched = [&](const std::vector<double>& p) {
    if (p[0] > 0.5 || p[0] < -2.0 || p[1] > 2.0 || p[1] < -2.0) left_box = true;
    return rosenbrock(p);
  };
  const MinimumResult r = minimize_nelder_mead(watched, {-1.0, 1.0}, options);
  EXPECT_FALSE(left_box);
  EXPECT_NEAR(r.parameters[0], 0.5, 1e-4);
  EXPECT_NEAR(r.parameters[1], 0.25, 1e-3);  // on x = 0.5 the minimum is y = x²
}

TEST(NelderMead, ProgressCanStopTheSearchAndBudgetIsHonoured) {
  int calls = 0;
  NelderMeadOptions options;
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
