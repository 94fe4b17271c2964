// The generated closure_positions reports a dead point instead of returning nonsense: a
// slider-crank driven by its slider (tests/data/mechanisms/slider_crank_slider_driven.yaml,
// generated as slider_crank_slider_driven) has its dead point at the stroke end
// (slider_joint = 0.06 m), where crank and rod are in line and Phi_z is singular, and no closed
// pose beyond it. Same status as the generic runtime (test_closure_positions), for both scalars;
// q stays finite.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

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
  }
  q[slider] = S(0.06);
  const robot::ClosureResult<S> at_dead_point = robot::closure_positions(q.data());
  EXPECT_EQ(at_dead_point.status, robot::ClosureStatus::singular) << "pivot ratio " << at_dead_point.pivot_ratio;
  for (S x : q) EXPECT_TRUE(std::isfinite(x));
  q[slider] = S(0.07);  // beyond the stroke: no closed pose
  const robot::ClosureResult<S> beyond = robot::closure_positions(q.data());
  EXPECT_NE(beyond.status, robot::ClosureStatus::converged);
  for (S x : q) EXPECT_TRUE(std::isfinite(x));
}

TEST(GeneratedDeadPoint, DoubleReportsSingularAtTheStrokeEnd) { approach_the_stroke_end<double>(); }
TEST(GeneratedDeadPoint, FloatReportsSingularAtTheStrokeEnd) { approach_the_stroke_end<float>(); }

}  // namespace
