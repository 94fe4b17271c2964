// Calls the code an installed mbgen generated for tests/data/tiny_arm.urdf, and the installed
// generic runtime, and checks both against closed forms. Exit 0 when all agree.
//
// tiny_arm: a two-link arm (shoulder, elbow about y, links along z; the tool is merged into the
// lower link) and a vertical prismatic "knee" on the fixed base. With v = 0 the gravity torques are
//   g_shoulder = -9.81 (0.6 sin q1 + 0.18 sin(q1 + q2)),  g_elbow = -9.81 * 0.18 sin(q1 + q2),
//   g_knee = 9.81 * 1 kg,
// (0.6 = 1 kg * 0.25 + 0.7 kg * 0.5; 0.18 = 0.5 kg * 0.2 + 0.2 kg * 0.4), and with tau = 0 the
// knee, decoupled from the arm, falls at qdd = -9.81.
#include <cmath>
#include <cstdio>
#include <cstring>

#include "mbgen/mbgen.hpp"
#include "tiny_arm.hpp"

namespace {

int failures = 0;

void expect_near(const char* what, double actual, double expected) {
  const double tolerance = 1e-12 * (1.0 + std::abs(expected));
  if (!(std::abs(actual - expected) <= tolerance)) {
    std::printf("FAIL %s: %.17g, expected %.17g\n", what, actual, expected);
    ++failures;
  }
}

int joint_index(const char* name) {
  for (int i = 0; i < tiny_arm::nv; ++i)
    if (std::strcmp(tiny_arm::joint_names[i], name) == 0) return i;
  std::printf("FAIL: no joint %s in the generated header\n", name);
  ++failures;
  return 0;
}

}  // namespace

int main() {
  static_assert(tiny_arm::nq == 3 && tiny_arm::nv == 3, "tiny_arm has three joints");
  const int shoulder = joint_index("shoulder"), elbow = joint_index("elbow"), knee = joint_index("knee");
  const double g = 9.81, q1 = 0.3, q2 = -0.7;

  double q[3], v[3] = {0, 0, 0}, zero[3] = {0, 0, 0}, tau[3], qdd[3];
  q[shoulder] = q1;
  q[elbow] = q2;
  q[knee] = 0.05;

  // Generated inverse dynamics at rest: the gravity torques.
  tiny_arm::inverse_dynamics(q, v, zero, tau);
  expect_near("inverse_dynamics shoulder", tau[shoulder], -g * (0.6 * std::sin(q1) + 0.18 * std::sin(q1 + q2)));
  expect_near("inverse_dynamics elbow", tau[elbow], -g * 0.18 * std::sin(q1 + q2));
  expect_near("inverse_dynamics knee", tau[knee], g * 1.0);

  // Generated forward dynamics: gravity compensation holds the arm still; without it the knee falls.
  tiny_arm::forward_dynamics(q, v, tau, qdd);
  for (int i = 0; i < 3; ++i) expect_near("forward_dynamics with gravity compensation", qdd[i], 0.0);
  tiny_arm::forward_dynamics(q, v, zero, qdd);
  expect_near("forward_dynamics knee, free fall", qdd[knee], -g);

  // The installed runtime (Eigen through mbgen::runtime): the knee alone, built by hand.
  mbgen::Model model;
  mbgen::Joint slider;
  slider.name = "knee";
  slider.type = mbgen::JointType::Prismatic;
  slider.axis = mbgen::Vec3<double>::UnitZ();
  mbgen::Inertia<double> leg;
  leg.mass = 1.0;
  leg.inertia_com = 0.01 * mbgen::Mat3<double>::Identity();
  model.add_body(mbgen::kWorldBody, slider, "leg", leg);
  mbgen::Data<double> data(model);
  const Eigen::VectorXd q_knee = Eigen::VectorXd::Constant(1, 0.05), v_knee = Eigen::VectorXd::Zero(1);
  const Eigen::VectorXd& qdd_knee = mbgen::aba<double>(model, data, q_knee, v_knee, v_knee);
  expect_near("runtime aba knee, free fall", qdd_knee[0], -g);

  if (failures == 0) std::printf("consumer: generated code and runtime agree with the closed forms\n");
  return failures == 0 ? 0 : 1;
}
