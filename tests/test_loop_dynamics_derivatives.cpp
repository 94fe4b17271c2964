// The closed system's derivatives in its independent coordinates
// (runtime/include/mbgen/algorithm/loop_dynamics_derivatives.hpp) against independent derivatives,
// on every closed-loop description of the suite (loop_cases: the parallel_legs models, the
// mechanisms, Lola, Cassie from MJCF, every closure type) and on Lola with a floating base:
//  - forward-mode dual numbers pushed through the generic forward_dynamics_loops_independent and
//    inverse_dynamics_independent (which recompute the closure's maps G and g, the Givens factor
//    of Phi_z and the articulated-body recursion with sub-systems in dual arithmetic), the
//    configuration moved along the tangent T e_c of the closed set: 1e-10, the forward
//    dynamics' weighted by M_y (weighted_relative below);
//  - central differences through closure_positions (y moved, Newton closes z again): 1e-6;
//  - the tangent: Phi_q T = 0;
//  - without loops, the tree's derivatives (aba_derivatives.hpp) to 1e-12;
//  - Singular at a dead point; no allocation.
#include <gtest/gtest.h>

#include <random>

#include "autodiff_reference.hpp"
#include "derivative_errors.hpp"
#include "malloc_guard.hpp"
#include "mbgen/algorithm/loop_dynamics_derivatives.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

VecX<double> independent_part(const Model& model, const VecX<double>& full) {
  const std::vector<int>& y = model.structure().independent_v;
  VecX<double> out(static_cast<int>(y.size()));
  for (std::size_t i = 0; i < y.size(); ++i) out[static_cast<int>(i)] = full[y[i]];
  return out;
}

/// A consistent state of d's model drawn around its assembled pose (up to 20 draws).
bool some_consistent_state(const gen::Description& d, std::mt19937_64& rng, VecX<double>& q, VecX<double>& v) {
  for (int attempt = 0; attempt < 20; ++attempt)
    if (consistent_state(d.model, d.assembly.q, rng, 0.05, q, v)) return true;
  return false;
}

struct WorstErrors {
  double dy = 0, dyd = 0, dtau = 0, id_dy = 0, id_dyd = 0, tangent = 0;
};

/// The analytic derivatives at (q, yd, tau) and at (q, yd, ydd) against dual numbers.
WorstErrors compare_with_duals(const Model& model, const VecX<double>& q, const VecX<double>& yd, const VecX<double>& tau,
                               const VecX<double>& ydd) {
  const int ny = model.structure().num_independent(), nv = model.nv();
  Data<double> data(model);
  LoopDynamicsDerivatives<double> ld(model);
  WorstErrors worst;
  EXPECT_EQ(forward_dynamics_loops_derivatives<double>(model, data, ld, q, yd, tau), ClosureStatus::Converged);
  const LoopDynamicsDerivatives<double> fd = ld;
  EXPECT_EQ(inverse_dynamics_loops_derivatives<double>(model, data, ld, q, yd, ydd), ClosureStatus::Converged);
  worst.tangent = (closure_jacobian<double>(model, data, q) * ld.T).cwiseAbs().maxCoeff();

  Data<Dual> dual(model);
  const VecX<Dual> q_plain = seeded_vector(q), yd_plain = seeded_vector(yd), tau_plain = seeded_vector(tau), ydd_plain = seeded_vector(ydd);
  MatX<double> dy(ny, ny), dyd(ny, ny), dtau(ny, nv), id_dy(ny, ny), id_dyd(ny, ny);
  for (int c = 0; c < ny; ++c) {
    const VecX<Dual> q_c = seeded_configuration_along(model, q, fd.T.col(c)), yd_c = seeded_vector(yd, c);
    forward_dynamics_loops_independent<Dual>(model, dual, q_c, yd_plain, tau_plain);
    dy.col(c) = independent_part(model, derivative_part(dual.ddq));
    forward_dynamics_loops_independent<Dual>(model, dual, q_plain, yd_c, tau_plain);
    dyd.col(c) = independent_part(model, derivative_part(dual.ddq));
    id_dy.col(c) = derivative_part(inverse_dynamics_independent<Dual>(model, dual, q_c, yd_plain, ydd_plain));
    id_dyd.col(c) = derivative_part(inverse_dynamics_independent<Dual>(model, dual, q_plain, yd_c, ydd_plain));
  }
  for (int k = 0; k < nv; ++k) {
    forward_dynamics_loops_independent<Dual>(model, dual, q_plain, yd_plain, seeded_vector(tau, k));
    dtau.col(k) = independent_part(model, derivative_part(dual.ddq));
  }
  worst.dy = weighted_relative(fd.M_y, fd.dydd_dy, dy);
  worst.dyd = weighted_relative(fd.M_y, fd.dydd_dyd, dyd);
  worst.dtau = weighted_relative(fd.M_y, fd.dydd_dtau, dtau);
  worst.id_dy = max_relative(ld.dtauy_dy, id_dy);
  worst.id_dyd = max_relative(ld.dtauy_dyd, id_dyd);
  // The values are the functions' own.
  Data<double> other(model);
  forward_dynamics_loops_independent<double>(model, other, q, yd, tau);
  EXPECT_LT(relative_error(fd.ydd, independent_part(model, other.ddq)), 1e-12);
  EXPECT_LT(relative_error(ld.tau_y, inverse_dynamics_independent<double>(model, other, q, yd, ydd)), 1e-12);
  return worst;
}

/// Prints the worst errors and holds them to the stated tolerances: 1e-10 (the derivatives against
/// dual numbers), 1e-12 (Phi_q T).
void expect_exact(const std::string& name, const WorstErrors& e) {
  std::printf("  %s: dydd/dy %.1e, dydd/dyd %.1e, dydd/dtau %.1e, dtau_y/dy %.1e, dtau_y/dyd %.1e, |Phi_q T| %.1e\n", name.c_str(), e.dy,
              e.dyd, e.dtau, e.id_dy, e.id_dyd, e.tangent);
  EXPECT_LT(e.dy, 1e-10);
  EXPECT_LT(e.dyd, 1e-10);
  EXPECT_LT(e.dtau, 1e-10);
  EXPECT_LT(e.id_dy, 1e-10);
  EXPECT_LT(e.id_dyd, 1e-10);
  EXPECT_LT(e.tangent, 1e-12);
}

class LoopDynamicsDerivativesTest : public ::testing::TestWithParam<LoopCase> {};

TEST_P(LoopDynamicsDerivativesTest, MatchDualNumbersAlongTheClosedSet) {
  const gen::Description d = load_loop_case(GetParam());
  const Model& model = d.model;
  ASSERT_FALSE(model.subsystems.empty());
  std::mt19937_64 rng(541);
  WorstErrors worst;
  int states = 0;
  for (int trial = 0; trial < 20 && states < 3; ++trial) {
    VecX<double> q, v;
    if (!consistent_state(model, d.assembly.q, rng, 0.05, q, v)) continue;
    const int ny = model.structure().num_independent();
    const VecX<double> yd = independent_part(model, v);
    const VecX<double> tau = random_vector<double>(model.nv(), rng, 5.0), ydd = random_vector<double>(ny, rng, 5.0);
    const WorstErrors e = compare_with_duals(model, q, yd, tau, ydd);
    worst.dy = std::max(worst.dy, e.dy), worst.dyd = std::max(worst.dyd, e.dyd), worst.dtau = std::max(worst.dtau, e.dtau);
    worst.id_dy = std::max(worst.id_dy, e.id_dy), worst.id_dyd = std::max(worst.id_dyd, e.id_dyd);
    worst.tangent = std::max(worst.tangent, e.tangent);
    ++states;
  }
  EXPECT_EQ(states, 3);
  expect_exact(GetParam().name, worst);
}

// Central differences in y with Newton closing z again, not through T: the closed set itself.
// h = 1e-5 rad, 1e-6 m on a prismatic coordinate (Lola's knee and ankle nuts travel
// millimetres): truncation h^2 against round-off over h, Newton closing to 1e-14 rather than its
// default 1e-12, by close_loops, whose every iterate is a full Newton step: its last one lands
// far below the tolerance. closure_positions may stop at an iterate checked by its residual
// alone, just below the tolerance (detail::residual_check_predicted), which over 2h is too
// coarse here (robot_delta: 1.4e-5 against central differences).
TEST_P(LoopDynamicsDerivativesTest, MatchCentralDifferencesThroughClosurePositions) {
  const gen::Description d = load_loop_case(GetParam());
  const Model& model = d.model;
  std::mt19937_64 rng(542);
  VecX<double> q, v;
  ASSERT_TRUE(some_consistent_state(d, rng, q, v));
  const int ny = model.structure().num_independent();
  const VecX<double> yd = independent_part(model, v), tau = random_vector<double>(model.nv(), rng, 5.0);
  Data<double> data(model), other(model);
  LoopDynamicsDerivatives<double> ld(model);
  ASSERT_EQ(forward_dynamics_loops_derivatives<double>(model, data, ld, q, yd, tau), ClosureStatus::Converged);
  ClosureOptions tight;
  tight.tolerance = 1e-14;
  MatX<double> want(ny, ny), got(ny, ny);
  int columns = 0;
  for (int c = 0; c < ny; ++c) {
    const int i = model.q_index_of_v(model.structure().independent_v[static_cast<std::size_t>(c)]);
    if (i < 0) continue;  // a floating base's: the dual-number test covers them
    const double h = model.joint(model.joint_of_v(model.structure().independent_v[static_cast<std::size_t>(c)])).type == JointType::Prismatic ? 1e-6 : 1e-5;
    VecX<double> plus = q, minus = q, v_plus = v, v_minus = v;
    plus[i] += h;
    minus[i] -= h;
    ASSERT_EQ(close_loops<double>(model, other, plus, v_plus, tight).status, ClosureStatus::Converged);
    ASSERT_EQ(close_loops<double>(model, other, minus, v_minus, tight).status, ClosureStatus::Converged);
    forward_dynamics_loops_independent<double>(model, other, plus, yd, tau);
    const VecX<double> ydd_plus = independent_part(model, other.ddq);
    forward_dynamics_loops_independent<double>(model, other, minus, yd, tau);
    want.col(columns) = (ydd_plus - independent_part(model, other.ddq)) / (2 * h);
    got.col(columns) = ld.dydd_dy.col(c);
    ++columns;
  }
  ASSERT_GT(columns, 0);
  const double error = weighted_relative(ld.M_y, got.leftCols(columns), want.leftCols(columns));
  std::printf("  %s: dydd/dy against central differences %.1e\n", GetParam().name.c_str(), error);
  EXPECT_LT(error, 1e-6);
}

TEST_P(LoopDynamicsDerivativesTest, AllocateNothing) {
  const gen::Description d = load_loop_case(GetParam());
  const Model& model = d.model;
  std::mt19937_64 rng(543);
  VecX<double> q, v;
  ASSERT_TRUE(some_consistent_state(d, rng, q, v));
  const VecX<double> yd = independent_part(model, v), tau = random_vector<double>(model.nv(), rng);
  Data<double> data(model);
  LoopDynamicsDerivatives<double> ld(model);
  MallocGuard guard;
  forward_dynamics_loops_derivatives<double>(model, data, ld, q, yd, tau);
  inverse_dynamics_loops_derivatives<double>(model, data, ld, q, yd, ld.ydd);
  EXPECT_EQ(guard.count(), 0u);
}

// The solves run along the factor's chains (the model's elimination tree of M_y): every entry of
// the dense L^T D L factor off them must be exactly zero, or the solves would drop it.
TEST_P(LoopDynamicsDerivativesTest, TheFactorIsZeroOffItsChains) {
  const gen::Description d = load_loop_case(GetParam());
  const Model& model = d.model;
  std::mt19937_64 rng(547);
  VecX<double> q, v;
  ASSERT_TRUE(some_consistent_state(d, rng, q, v));
  Data<double> data(model);
  LoopDynamicsDerivatives<double> ld(model);
  forward_dynamics_loops_derivatives<double>(model, data, ld, q, independent_part(model, v), random_vector<double>(model.nv(), rng));
  const int ny = model.structure().num_independent();
  int on_chains = 0;
  for (int k = 0; k < ny; ++k) {
    std::vector<bool> chain(static_cast<std::size_t>(k), false);
    for (int i = ld.y_parent[static_cast<std::size_t>(k)]; i >= 0; i = ld.y_parent[static_cast<std::size_t>(i)]) chain[static_cast<std::size_t>(i)] = true, ++on_chains;
    for (int i = 0; i < k; ++i) {
      if (!chain[static_cast<std::size_t>(i)]) {
        EXPECT_EQ(ld.M_y_factor(k, i), 0.0) << k << ", " << i;
      }
    }
  }
  std::printf("  %s: ny %d, %d factor entries on the chains of %d below the diagonal\n", GetParam().name.c_str(), ny, on_chains, ny * (ny - 1) / 2);
}

INSTANTIATE_TEST_SUITE_P(LoopModels, LoopDynamicsDerivativesTest, ::testing::ValuesIn(loop_cases()),
                         [](const ::testing::TestParamInfo<LoopCase>& info) { return info.param.name; });

TEST(LoopDynamicsDerivatives, LolaWithAFloatingBaseMatchesDualNumbers) {
  const gen::Description d = load_lola();
  const Model& model = d.model;
  std::mt19937_64 rng(544);
  VecX<double> q, v;
  ASSERT_TRUE(some_consistent_state(d, rng, q, v));
  const int ny = model.structure().num_independent();
  const VecX<double> yd = independent_part(model, v), tau = random_vector<double>(model.nv(), rng, 5.0), ydd = random_vector<double>(ny, rng, 5.0);
  expect_exact("lola floating", compare_with_duals(model, q, yd, tau, ydd));
}

// Without loops T = I and the closed system is the tree: the same numbers as aba_derivatives.hpp.
TEST(LoopDynamicsDerivatives, WithoutLoopsTheyAreTheTreesDerivatives) {
  const Model model = load_tree(shared_robot("hyq/hyq_no_sensors.urdf"), gen::BaseType::Floating);
  std::mt19937_64 rng(545);
  const VecX<double> q = random_configuration<double>(model, rng), v = random_vector<double>(model.nv(), rng, 2.0),
                     tau = random_vector<double>(model.nv(), rng, 10.0);
  Data<double> data(model);
  LoopDynamicsDerivatives<double> ld(model);
  DynamicsDerivatives<double> tree(model);
  ASSERT_EQ(forward_dynamics_loops_derivatives<double>(model, data, ld, q, v, tau), ClosureStatus::Converged);
  forward_dynamics_derivatives<double>(model, data, tree, q, v, tau);
  EXPECT_LT(max_relative(ld.dydd_dy, tree.dddq_dq), 1e-12);
  EXPECT_LT(max_relative(ld.dydd_dyd, tree.dddq_dv), 1e-12);
  EXPECT_LT(max_relative(ld.dydd_dtau, tree.Minv), 1e-12);
  // And the factor's elimination tree is the tree's own: each coordinate's velocity parent.
  for (int k = 0; k < model.nv(); ++k) EXPECT_EQ(ld.y_parent[static_cast<std::size_t>(k)], model.velocity_parent(k)) << k;
}

// At the slider-driven slider-crank's stroke end crank and rod are in line: Phi_z is singular and
// the derivatives, like the accelerations, are not defined: the status says so.
TEST(LoopDynamicsDerivatives, ReportSingularAtADeadPoint) {
  gen::LoadOptions options;
  options.extras_file = MBGEN_TEST_DATA "/mechanisms/slider_crank_slider_driven.yaml";
  const gen::Description d = gen::load_description(MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.urdf", options);
  const Model& model = d.model;
  Data<double> data(model);
  LoopDynamicsDerivatives<double> ld(model);
  VecX<double> q = VecX<double>::Zero(model.nq());
  const int slider = model.joint(*model.find_joint("slider_joint")).idx_q;
  const int ny = model.structure().num_independent();
  const VecX<double> yd = VecX<double>::Zero(ny), tau = VecX<double>::Ones(model.nv());
  for (double x : {0.02, 0.04, 0.05}) {
    q[slider] = x;
    ASSERT_EQ(closure_positions<double>(model, data, q).status, ClosureStatus::Converged);
    EXPECT_EQ(forward_dynamics_loops_derivatives<double>(model, data, ld, q, yd, tau), ClosureStatus::Converged) << x;
  }
  q[slider] = 0.06;
  closure_positions<double>(model, data, q);
  EXPECT_EQ(forward_dynamics_loops_derivatives<double>(model, data, ld, q, yd, tau), ClosureStatus::Singular);
  EXPECT_EQ(inverse_dynamics_loops_derivatives<double>(model, data, ld, q, yd, yd), ClosureStatus::Singular);
}

}  // namespace
}  // namespace mbgen::test
