// The generated closure_positions reports a dead point instead of returning nonsense: a
// slider-crank driven by its slider (tests/data/mechanisms/slider_crank_slider_driven.yaml,
// generated as slider_crank_slider_driven) has its dead point at the stroke end
// (slider_joint = 0.06 m), where crank and rod are in line and Phi_z is singular, and no closed
// pose beyond it. Status singular there in double and in float, as the generic runtime's
// (test_closure_positions); q stays finite. The runtime's options per scalar
// (default_closure_options<S>, which the simulator's generic backends take) are the generated ones.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mbgen/algorithm/closure_positions.hpp"
#include "slider_crank_slider_driven.hpp"

namespace robot = slider_crank_slider_driven;

namespace {

int q_index(const char* joint) {
  for (int i = 0; i < robot::nq; ++i)
    if (std::string(robot::joint_names[i]) == joint) return i;  // 1-DoF joints: q index = joint index
  return -1;
}

template <typename S> void approach_the_stroke_end() {
  ASSERT_EQ(robot::ny, 1);
  const int slider = q_index("slider_joint");
  ASSERT_EQ(robot::independent_v_index[0], slider);
  std::vector<S> q(robot::nq, S(0));
  for (double x : {0.01, 0.02, 0.03, 0.04, 0.05}) {  // warm-started approach: regular
    q[slider] = S(x);
    const robot::ClosureResult<S> r = robot::closure_positions(q.data());
    EXPECT_EQ(r.status, robot::ClosureStatus::converged) << x << ": residual " << r.residual;
    EXPECT_GT(r.pivot_ratio, S(0.01)) << x;
    EXPECT_GT(r.relative_pivot_ratio, S(0.3)) << x;  // 0.37 at 0.05: far above either dead_point_tolerance
  }
  q[slider] = S(0.06);
  const robot::ClosureResult<S> at_dead_point = robot::closure_positions(q.data());
  // double: the pivot ratio falls below singular_tolerance (1e-5) on the way in. float: Newton
  // closes to 2e-6 while ~2e-3 in pivot ratio from the dead point (above singular_tolerance,
  // 1e-3, which regular poses of other robots need), but relative to the assembled pose's 0.42
  // that is ~4.5e-3, below dead_point_tolerance (2e-2): singular too (closure_options_float).
  EXPECT_EQ(at_dead_point.status, robot::ClosureStatus::singular)
      << "pivot ratio " << at_dead_point.pivot_ratio << ", relative " << at_dead_point.relative_pivot_ratio;
  EXPECT_LT(at_dead_point.pivot_ratio, S(1e-2));
  EXPECT_LT(at_dead_point.relative_pivot_ratio, robot::closure_options_float.dead_point_tolerance);
  const char* status = at_dead_point.status == robot::ClosureStatus::singular    ? "singular"
                       : at_dead_point.status == robot::ClosureStatus::converged ? "converged"
                                                                                 : "not_converged";
  std::printf("[ dead pt  ] %s: %s after %d steps, pivot ratio %.2g (relative %.2g), residual %.2g\n",
              sizeof(S) == 8 ? "double" : "float", status, at_dead_point.iterations, static_cast<double>(at_dead_point.pivot_ratio),
              static_cast<double>(at_dead_point.relative_pivot_ratio), static_cast<double>(at_dead_point.residual));
  for (S x : q) EXPECT_TRUE(std::isfinite(x));
  q[slider] = S(0.07);  // beyond the stroke: no closed pose
  const robot::ClosureResult<S> beyond = robot::closure_positions(q.data());
  EXPECT_NE(beyond.status, robot::ClosureStatus::converged);
  for (S x : q) EXPECT_TRUE(std::isfinite(x));
}

TEST(GeneratedDeadPoint, NanSliderIsNotConverged) {
  std::vector<double> q(robot::nq, 0.0);
  q[static_cast<std::size_t>(robot::independent_v_index[0])] = std::nan("");
  const robot::ClosureResult<double> r = robot::closure_positions(q.data());
  EXPECT_EQ(r.status, robot::ClosureStatus::not_converged);
  EXPECT_EQ(r.iterations, 0);
}

TEST(GeneratedDeadPoint, DoubleReportsSingularAtTheStrokeEnd) { approach_the_stroke_end<double>(); }
TEST(GeneratedDeadPoint, FloatReportsSingularAtTheStrokeEnd) { approach_the_stroke_end<float>(); }

template <typename S> void expect_same_options(const mbgen::ClosureOptions& runtime, const robot::ClosureOptions<S>& generated) {
  EXPECT_EQ(S(runtime.tolerance), generated.tolerance);
  EXPECT_EQ(runtime.max_iterations, generated.max_iterations);
  EXPECT_EQ(S(runtime.max_step), generated.max_step);
  EXPECT_EQ(S(runtime.singular_tolerance), generated.singular_tolerance);
  EXPECT_EQ(S(runtime.dead_point_tolerance), generated.dead_point_tolerance);
}

TEST(GeneratedDeadPoint, RuntimeOptionsPerScalarAreTheGeneratedOnes) {
  expect_same_options(mbgen::default_closure_options<double>(), robot::closure_options_double);
  expect_same_options(mbgen::default_closure_options<float>(), robot::closure_options_float);
}

}  // namespace
