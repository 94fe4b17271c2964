// The joint-limit potential (runtime/include/mbgen/control/joint_limit_potential.hpp): its limits
// against the URDF as urdfdom reads it, its gradient against central differences of the
// potential, its zero away from the limits, and its option checks. The differential IK's use of
// it is in test_differential_ik.cpp.
#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <random>
#include <string>

#include "mbgen/control/joint_limit_potential.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

using namespace mbgen::control;

Model talos() { return load_tree(shared_robot("talos/talos_reduced.urdf"), gen::BaseType::Floating); }

// Every revolute and prismatic joint of the file with a range, and nothing else, by its name.
TEST(JointLimitPotential, LimitsAreTheDescriptionsRanges) {
  const std::string path = shared_robot("talos/talos_reduced.urdf");
  const urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDFFile(path);
  ASSERT_TRUE(urdf);
  const Model model = talos();
  const std::vector<JointLimit> limits = joint_position_limits(model);
  int expected = 0;
  for (const auto& [name, joint] : urdf->joints_) {
    const bool ranged = (joint->type == urdf::Joint::REVOLUTE || joint->type == urdf::Joint::PRISMATIC) && joint->limits &&
                        joint->limits->lower < joint->limits->upper;
    if (!ranged) continue;
    ++expected;
    const auto it = std::find_if(limits.begin(), limits.end(), [&](const JointLimit& l) { return l.joint == name; });
    ASSERT_NE(it, limits.end()) << name;
    EXPECT_EQ(it->lower, joint->limits->lower) << name;
    EXPECT_EQ(it->upper, joint->limits->upper) << name;
    const Joint& j = model.joint(*model.find_joint(name));
    EXPECT_EQ(it->q_index, j.idx_q) << name;
    EXPECT_EQ(it->v_index, j.idx_v) << name;
  }
  EXPECT_EQ(static_cast<int>(limits.size()), expected);
  EXPECT_GT(expected, 20);  // talos_reduced: legs, torso, arms, head
}

// A pose with joints inside their margins on both sides, one beyond its limit, the rest away.
VecX<double> pose_near_limits(const Model& model, const JointLimitOptions& o) {
  VecX<double> q = neutral_configuration<double>(model);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> inside(0.0, o.activation);
  for (std::size_t i = 0; i < o.limits.size(); ++i) {
    const JointLimit& l = o.limits[i];
    switch (i % 4) {
      case 0: q[l.q_index] = l.lower + inside(rng); break;
      case 1: q[l.q_index] = l.upper - inside(rng); break;
      case 2: q[l.q_index] = l.upper + 0.5 * o.activation; break;  // beyond the limit
      default: q[l.q_index] = 0.5 * (l.lower + l.upper); break;
    }
  }
  return q;
}

// dP/dq against central differences of P along each coordinate: P is piecewise quadratic, so the
// difference is exact but for rounding (no coordinate sits within h of a margin's kink).
TEST(JointLimitPotential, GradientIsThePotentialsDerivative) {
  const Model model = talos();
  JointLimitOptions o;
  o.limits = joint_position_limits(model);
  o.activation = 0.2;
  o.stiffness = 7.0;
  const VecX<double> q = pose_near_limits(model, o);
  VecX<double> gradient = VecX<double>::Zero(model.nv());
  const int active = add_joint_limit_gradient<double>(q.data(), o, gradient);
  int expected_active = 0;
  for (const JointLimit& l : o.limits) {
    const double h = 1e-6;
    VecX<double> plus = q, minus = q;
    plus[l.q_index] += h;
    minus[l.q_index] -= h;
    const double fd = (joint_limit_potential<double>(plus.data(), o) - joint_limit_potential<double>(minus.data(), o)) / (2 * h);
    EXPECT_NEAR(gradient[l.v_index], fd, 1e-8 * std::max(1.0, std::abs(fd))) << l.joint;
    const double margin = std::min(q[l.q_index] - l.lower, l.upper - q[l.q_index]);
    if (margin < o.activation) {
      ++expected_active;
      EXPECT_NE(gradient[l.v_index], 0.0) << l.joint;
    } else {
      EXPECT_EQ(gradient[l.v_index], 0.0) << l.joint;
    }
    // The descent direction points inside: away from the nearer limit.
    if (margin < o.activation) {
      EXPECT_EQ(gradient[l.v_index] < 0, q[l.q_index] - l.lower < l.upper - q[l.q_index]) << l.joint;
    }
  }
  EXPECT_EQ(active, expected_active);
  EXPECT_GT(active, static_cast<int>(o.limits.size()) / 2);
  // The floating base and every coordinate without a limit get nothing.
  for (int v = 0; v < 6; ++v) EXPECT_EQ(gradient[v], 0.0);
}

// The closed form on one joint: 0.03 inside its lower limit with a = 0.2 and stiffness 7, the gap
// is 0.17: P = 7 * 0.17^2 / 2, dP/dq = -7 * 0.17; past the upper limit by 0.05, the gap is 0.25.
TEST(JointLimitPotential, ClosedFormOnOneJoint) {
  JointLimitOptions o;
  o.limits = {{"j", 0, 0, -1.0, 1.0}};
  o.activation = 0.2;
  o.stiffness = 7.0;
  double q = -0.97, gradient[1] = {0.0};
  EXPECT_EQ(add_joint_limit_gradient<double>(&q, o, gradient), 1);
  EXPECT_NEAR(gradient[0], -7.0 * 0.17, 1e-14);
  EXPECT_NEAR(joint_limit_potential<double>(&q, o), 0.5 * 7.0 * 0.17 * 0.17, 1e-14);
  q = 1.05;
  gradient[0] = 0.0;
  EXPECT_EQ(add_joint_limit_gradient<double>(&q, o, gradient), 1);
  EXPECT_NEAR(gradient[0], 7.0 * 0.25, 1e-14);
  EXPECT_NEAR(joint_limit_potential<double>(&q, o), 0.5 * 7.0 * 0.25 * 0.25, 1e-14);
}

TEST(JointLimitPotential, ZeroAwayFromTheLimits) {
  const Model model = talos();
  JointLimitOptions o;
  o.limits = joint_position_limits(model);
  VecX<double> q = neutral_configuration<double>(model);
  for (const JointLimit& l : o.limits) q[l.q_index] = 0.5 * (l.lower + l.upper);
  VecX<double> gradient = VecX<double>::Zero(model.nv());
  EXPECT_EQ(add_joint_limit_gradient<double>(q.data(), o, gradient), 0);
  EXPECT_EQ(joint_limit_potential<double>(q.data(), o), 0.0);
  EXPECT_TRUE(gradient.isZero(0.0));
  // One activation margin inside a limit is still outside the zone (strict: C^1 there).
  q[o.limits[0].q_index] = o.limits[0].lower + o.activation;
  EXPECT_EQ(add_joint_limit_gradient<double>(q.data(), o, gradient), 0);
}

template <typename F> std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no exception";
}

TEST(JointLimitPotential, BadOptionsAreRefusedWithAMessage) {
  JointLimitOptions o;
  o.limits = {{"knee", 7, 6, -0.1, 2.0}};
  EXPECT_EQ(error_of([&] { check(o, 8, 7); }), "no exception");
  o.activation = 0;
  EXPECT_EQ(error_of([&] { check(o, 8, 7); }), "joint limits: activation must be finite and > 0, got 0.000000");
  o.activation = 0.1;
  o.stiffness = std::nan("");
  EXPECT_EQ(error_of([&] { check(o, 8, 7); }), "joint limits: stiffness must be finite and > 0, got nan");
  o.stiffness = 10;
  EXPECT_EQ(error_of([&] { check(o, 7, 7); }),
            "joint limits: 'knee': coordinate q[7], v[6] outside the model's nq = 7, nv = 7");
  o.limits[0].upper = -0.2;
  EXPECT_EQ(error_of([&] { check(o, 8, 7); }),
            "joint limits: 'knee': lower -0.100000 must be below upper -0.200000, both finite (leave an unlimited joint out)");
  o.limits.clear();  // no limits: nothing to check
  o.activation = -1;
  EXPECT_EQ(error_of([&] { check(o, 8, 7); }), "no exception");
}

}  // namespace
}  // namespace mbgen::test
