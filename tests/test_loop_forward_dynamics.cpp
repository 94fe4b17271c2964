// O(n) forward dynamics with sub-systems (runtime/include/mbgen/algorithm/loop_forward_dynamics.hpp)
// against the O(n^3) reference with Lagrange multipliers (forward_dynamics_kkt), on every
// closed-loop description: the parallel_legs models, the mechanisms and the Lola biped.
// Seeded random consistent states (loops closed by Newton, v = G vy) and joint forces; the two
// agree to 1e-10 relative (||a - b|| / max(1, ||b||)), as DESIGN.md asks: both are exact
// methods in double, so only round-off amplified by the conditioning of the closed system
// separates them.
#include <gtest/gtest.h>

#include <random>

#include "malloc_guard.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

class LoopForwardDynamicsTest : public ::testing::TestWithParam<LoopCase> {
 protected:
  LoopForwardDynamicsTest() : d(load_loop_case(GetParam())), model(d.model), data(model), reference_data(model), ws(model), reference(model) {}
  gen::Description d;
  const Model& model;
  Data<double> data, reference_data;
  LoopWorkspace<double> ws;
  ConstrainedDynamicsWorkspace<double> reference;
};

TEST_P(LoopForwardDynamicsTest, EqualsTheKktReference) {
  ASSERT_FALSE(model.subsystems.empty());
  std::mt19937_64 rng(53);
  double worst = 0, worst_independent = 0;
  int states = 0;
  for (int trial = 0; trial < 60 && states < 20; ++trial) {
    VecX<double> q, v;
    if (!consistent_state(model, d.assembly.q, rng, 0.05, q, v)) continue;  // Newton may fail far out (wl16_like)
    const VecX<double> tau = random_vector<double>(model.nv(), rng, 5.0);
    ASSERT_EQ(forward_dynamics_loops<double>(model, data, q, v, tau), LoopSolveStatus::Converged);
    const VecX<double> expected = forward_dynamics_kkt<double>(model, reference_data, reference, q, v, tau);
    worst = std::max(worst, relative_error(data.ddq, expected));
    // The same from the independent velocities alone (the form the generator traces).
    const VecX<double> qdd = data.ddq;
    VecX<double> vy(static_cast<int>(ws.independent.size()));
    for (int i = 0; i < vy.size(); ++i) vy[i] = v[ws.independent[static_cast<std::size_t>(i)]];
    forward_dynamics_loops_independent<double>(model, data, ws.independent, q, vy, tau);
    worst_independent = std::max(worst_independent, relative_error(data.ddq, qdd));
    ++states;
  }
  std::printf("  %s: O(n) vs KKT worst relative error %.2e over %d states\n", GetParam().name.c_str(), worst, states);
  EXPECT_GE(states, 15);
  EXPECT_LT(worst, 1e-10);
  EXPECT_LT(worst_independent, 1e-12);
}

TEST_P(LoopForwardDynamicsTest, DoesNotAllocate) {
  std::mt19937_64 rng(59);
  VecX<double> q, v;
  bool found = false;
  for (int attempt = 0; attempt < 20 && !found; ++attempt) found = consistent_state(model, d.assembly.q, rng, 0.05, q, v);
  ASSERT_TRUE(found);
  const VecX<double> tau = random_vector<double>(model.nv(), rng);
  {
    MallocGuard guard;
    forward_dynamics_loops<double>(model, data, q, v, tau);
    EXPECT_EQ(guard.count(), 0u);
  }
  EXPECT_TRUE(data.ddq.allFinite());
}

TEST(LoopForwardDynamicsDeadPoint, SliderDrivenSliderCrankReportsSingular) {
  // tests/data/mechanisms/slider_crank_slider_driven.yaml: the slider is independent; at the
  // stroke end (slider_joint = 0.06) crank and rod are in line, Phi_z is singular and the
  // accelerations are undefined: the status says so (and no silent NaN status of Converged).
  gen::LoadOptions options;
  options.extras_file = MBGEN_TEST_DATA "/mechanisms/slider_crank_slider_driven.yaml";
  const gen::Description d = gen::load_description(MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.urdf", options);
  const Model& model = d.model;
  Data<double> data(model);
  LoopWorkspace<double> ws(model);
  VecX<double> q = VecX<double>::Zero(model.nq());
  const int slider = model.joint(*model.find_joint("slider_joint")).idx_q;
  const VecX<double> v = VecX<double>::Zero(model.nv()), tau = VecX<double>::Ones(model.nv());
  for (double x : {0.02, 0.04, 0.05}) {  // warm-started approach: regular
    q[slider] = x;
    ASSERT_EQ(solve_dependent_coordinates<double>(model, data, ws, q), LoopSolveStatus::Converged);
    EXPECT_EQ(forward_dynamics_loops<double>(model, data, q, v, tau), LoopSolveStatus::Converged) << x;
    EXPECT_TRUE(data.ddq.allFinite());
  }
  q[slider] = 0.06;
  solve_dependent_coordinates<double>(model, data, ws, q);
  EXPECT_EQ(forward_dynamics_loops<double>(model, data, q, v, tau), LoopSolveStatus::Singular);
}

INSTANTIATE_TEST_SUITE_P(ClosedLoops, LoopForwardDynamicsTest, ::testing::ValuesIn(loop_cases()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace mbgen::test
