// Closure constraints (runtime/include/mbgen/algorithm/closure.hpp): residual, Jacobian and bias
// against finite differences, on every closed-loop description (test_support.hpp, loop_cases).
//
// Tolerances. Central differences with step h have truncation error O(h^2) and round-off
// O(eps / h); with h = 1e-6 on unit-sized quantities both stay below 1e-9, so 1e-7 relative.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <random>

#include "test_support.hpp"

namespace mbgen::test {
namespace {

class ClosureTest : public ::testing::TestWithParam<LoopCase> {
 protected:
  ClosureTest() : d(load_loop_case(GetParam())), model(d.model), data(model) {}
  gen::Description d;
  const Model& model;
  Data<double> data;
};

TEST_P(ClosureTest, AssembledPoseIsClosed) {
  EXPECT_LT(closure_residual<double>(model, data, d.assembly.q).cwiseAbs().maxCoeff(), 1e-12);
}

TEST_P(ClosureTest, JacobianMatchesFiniteDifferencesAtClosedPoses) {
  // Phi_q is the exact derivative of Phi on the closed set (closure.hpp): test there, at the
  // assembled pose and at random consistent states.
  std::mt19937_64 rng(11);
  const double h = 1e-6;
  for (int trial = 0; trial < 4; ++trial) {
    VecX<double> q = d.assembly.q, v;
    if (trial > 0) {
      ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
    }
    const MatX<double> Phi_q = closure_jacobian<double>(model, data, q);
    for (int dir = 0; dir < 3; ++dir) {
      const VecX<double> dq = random_vector<double>(model.nv(), rng);
      const CentralPair p = central_pair(model, q, dq, h);
      const VecX<double> plus = closure_residual<double>(model, data, p.plus);
      const VecX<double> minus = closure_residual<double>(model, data, p.minus);
      const VecX<double> fd = (plus - minus) / (2 * h);
      EXPECT_LT(relative_error(Phi_q * dq, fd), 1e-7) << "trial " << trial;
    }
  }
}

TEST_P(ClosureTest, LinearRowsAreExactDerivativesAnywhere) {
  // Away from the closed set only the position rows of weld / point / revolute / universal
  // closures are exact derivatives; the zero pose of parallel_legs is far from closed.
  std::mt19937_64 rng(12);
  const double h = 1e-6;
  const VecX<double> q = neutral_configuration<double>(model);
  const MatX<double> Phi_q = closure_jacobian<double>(model, data, q);
  const VecX<double> dq = random_vector<double>(model.nv(), rng);
  const CentralPair p = central_pair(model, q, dq, h);
  const VecX<double> plus = closure_residual<double>(model, data, p.plus);  // copies: data.Phi is reused
  const VecX<double> minus = closure_residual<double>(model, data, p.minus);
  const VecX<double> fd = (plus - minus) / (2 * h);
  const VecX<double> analytic = Phi_q * dq;
  for (const LoopClosure& c : model.closures) {
    if (c.type == ClosureType::Prismatic) continue;
    // The first three rows are the linear ones; a coupling has one row, linear in q. (Three rows
    // of a coupling read past the residual: the sanitized subset's heap-buffer-overflow.)
    const int linear_rows = std::min(3, c.rows());
    EXPECT_LT(relative_error(analytic.segment(c.row_offset, linear_rows), fd.segment(c.row_offset, linear_rows)), 1e-7)
        << c.name;
  }
}

TEST_P(ClosureTest, BiasIsMinusTheRateOfTheConstraintVelocity) {
  // gamma = -(d/dt Phi_q) v along q(t) = q (+) t v (qdd = 0): central differences in t, at any
  // state (closed or not), since gamma differentiates the velocity rows as defined.
  std::mt19937_64 rng(13);
  const double h = 1e-6;
  for (int trial = 0; trial < 3; ++trial) {
    VecX<double> q = d.assembly.q, v = random_vector<double>(model.nv(), rng);
    if (trial == 1) {
      ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
    }
    if (trial == 2) q = random_configuration<double>(model, rng);
    const VecX<double> gamma = closure_bias<double>(model, data, q, v);
    const CentralPair p = central_pair(model, q, v, h);
    const VecX<double> plus = closure_jacobian<double>(model, data, p.plus) * v;
    const VecX<double> minus = closure_jacobian<double>(model, data, p.minus) * v;
    const VecX<double> fd = -(plus - minus) / (2 * h);
    EXPECT_LT(relative_error(gamma, fd), 1e-6) << "trial " << trial;
  }
}

TEST_P(ClosureTest, OnePassGivesTheThreeFunctionsRows) {
  // closure_constraints runs the kinematics once for the three: the same operations as each
  // function's own pass, so the same bits, closed pose or not.
  std::mt19937_64 rng(15);
  for (int trial = 0; trial < 2; ++trial) {
    const VecX<double> q = trial == 0 ? d.assembly.q : random_configuration<double>(model, rng);
    const VecX<double> v = random_vector<double>(model.nv(), rng);
    const VecX<double> Phi = closure_residual<double>(model, data, q);
    const MatX<double> Phi_q = closure_jacobian<double>(model, data, q);
    const VecX<double> gamma = closure_bias<double>(model, data, q, v);
    Data<double> fresh(model);
    closure_constraints<double>(model, fresh, q, v);
    EXPECT_EQ(fresh.Phi, Phi) << "trial " << trial;
    EXPECT_EQ(fresh.Phi_q, Phi_q) << "trial " << trial;
    EXPECT_EQ(fresh.gamma, gamma) << "trial " << trial;
  }
  // The kept rows: as many as the dependent coordinates, independent at the assembled pose.
  closure_constraints<double>(model, data, d.assembly.q, VecX<double>::Zero(model.nv()));
  MatX<double> kept(num_kept_closure_rows(model), model.nv());
  int r = 0;
  for (const SubSystem& s : model.subsystems)
    for (int row : s.rows) kept.row(r++) = data.Phi_q.row(row);
  EXPECT_EQ(num_kept_closure_rows(model), model.nv() - static_cast<int>(model.structure().independent_v.size()));
  EXPECT_EQ(Eigen::FullPivLU<MatX<double>>(kept).rank(), kept.rows());
}

TEST_P(ClosureTest, FloatTwinMatchesDouble) {
  // The runtime is templated on the scalar: float gives the same rows to single-precision
  // round-off (unit round-off 6e-8, recursions of depth < 40: 1e-4 relative to the terms' size).
  std::mt19937_64 rng(14);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
  Data<float> data_f(model);
  const VecX<float> qf = q.cast<float>(), vf = v.cast<float>();
  const VecX<double> Phi_q_v = closure_jacobian<double>(model, data, q) * v;
  const VecX<double> gamma = closure_bias<double>(model, data, q, v);
  const VecX<float> Phi_q_v_f = closure_jacobian<float>(model, data_f, qf) * vf;
  const VecX<float> gamma_f = closure_bias<float>(model, data_f, qf, vf);
  EXPECT_LT((closure_jacobian<float>(model, data_f, qf).cast<double>() - closure_jacobian<double>(model, data, q)).norm(),
            1e-4 * std::max(1.0, data.Phi_q.norm()));
  EXPECT_LT((gamma_f.cast<double>() - gamma).norm(), 1e-4 * std::max(1.0, gamma.norm()));
  EXPECT_LT(closure_residual<float>(model, data_f, qf).cast<double>().cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LT(Phi_q_v_f.cast<double>().norm(), 1e-4 * std::max(1.0, v.norm()));
  (void)Phi_q_v;
}

TEST_P(ClosureTest, RowsDependOnTheCyclesAlone) {
  // Every row is computed in its cycle's top frame with the top at rest (closure.hpp), so the
  // joints of no cycle (a floating base, a hip above a knee loop) do not enter at all: moving
  // them, positions and velocities, leaves Phi, Phi_q and gamma the same bit for bit. Computed
  // through the world frame, their poses cancelled only to round-off.
  std::vector<bool> on_cycle(static_cast<std::size_t>(model.num_bodies()), false);
  for (const LoopClosure& c : model.closures) {
    const BodyIndex top = closure_top(model, c);  // a coupling's: above both of its joints
    for (BodyIndex b : {c.body_a, c.body_b})
      for (; b != top; b = model.body(b).parent) on_cycle[static_cast<std::size_t>(b.value())] = true;
  }
  // ModelStructure::cycle_bodies, which Newton places (closure_positions), is the same set.
  std::vector<BodyIndex> cycle_bodies;
  for (int k = 1; k < model.num_bodies(); ++k)
    if (on_cycle[static_cast<std::size_t>(k)]) cycle_bodies.push_back(BodyIndex(k));
  EXPECT_EQ(model.structure().cycle_bodies, cycle_bodies);
  std::mt19937_64 rng(15);
  int moved = 0;
  for (int trial = 0; trial < 4; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng), v = random_vector<double>(model.nv(), rng);
    VecX<double> q2 = random_configuration<double>(model, rng), v2 = random_vector<double>(model.nv(), rng);
    for (int k = 1; k < model.num_bodies(); ++k) {
      const Joint& joint = model.joint(model.body(BodyIndex(k)).joint);
      if (!on_cycle[static_cast<std::size_t>(k)]) {
        moved += trial == 0 ? joint.nv : 0;
        continue;
      }
      q2.segment(joint.idx_q, joint.nq) = q.segment(joint.idx_q, joint.nq);
      v2.segment(joint.idx_v, joint.nv) = v.segment(joint.idx_v, joint.nv);
    }
    const VecX<double> Phi = closure_residual<double>(model, data, q);
    const MatX<double> Phi_q = closure_jacobian<double>(model, data, q);
    const VecX<double> gamma = closure_bias<double>(model, data, q, v);
    EXPECT_EQ(closure_residual<double>(model, data, q2), Phi) << "trial " << trial;
    EXPECT_EQ(closure_jacobian<double>(model, data, q2), Phi_q) << "trial " << trial;
    EXPECT_EQ(closure_bias<double>(model, data, q2, v2), gamma) << "trial " << trial;
  }
  RecordProperty("coordinates_off_the_cycles", moved);
}

INSTANTIATE_TEST_SUITE_P(ClosedLoops, ClosureTest, ::testing::ValuesIn(loop_cases()),
                         [](const auto& info) { return info.param.name; });

TEST(ClosureFrames, MechanismsCloseAtTheirNominalPose) {
  // robots/mechanisms/README.md: each mechanism closes at q = 0 to round-off (<= 3e-17 m).
  for (const LoopCase& c : loop_cases()) {
    if (c.name != "four_bar" && c.name != "slider_crank" && c.name != "ankle_2dof") continue;
    const gen::Description d = load_loop_case(c);
    Data<double> data(d.model);
    EXPECT_LT(closure_residual<double>(d.model, data, neutral_configuration<double>(d.model)).cwiseAbs().maxCoeff(), 1e-15)
        << c.name;
    EXPECT_EQ(d.assembly.max_joint_change, 0.0) << c.name;
  }
}

}  // namespace
}  // namespace mbgen::test
