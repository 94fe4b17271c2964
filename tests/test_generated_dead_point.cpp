// The generated closure_positions reports a dead point instead of returning nonsense: a
// slider-crank driven by its slider (tests/data/mechanisms/slider_crank_slider_driven.yaml,
// generated as slider_crank_slider_driven) has its dead point at the stroke end
// (slider_joint = 0.06 m), where crank and rod are in line and Phi_z is singular, and no closed
// pose beyond it. Status singular there in double and in float, as the generic runtime's
// (test_closure_positions); q stays finite. The runtime's options per scalar
// (default_closure_options<S>, which the simulator's generic backends take) are the generated ones.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mbgen/algorithm/closure_positions.hpp"
#include "mbgen/sim/simulator.hpp"
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

// The simulator through the dead point on the generated backend (SimulatorOptions::continuation;
// the generic backend's run is test_simulator's SimulatorContinuation): the slider pushed by 50 N
// to its stroke end, where the generated close_loops reports the dead point; the loop turns soft
// (the generated closure_constraints), the crank turns on, the slider comes back, and every span
// names rod_slider and closes again.
TEST(GeneratedDeadPoint, TheSimulatorContinuesThroughIt) {
  mbgen::sim::SimulatorOptions o;
  o.step = 1e-3;
  o.continuation.enabled = true;
  mbgen::sim::Simulator<robot::Backend> sim{robot::Backend{}, o};
  std::vector<double> q(robot::nq, 0.0), v(robot::nv, 0.0);
  const int slider = q_index("slider_joint");
  ASSERT_EQ(sim.set_state(q.data(), v.data()), 0);  // closed from the slider at 0
  sim.set_controller([slider](double, const double*, const double*, double* tau) {
    for (int i = 0; i < robot::nv; ++i) tau[i] = 0;
    tau[slider] = 50;  // N, towards the stroke end
  });
  double slider_max = -1, slider_min_after = 1;
  bool passed = false;
  while (sim.time() < 2.0 - 1e-9) {
    const mbgen::sim::StepStatus s = sim.step();
    ASSERT_TRUE(mbgen::sim::advanced(s)) << mbgen::sim::to_string(s) << " at " << sim.time();
    passed = passed || s == mbgen::sim::StepStatus::continued;
    slider_max = std::max(slider_max, sim.q()[slider]);
    if (passed) slider_min_after = std::min(slider_min_after, sim.q()[slider]);
  }
  const auto& spans = sim.continuation_spans();
  ASSERT_FALSE(spans.empty());
  for (const mbgen::sim::ContinuationSpan& span : spans) {
    EXPECT_EQ(span.subsystem, 0);
    EXPECT_STREQ(sim.backend().subsystem_name(span.subsystem), "rod_slider");
    EXPECT_GT(span.steps, 0);
    EXPECT_LT(span.max_violation, 1e-3);
  }
  EXPECT_GT(spans.front().end, spans.front().begin);
  EXPECT_GT(slider_max, 0.0599);
  EXPECT_LT(slider_min_after, 0.03) << "the slider comes back";
  std::printf("[ continue ] generated slider-crank 2 s: %zu spans (first %.4f .. %.4f s), %ld soft steps, largest violation %.3g m\n",
              spans.size(), spans.front().begin, spans.front().end, sim.statistics().soft_steps,
              sim.statistics().max_loop_violation);
}

}  // namespace
