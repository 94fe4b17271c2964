// Actuator <-> joint maps on the generated code (runtime control/actuator_joint_map.hpp over
// lola::Backend: the generated closure Newton and velocity map), against Lola's drive linkages
// in closed form (tests/lola_closed_forms.hpp): the outputs of random actuator positions give
// those positions back through the closed forms (1e-11 m); the inverse direction from random
// output angles equals the closed forms (1e-11 m) in a few Newton steps; the Jacobians are each
// other's inverse and da/do matches the closed forms' central differences (1e-8); the calls do
// not allocate; refusals say what is wrong.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "lola.hpp"
#include "lola_closed_forms.hpp"
#include "malloc_guard.hpp"
#include "mbgen/control/actuator_joint_map.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

using control::ActuatorJointMap;
using control::MapStatus;

/// Lola's drive actuators and their output joints, leg by leg (v indices of the generated robot).
struct Joints {
  std::vector<int> actuators, outputs;
  explicit Joints(const Model& model) {
    for (const char* side : {"_l", "_r"}) {
      for (const char* a : {"knee_act", "ankle_act_lat", "ankle_act_med"}) actuators.push_back(index(model, std::string(a) + side));
      for (const char* o : {"knee", "ankle_pitch", "ankle_roll"}) outputs.push_back(index(model, std::string(o) + side));
    }
  }
  static int index(const Model& model, const std::string& name) { return model.joint(*model.find_joint(name)).idx_v; }
};

/// The closed forms' actuator positions for outputs o (knee, pitch, roll per leg; the lateral
/// rod at b_y = +0.045 on the left leg, -0.045 on the right).
VecX<double> closed_forms(const VecX<double>& o) {
  VecX<double> a(6);
  a << knee_actuator(o[0]), ankle_actuator(o[1], o[2], 0.045), ankle_actuator(o[1], o[2], -0.045), knee_actuator(o[3]),
      ankle_actuator(o[4], o[5], -0.045), ankle_actuator(o[4], o[5], 0.045);
  return a;
}

TEST(ActuatorJointMap, LolasDrivesAgainstTheirClosedForms) {
  const gen::Description d = load_lola();
  const Joints joints(d.model);
  ActuatorJointMap<lola::Backend> map(lola::Backend{}, joints.actuators, joints.outputs);
  ASSERT_EQ(map.size(), 6);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> knee(-0.06, -0.005), rod(-0.015, 0.015), angle(0.3, 1.2), tilt(-0.2, 0.2);
  double worst_forward = 0, worst_inverse = 0, worst_product = 0, worst_derivative = 0;
  int most_iterations = 0;
  for (int trial = 0; trial < 30; ++trial) {
    // Forward: random actuator positions -> outputs -> the closed forms give the positions back.
    VecX<double> q = d.assembly.q, a(6), o(6), a_back(6);
    a << knee(rng), rod(rng), rod(rng), knee(rng), rod(rng), rod(rng);
    Eigen::Matrix<double, 6, 6, Eigen::RowMajor> J_oa, J_ao;
    ASSERT_EQ(map.to_joints(a.data(), q.data(), o.data(), J_oa.data()), MapStatus::converged) << trial;
    worst_forward = std::max(worst_forward, (closed_forms(o) - a).cwiseAbs().maxCoeff());
    // Inverse: random outputs -> actuators, warm-started from the assembled pose.
    VecX<double> target(6);
    target << angle(rng), tilt(rng), tilt(rng), angle(rng), tilt(rng), tilt(rng);
    VecX<double> q_inverse = d.assembly.q;
    int iterations = 0;
    ASSERT_EQ(map.to_actuators(target.data(), q_inverse.data(), a_back.data(), J_ao.data(), ActuatorJointMap<lola::Backend>::default_tolerance(), 20, &iterations),
              MapStatus::converged)
        << trial;
    most_iterations = std::max(most_iterations, iterations);
    worst_inverse = std::max(worst_inverse, (closed_forms(target) - a_back).cwiseAbs().maxCoeff());
    // Jacobians: da/do at the inverse's solution against the closed forms' central differences,
    // and do/da there its inverse.
    const double h = 1e-6;
    for (int c = 0; c < 6; ++c) {
      VecX<double> plus = target, minus = target;
      plus[c] += h, minus[c] -= h;
      const VecX<double> fd = (closed_forms(plus) - closed_forms(minus)) / (2 * h);
      worst_derivative = std::max(worst_derivative, (J_ao.col(c) - fd).cwiseAbs().maxCoeff() / J_ao.cwiseAbs().maxCoeff());
    }
    VecX<double> o_again(6);
    ASSERT_EQ(map.to_joints(a_back.data(), q_inverse.data(), o_again.data(), J_oa.data()), MapStatus::converged);
    worst_product = std::max(worst_product, (J_oa * J_ao - Eigen::Matrix<double, 6, 6>::Identity()).cwiseAbs().maxCoeff());
  }
  std::printf("  forward vs closed forms %.1e m, inverse vs closed forms %.1e m (<= %d Newton steps), da/do vs central differences "
              "%.1e, |do/da da/do - I| %.1e\n",
              worst_forward, worst_inverse, most_iterations, worst_derivative, worst_product);
  EXPECT_LT(worst_forward, 1e-11);
  EXPECT_LT(worst_inverse, 1e-11);
  EXPECT_LE(most_iterations, 8);
  EXPECT_LT(worst_derivative, 1e-8);
  EXPECT_LT(worst_product, 1e-10);
}

TEST(ActuatorJointMap, DoesNotAllocate) {
  const gen::Description d = load_lola();
  const Joints joints(d.model);
  ActuatorJointMap<lola::Backend> map(lola::Backend{}, joints.actuators, joints.outputs);
  VecX<double> q = d.assembly.q, a = VecX<double>::Constant(6, -0.01), o(6), J(36);
  a[1] = a[2] = a[4] = a[5] = 0.005;
  VecX<double> target(6);
  target << 0.8, 0.1, -0.1, 0.7, -0.05, 0.05;
  MallocGuard guard;
  map.to_joints(a.data(), q.data(), o.data(), J.data());
  map.to_actuators(target.data(), q.data(), a.data(), J.data());
  EXPECT_EQ(guard.count(), 0u);
}

TEST(ActuatorJointMap, RefusalsSayWhatIsWrong) {
  const gen::Description d = load_lola();
  const Joints joints(d.model);
  auto message = [](auto&& make) {
    try {
      make();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_NE(message([&] { ActuatorJointMap<lola::Backend>(lola::Backend{}, joints.actuators, {joints.outputs[0]}); })
                .find("6 actuator(s) and 1 output(s)"),
            std::string::npos);
  // The knee itself is dependent in the loops: it cannot be set as an actuator.
  EXPECT_NE(message([&] { ActuatorJointMap<lola::Backend>(lola::Backend{}, {joints.outputs[0]}, {joints.actuators[0]}); })
                .find("is not an independent coordinate"),
            std::string::npos);
}

}  // namespace
}  // namespace mbgen::test
