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
  LoopForwardDynamicsTest() : d(load_loop_case(GetParam())), model(d.model), data(model), reference_data(model), reference(model) {}
  gen::Description d;
  const Model& model;
  Data<double> data, reference_data;
  ConstrainedDynamicsWorkspace<double> reference;
};

TEST_P(LoopForwardDynamicsTest, EqualsTheKktReference) {
  ASSERT_FALSE(model.subsystems.empty());
  std::mt19937_64 rng(53);
  double worst = 0, worst_independent = 0, worst_plain = 0;
  int states = 0;
  for (int trial = 0; trial < 60 && states < 20; ++trial) {
    VecX<double> q, v;
    if (!consistent_state(model, d.assembly.q, rng, 0.05, q, v)) continue;  // Newton may fail far out (wl16_like)
    const VecX<double> tau = random_vector<double>(model.nv(), rng, 5.0);
    ASSERT_EQ(forward_dynamics_loops<double>(model, data, q, v, tau), ClosureStatus::Converged);
    const VecX<double> expected = forward_dynamics_kkt<double>(model, reference_data, reference, q, v, tau);
    worst = std::max(worst, relative_error(data.ddq, expected));
    // Plain aba() on a model with loops computes the maps itself: the same, never a silent NaN.
    worst_plain = std::max(worst_plain, relative_error(VecX<double>(aba<double>(model, data, q, v, tau)), expected));
    // The same from the independent velocities alone (the form the generator traces).
    const VecX<double> qdd = data.ddq;
    VecX<double> vy(static_cast<int>(model.structure().independent_v.size()));
    for (int i = 0; i < vy.size(); ++i) vy[i] = v[model.structure().independent_v[static_cast<std::size_t>(i)]];
    forward_dynamics_loops_independent<double>(model, data, q, vy, tau);
    worst_independent = std::max(worst_independent, relative_error(data.ddq, qdd));
    ++states;
  }
  std::printf("  %s: O(n) vs KKT worst relative error %.2e over %d states\n", GetParam().name.c_str(), worst, states);
  EXPECT_GE(states, 15);
  EXPECT_LT(worst, 1e-10);
  EXPECT_LT(worst_independent, 1e-12);
  EXPECT_LT(worst_plain, 1e-10);
}

TEST_P(LoopForwardDynamicsTest, InverseDynamicsAndMassMatrixInIndependentCoordinates) {
  // Three methods in y: forward dynamics (O(n)) gives ydd for tau; inverse dynamics must give back
  // T^T tau (the forces tau exert on y), and M_y ydd + tau_y(ydd = 0) = T^T tau. Normwise
  // backward error below 1e-12: |residual| / (|M_y| |ydd| + |bias| + |T^T tau|) (ydd can be large
  // near a singular pose, 5bar_linkage's, and the terms then cancel).
  std::mt19937_64 rng(67);
  double worst_id = 0, worst_m = 0;
  for (int trial = 0, states = 0; trial < 40 && states < 10; ++trial) {
    VecX<double> q, v;
    if (!consistent_state(model, d.assembly.q, rng, 0.05, q, v)) continue;
    ++states;
    const VecX<double> tau = random_vector<double>(model.nv(), rng, 5.0);
    ASSERT_EQ(forward_dynamics_loops<double>(model, data, q, v, tau), ClosureStatus::Converged);
    const int ny = static_cast<int>(model.structure().independent_v.size());
    VecX<double> ydd(ny), tau_projected(ny);
    for (int i = 0; i < ny; ++i) ydd[i] = data.ddq[model.structure().independent_v[static_cast<std::size_t>(i)]];
    detail::project_independent<double>(model, data, tau, tau_projected);
    const VecX<double> tau_y = inverse_dynamics_loops<double>(model, data, q, v, ydd);
    const VecX<double> bias = inverse_dynamics_loops<double>(model, data, q, v, VecX<double>::Zero(ny));
    const MatX<double> M_y = mass_matrix_loops<double>(model, data, q);
    const double scale = M_y.norm() * ydd.norm() + bias.norm() + tau_projected.norm();
    worst_id = std::max(worst_id, (tau_y - tau_projected).norm() / scale);
    worst_m = std::max(worst_m, (M_y * ydd + bias - tau_projected).norm() / scale);
    EXPECT_LT((M_y - M_y.transpose()).norm(), 1e-12 * M_y.norm());
  }
  std::printf("  %s: inverse dynamics %.2e, mass matrix %.2e\n", GetParam().name.c_str(), worst_id, worst_m);
  EXPECT_LT(worst_id, 1e-12);
  EXPECT_LT(worst_m, 1e-12);
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
    inverse_dynamics_loops<double>(model, data, q, v, data.scratch_y);
    mass_matrix_loops<double>(model, data, q);
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
  VecX<double> q = VecX<double>::Zero(model.nq());
  const int slider = model.joint(*model.find_joint("slider_joint")).idx_q;
  const VecX<double> v = VecX<double>::Zero(model.nv()), tau = VecX<double>::Ones(model.nv());
  for (double x : {0.02, 0.04, 0.05}) {  // warm-started approach: regular
    q[slider] = x;
    ASSERT_EQ(closure_positions<double>(model, data, q).status, ClosureStatus::Converged);
    EXPECT_EQ(forward_dynamics_loops<double>(model, data, q, v, tau), ClosureStatus::Converged) << x;
    EXPECT_TRUE(data.ddq.allFinite());
  }
  q[slider] = 0.06;
  closure_positions<double>(model, data, q);
  EXPECT_EQ(forward_dynamics_loops<double>(model, data, q, v, tau), ClosureStatus::Singular);
}

// A passive simulation in independent coordinates with the O(n) forward dynamics: RK4 on (y, yd),
// the dependent coordinates closed by Newton (warm-started) at every stage, no stabilisation
// needed. Over 5 s the closure residual stays at Newton's tolerance (<= 1e-12) at every step, and
// the energy drifts by less than 1e-6 of its size (RK4 at dt 1e-3 truncates ~1e-8 J here; a wrong
// term of the maps, g dropped say, drifts by O(1)). The reference integrated in full coordinates
// drifts without Baumgarte (test_constrained_dynamics.cpp).
class PassiveLoopSimulation : public ::testing::TestWithParam<LoopCase> {};

TEST_P(PassiveLoopSimulation, ClosesTheLoopsAndConservesEnergyOverFiveSeconds) {
  const gen::Description d = load_loop_case(GetParam());
  const Model& model = d.model;
  Data<double> data(model);
  const std::vector<int>& y_index = model.structure().independent_v;  // 1-DoF joints: q index = v index here
  const int ny = static_cast<int>(y_index.size());
  const VecX<double> zero_tau = VecX<double>::Zero(model.nv());
  VecX<double> q = d.assembly.q, yd(ny);
  for (int i = 0; i < ny; ++i)  // 2 rad/s, or 2 cm/s for the ankle's linear actuators (a short stroke)
    for (int j = 1; j < model.num_joints(); ++j)
      if (model.joint(JointIndex(j)).idx_v == y_index[static_cast<std::size_t>(i)])
        yd[i] = model.joint(JointIndex(j)).type == JointType::Prismatic ? 0.02 : 2.0;
  // State derivative at (q with the independent positions y, yd): closes the loops first.
  auto derivative = [&](VecX<double>& q_stage, const VecX<double>& y, const VecX<double>& yd_stage, VecX<double>& ydd) {
    for (int i = 0; i < ny; ++i) q_stage[y_index[static_cast<std::size_t>(i)]] = y[i];
    EXPECT_EQ(closure_positions<double>(model, data, q_stage).status, ClosureStatus::Converged);
    forward_dynamics_loops_independent<double>(model, data, q_stage, yd_stage, zero_tau);
    for (int i = 0; i < ny; ++i) ydd[i] = data.ddq[y_index[static_cast<std::size_t>(i)]];
  };
  auto energy = [&](const VecX<double>& q_now, const VecX<double>& yd_now) {
    VecX<double> v(model.nv());
    full_velocities<double>(model, data, q_now, yd_now, v);
    return kinetic_energy<double>(model, data, q_now, v) + potential_energy<double>(model, data, q_now);
  };
  const double dt = 1e-3, e0 = energy(q, yd);
  double e_min = e0, e_max = e0, worst_residual = 0, worst_drift = 0;
  VecX<double> y(ny), k1(ny), k2(ny), k3(ny), k4(ny), a1(ny), a2(ny), a3(ny), a4(ny);
  for (int i = 0; i < ny; ++i) y[i] = q[y_index[static_cast<std::size_t>(i)]];
  for (int step = 0; step < 5000; ++step) {
    VecX<double> qs = q;
    k1 = yd;
    derivative(qs, y, k1, a1);
    k2 = yd + 0.5 * dt * a1;
    derivative(qs, y + 0.5 * dt * k1, k2, a2);
    k3 = yd + 0.5 * dt * a2;
    derivative(qs, y + 0.5 * dt * k2, k3, a3);
    k4 = yd + dt * a3;
    derivative(qs, y + dt * k3, k4, a4);
    y += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    yd += dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
    for (int i = 0; i < ny; ++i) q[y_index[static_cast<std::size_t>(i)]] = y[i];
    ASSERT_EQ(closure_positions<double>(model, data, q).status, ClosureStatus::Converged) << "step " << step;
    worst_residual = std::max(worst_residual, closure_residual<double>(model, data, q).cwiseAbs().maxCoeff());
    const double e = energy(q, yd);
    e_min = std::min(e_min, e);
    e_max = std::max(e_max, e);
    worst_drift = std::max(worst_drift, std::abs(e - e0));
  }
  const double swing = std::max(1e-9, std::abs(potential_energy<double>(model, data, q)) + std::abs(e0));
  std::printf("  %s: 5 s, closure residual <= %.1e, energy drift %.2e J (of |E| %.3g J)\n", GetParam().name.c_str(),
              worst_residual, worst_drift, swing);
  EXPECT_LE(worst_residual, 1e-12);
  EXPECT_LT(worst_drift, 1e-6 * swing);
}

/// The mechanisms, and the ankle with rotor bodies in its loops (their spin energy counts).
std::vector<LoopCase> mechanism_cases() {
  std::vector<LoopCase> cases;
  for (const LoopCase& c : loop_cases())
    for (const char* name : {"four_bar", "slider_crank", "ankle_2dof", "ankle_2dof_rotors"})
      if (c.name == name) cases.push_back(c);
  return cases;
}
INSTANTIATE_TEST_SUITE_P(Mechanisms, PassiveLoopSimulation, ::testing::ValuesIn(mechanism_cases()),
                         [](const auto& info) { return info.param.name; });

INSTANTIATE_TEST_SUITE_P(ClosedLoops, LoopForwardDynamicsTest, ::testing::ValuesIn(loop_cases()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace mbgen::test
