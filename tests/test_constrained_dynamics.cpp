// Reference forward dynamics of closed loops (runtime/include/mbgen/algorithm/
// constrained_dynamics.hpp): the full-coordinate KKT solve against the independent-coordinate
// solve (two independent methods), the constraint and equation-of-motion residuals, passive
// energy conservation, and Baumgarte stabilisation against drift.
#include <gtest/gtest.h>

#include <random>

#include "malloc_guard.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

class ConstrainedDynamicsTest : public ::testing::TestWithParam<LoopCase> {
 protected:
  ConstrainedDynamicsTest() : d(load_loop_case(GetParam())), model(d.model), data(model), ws(model) {}
  gen::Description d;
  const Model& model;
  Data<double> data;
  ConstrainedDynamicsWorkspace<double> ws;
};

TEST_P(ConstrainedDynamicsTest, KktAndIndependentCoordinatesAgree) {
  // Seeded random consistent states and joint forces: the two methods agree to 1e-10 relative
  // (|a - b| / max(1, |b|)).
  std::mt19937_64 rng(31);
  for (int trial = 0; trial < 4; ++trial) {
    VecX<double> q, v;
    ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
    const VecX<double> tau = random_vector<double>(model.nv(), rng);
    const VecX<double> kkt = forward_dynamics_kkt<double>(model, data, ws, q, v, tau);
    LoopSolveStatus status;
    const VecX<double> independent = forward_dynamics_independent<double>(model, data, ws, q, v, tau, &status);
    ASSERT_EQ(status, LoopSolveStatus::Converged);
    EXPECT_LT(relative_error(kkt, independent), 1e-10) << "trial " << trial << ", |qdd| " << independent.norm();
  }
}

TEST_P(ConstrainedDynamicsTest, KktSatisfiesTheConstraintsAndTheEquationsOfMotion) {
  std::mt19937_64 rng(32);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
  const VecX<double> tau = random_vector<double>(model.nv(), rng);
  const VecX<double> qdd = forward_dynamics_kkt<double>(model, data, ws, q, v, tau);
  const VecX<double> lambda = ws.lambda;
  // Normwise backward errors, 1e-12: some models have joints with almost no inertia along their
  // motion (robot_delta's rods spinning about their own axes: |qdd| ~ 1e11 for unit torques),
  // so residuals are compared with the size of the terms, not with 1.
  // All rows, the redundant ones included: Phi_q qdd = gamma.
  const VecX<double> gamma = closure_bias<double>(model, data, q, v);
  const MatX<double> Phi_q = closure_jacobian<double>(model, data, q);
  EXPECT_LT((Phi_q * qdd - gamma).norm(), 1e-12 * (Phi_q.norm() * qdd.norm() + gamma.norm()));
  // M qdd + C v + g = tau + Phi_k^T lambda, against RNEA.
  VecX<double> constraint_force = VecX<double>::Zero(model.nv());
  for (std::size_t i = 0; i < ws.rows.size(); ++i) constraint_force += Phi_q.row(ws.rows[i]).transpose() * lambda[i];
  const VecX<double> id = rnea<double>(model, data, q, v, qdd);
  const double M_norm = crba<double>(model, data, q).norm();
  EXPECT_LT((id - tau - constraint_force).norm(), 1e-12 * (M_norm * qdd.norm() + tau.norm() + constraint_force.norm() + 1));
}

TEST_P(ConstrainedDynamicsTest, ReferenceDynamicsDoNotAllocate) {
  std::mt19937_64 rng(33);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
  const VecX<double> tau = random_vector<double>(model.nv(), rng);
  MallocGuard guard;
  forward_dynamics_kkt<double>(model, data, ws, q, v, tau, BaumgarteGains{10, 10});
  forward_dynamics_independent<double>(model, data, ws, q, v, tau);
  EXPECT_EQ(guard.count(), 0u);
}

INSTANTIATE_TEST_SUITE_P(ClosedLoops, ConstrainedDynamicsTest, ::testing::ValuesIn(loop_cases()),
                         [](const auto& info) { return info.param.name; });

// ---- integration: energy and drift --------------------------------------------------------

/// Classical RK4 on (q, v) of a fixed-base model (qdot = v) with the KKT reference, tau = 0.
struct Rk4Kkt {
  const Model& model;
  Data<double>& data;
  ConstrainedDynamicsWorkspace<double>& ws;
  BaumgarteGains gains;
  void step(VecX<double>& q, VecX<double>& v, double dt) {
    const VecX<double> tau = VecX<double>::Zero(model.nv());
    VecX<double> k1v = forward_dynamics_kkt<double>(model, data, ws, q, v, tau, gains), k1q = v;
    VecX<double> q2 = q + dt / 2 * k1q, v2 = v + dt / 2 * k1v;
    VecX<double> k2v = forward_dynamics_kkt<double>(model, data, ws, q2, v2, tau, gains), k2q = v2;
    VecX<double> q3 = q + dt / 2 * k2q, v3 = v + dt / 2 * k2v;
    VecX<double> k3v = forward_dynamics_kkt<double>(model, data, ws, q3, v3, tau, gains), k3q = v3;
    VecX<double> q4 = q + dt * k3q, v4 = v + dt * k3v;
    VecX<double> k4v = forward_dynamics_kkt<double>(model, data, ws, q4, v4, tau, gains), k4q = v4;
    q += dt / 6 * (k1q + 2 * k2q + 2 * k3q + k4q);
    v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
  }
};

double energy(const Model& model, Data<double>& data, const VecX<double>& q, const VecX<double>& v) {
  return kinetic_energy<double>(model, data, q, v) + potential_energy<double>(model, data, q);
}

class PassiveMechanism : public ::testing::TestWithParam<std::string> {};

TEST_P(PassiveMechanism, EnergyIsConservedWithAFineStep) {
  // Passive (tau = 0) under gravity, from a consistent state with a random velocity: RK4 with
  // dt = 1e-4 s over 0.5 s keeps the total energy to 1e-8 relative (RK4's error ~ dt^4 per unit
  // time), with no stabilisation.
  const std::string m = GetParam();
  const gen::Description d = load_loop_case({m, MBGEN_SOURCE_DIR "/robots/mechanisms/" + m + ".urdf",
                                             MBGEN_SOURCE_DIR "/robots/mechanisms/" + m + ".yaml"});
  Data<double> data(d.model);
  ConstrainedDynamicsWorkspace<double> ws(d.model);
  std::mt19937_64 rng(41);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(d.model, d.assembly.q, rng, 0.05, q, v));
  const double e0 = energy(d.model, data, q, v);
  Rk4Kkt rk4{d.model, data, ws, {}};
  double worst = 0;
  for (int k = 0; k < 5000; ++k) {
    rk4.step(q, v, 1e-4);
    worst = std::max(worst, std::abs(energy(d.model, data, q, v) - e0));
  }
  const double scale = std::max(1e-3, std::abs(e0) + kinetic_energy<double>(d.model, data, q, v));
  EXPECT_LT(worst / scale, 1e-8) << "energy " << e0 << " J";
  std::cout << "[ energy   ] " << m << ": max |E - E0| = " << worst << " J over 0.5 s (E0 = " << e0 << " J)\n";
}

TEST_P(PassiveMechanism, BaumgarteBoundsTheDriftThatTheBareReferenceAccumulates) {
  // A coarse step (dt = 5e-3 s, 4 s) lets the bare reference drift off the closed set (the
  // constraint holds only at the acceleration level); Baumgarte (alpha = beta = 20 / s) pulls it
  // back. Both figures are printed. The bare drift grows (its last 2 s reach more than twice its
  // first 2 s); the stabilised one is 10 times smaller and bounded (a steady level where the
  // correction balances RK4's error: the last 2 s within 10 % of the first 2 s).
  const std::string m = GetParam();
  const gen::Description d = load_loop_case({m, MBGEN_SOURCE_DIR "/robots/mechanisms/" + m + ".urdf",
                                             MBGEN_SOURCE_DIR "/robots/mechanisms/" + m + ".yaml"});
  Data<double> data(d.model);
  ConstrainedDynamicsWorkspace<double> ws(d.model);
  double drift[2], late_drift[2], early_drift[2];
  for (int stabilised = 0; stabilised < 2; ++stabilised) {
    std::mt19937_64 rng(42);
    VecX<double> q, v;
    ASSERT_TRUE(consistent_state(d.model, d.assembly.q, rng, 0.05, q, v));
    v *= 5;  // a brisk motion makes the drift visible
    Rk4Kkt rk4{d.model, data, ws, stabilised ? BaumgarteGains{20, 20} : BaumgarteGains{}};
    early_drift[stabilised] = late_drift[stabilised] = 0;
    for (int k = 0; k < 800; ++k) {
      rk4.step(q, v, 5e-3);
      double& worst = k < 400 ? early_drift[stabilised] : late_drift[stabilised];
      worst = std::max(worst, closure_residual<double>(d.model, data, q).cwiseAbs().maxCoeff());
    }
    drift[stabilised] = std::max(early_drift[stabilised], late_drift[stabilised]);
  }
  std::cout << "[ drift    ] " << m << ": max |Phi| over 4 s, bare " << drift[0] << " (first 2 s " << early_drift[0]
            << "), Baumgarte " << drift[1] << " (first 2 s " << early_drift[1] << ")\n";
  EXPECT_LT(drift[1], drift[0] / 10);
  EXPECT_GT(late_drift[0], 2 * early_drift[0]);
  EXPECT_LE(late_drift[1], 1.1 * early_drift[1]);
}

INSTANTIATE_TEST_SUITE_P(Mechanisms, PassiveMechanism, ::testing::Values("four_bar", "slider_crank", "ankle_2dof"));

}  // namespace
}  // namespace mbgen::test
