// Reference forward dynamics of closed loops (runtime/include/mbgen/algorithm/
// constrained_dynamics.hpp): the full-coordinate KKT solve against the independent-coordinate
// solve (two independent methods), the constraint and equation-of-motion residuals, passive
// energy conservation, and Baumgarte stabilisation against drift.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
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
    ClosureStatus status;
    const VecX<double> independent = forward_dynamics_independent<double>(model, data, ws, q, v, tau, &status);
    ASSERT_EQ(status, ClosureStatus::Converged);
    EXPECT_LT(relative_error(kkt, independent), 1e-10) << "trial " << trial << ", |qdd| " << independent.norm();
  }
}

// A workspace copied and moved before its first solve (the study moves one into its backend) is
// a whole object: every factorisation's status is set, and the copies compute what a fresh
// workspace does, bit for bit. Before the fix the copy read LLT's unset status enum, which the
// sanitized build reports (scripts/test_sanitized.sh; issue 61).
TEST_P(ConstrainedDynamicsTest, WorkspaceCopiedAndMovedBeforeFirstUseIsWhole) {
  ConstrainedDynamicsWorkspace<double> fresh(model);
  const ConstrainedDynamicsWorkspace<double> copied(fresh);
  ConstrainedDynamicsWorkspace<double> moved(std::move(fresh));
  EXPECT_EQ(copied.Mr_llt.info(), Eigen::Success);
  EXPECT_EQ(moved.Mr_llt.info(), Eigen::Success);
  ConstrainedDynamicsWorkspace<double> from_copy(copied);
  std::mt19937_64 rng(33);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
  const VecX<double> tau = random_vector<double>(model.nv(), rng);
  const VecX<double> expected = forward_dynamics_kkt<double>(model, data, ws, q, v, tau);
  EXPECT_EQ(forward_dynamics_kkt<double>(model, data, moved, q, v, tau), expected);
  EXPECT_EQ(forward_dynamics_kkt<double>(model, data, from_copy, q, v, tau), expected);
  ClosureStatus status;
  const VecX<double> independent = forward_dynamics_independent<double>(model, data, ws, q, v, tau, &status);
  EXPECT_EQ(forward_dynamics_independent<double>(model, data, moved, q, v, tau, &status), independent);
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

// ---- four-bar against its closed-form Lagrangian --------------------------------------------

/// The four-bar of robots/mechanisms/README.md in closed form: crank angle t2 -> rocker t4
/// (Freudenstein, nominal branch) and coupler t3; each link's frame origin and turn angle in the
/// x-z plane (link frames turn about -y, +x towards +z, and are parallel to the world at q = 0).
struct FourBarPose {
  double crank, coupler, rocker;     ///< joint values
  Vec3<double> origin[3];            ///< frame origins of crank, coupler, rocker (world)
  double angle[3];                   ///< absolute turn of each link frame from the nominal pose
};
FourBarPose four_bar_pose(double q_crank) {
  const double a = 0.05, b = 0.182, c = 0.122, d = 0.19;
  const double t20 = M_PI / 2, t30 = std::atan2(0.07, 0.168), t40 = std::atan2(0.12, -0.022);
  const double t2 = t20 + q_crank;
  const double K1 = d / a, K2 = d / c, K3 = (a * a - b * b + c * c + d * d) / (2 * a * c);
  const double A = std::cos(t2) - K1 - K2 * std::cos(t2) + K3, B = -2 * std::sin(t2), C = K1 - (K2 + 1) * std::cos(t2) + K3;
  const double t4 = 2 * std::atan2(-B - std::sqrt(B * B - 4 * A * C), 2 * A);
  const double t3 = std::atan2(c * std::sin(t4) - a * std::sin(t2), d + c * std::cos(t4) - a * std::cos(t2));
  FourBarPose p;
  p.crank = q_crank;
  p.rocker = std::remainder(t4 - t40, 2 * M_PI);
  p.coupler = std::remainder(t3 - t30 - q_crank, 2 * M_PI);
  p.origin[0] = Vec3<double>::Zero();
  p.origin[1] = Vec3<double>(a * std::cos(t2), 0, a * std::sin(t2));
  p.origin[2] = Vec3<double>(d, 0, 0);
  p.angle[0] = q_crank;
  p.angle[1] = q_crank + p.coupler;
  p.angle[2] = p.rocker;
  return p;
}

TEST(FourBarClosedForm, IndependentDynamicsMatchTheLagrangianInTheCrankAngle) {
  // m(t) tdd + 1/2 m'(t) td^2 + V'(t) = tau, with m(t) = sum m_i |dc_i/dt|^2 + (dphi_i/dt)^2 I_i
  // and V(t) = sum m_i 9.81 c_i,z from the closed-form positions (inertias from the model, the
  // rest from robots/mechanisms/README.md). Derivatives in t by central differences (h = 1e-4:
  // ~1e-8 relative), hence 1e-6 relative on the crank acceleration.
  const std::string dir = MBGEN_SOURCE_DIR "/robots/mechanisms/";
  const gen::Description d = load_loop_case({"four_bar", dir + "four_bar.urdf", dir + "four_bar.yaml"});
  const Model& model = d.model;
  Data<double> data(model);
  ConstrainedDynamicsWorkspace<double> ws(model);
  const char* joints[3] = {"crank_joint", "coupler_joint", "rocker_joint"};
  const Vec3<double> axis(0, -1, 0);
  auto com = [&](const FourBarPose& p, int k) {  // centre of mass of link k, world
    const Inertia<double>& I = model.body(model.joint(*model.find_joint(joints[k])).child).inertia;
    return Vec3<double>(p.origin[k] + Eigen::AngleAxisd(p.angle[k], axis).toRotationMatrix() * I.com);
  };
  auto mass_and_potential = [&](double t, double& m, double& V) {
    const double h = 1e-5;
    const FourBarPose p = four_bar_pose(t), pp = four_bar_pose(t + h), pm = four_bar_pose(t - h);
    m = V = 0;
    for (int k = 0; k < 3; ++k) {
      const Inertia<double>& I = model.body(model.joint(*model.find_joint(joints[k])).child).inertia;
      const Vec3<double> dc = (com(pp, k) - com(pm, k)) / (2 * h);
      const double dphi = std::remainder(pp.angle[k] - pm.angle[k], 2 * M_PI) / (2 * h);
      m += I.mass * dc.squaredNorm() + dphi * dphi * axis.dot(I.inertia_com * axis);
      V += I.mass * 9.81 * com(p, k).z();
    }
  };
  std::mt19937_64 rng(61);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 6; ++trial) {
    const double t = M_PI * unit(rng), td = 3 * unit(rng), tau_crank = 0.2 * unit(rng);
    const FourBarPose p = four_bar_pose(t);
    VecX<double> q = VecX<double>::Zero(model.nq());
    for (int k = 0; k < 3; ++k) q[model.joint(*model.find_joint(joints[k])).idx_q] = k == 0 ? p.crank : k == 1 ? p.coupler : p.rocker;
    ASSERT_LT(closure_residual<double>(model, data, q).cwiseAbs().maxCoeff(), 1e-12);
    VecX<double> v(model.nv());
    full_velocities<double>(model, data, q, (VecX<double>(1) << td).finished(), v);
    ASSERT_GT(subsystem_pivot_ratio<double>(model, data), 1e-3);
    VecX<double> tau = VecX<double>::Zero(model.nv());
    tau[model.joint(*model.find_joint("crank_joint")).idx_v] = tau_crank;
    const double tdd = forward_dynamics_independent<double>(model, data, ws, q, v, tau)[model.joint(*model.find_joint("crank_joint")).idx_v];
    const double h = 1e-4;
    double m0, V0, mp, Vp, mm, Vm;
    mass_and_potential(t, m0, V0);
    mass_and_potential(t + h, mp, Vp);
    mass_and_potential(t - h, mm, Vm);
    const double expected = (tau_crank - 0.5 * (mp - mm) / (2 * h) * td * td - (Vp - Vm) / (2 * h)) / m0;
    EXPECT_NEAR(tdd, expected, 1e-6 * std::max(1.0, std::abs(expected))) << "t " << t << ", td " << td;
  }
}

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
