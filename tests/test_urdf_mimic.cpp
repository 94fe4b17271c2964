// URDF <mimic> (generator/load/urdf_mimic.cpp): independent by default, as Pinocchio's
// buildModel and MuJoCo load it; with `mimic: couple` (extras) or --mimic couple a coupling
// closure, so the follower has no coordinate of its own in the closed system. The coupled
// dynamics against the textbook closed form of a planar two-link arm whose elbow follows its
// shoulder; the coupled robots also run every loop test (test_support.hpp's loop_cases: O(n)
// against the KKT reference, inverse dynamics, mass matrix, derivatives).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <optional>
#include <random>

#include "load/load_error.hpp"
#include "model/topology.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

const std::string kMimic = MBGEN_TEST_DATA "/mimic";

gen::Description load(const std::string& urdf, std::optional<bool> couple, const std::string& extras = "") {
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  options.couple_mimics = couple;
  if (!extras.empty()) options.extras_file = extras;
  return gen::load_description(urdf, options);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(UrdfMimic, IndependentByDefaultWithAWarningThatSaysHowToCouple) {
  const gen::Description d = load(shared_robot("panda/panda.urdf"), std::nullopt);
  EXPECT_TRUE(d.closures.empty());
  EXPECT_EQ(d.closed_dof, 9);
  bool warned = false;
  for (const std::string& w : d.warnings)
    warned |= contains(w, "joint 'panda_finger_joint2' mimics 'panda_finger_joint1'") && contains(w, "mimic: couple");
  EXPECT_TRUE(warned);
}

TEST(UrdfMimic, CoupledPandaHasOneCoordinateLessAndTheFollowerIsDependent) {
  for (const gen::Description& d : {load(shared_robot("panda/panda.urdf"), true),
                                     load(shared_robot("panda/panda.urdf"), std::nullopt, kMimic + "/panda_coupled.yaml")}) {
    ASSERT_EQ(d.closures.size(), 1u);
    EXPECT_EQ(d.closures[0].type, "coupling");
    EXPECT_EQ(d.closures[0].frame_a, "panda_finger_joint1");
    EXPECT_EQ(d.closures[0].frame_b, "panda_finger_joint2");
    EXPECT_EQ(d.model.nv(), 9);
    EXPECT_EQ(d.closed_dof, 8);
    ASSERT_EQ(d.model.subsystems.size(), 1u);
    ASSERT_EQ(d.model.subsystems[0].dependent.size(), 1u);
    EXPECT_EQ(gen::coordinate_name(d.model, d.model.subsystems[0].dependent[0]), "panda_finger_joint2");
    for (const std::string& w : d.warnings) EXPECT_FALSE(contains(w, "mimics")) << w;
  }
  // The command line's choice wins over the extras'.
  EXPECT_TRUE(load(shared_robot("panda/panda.urdf"), false, kMimic + "/panda_coupled.yaml").closures.empty());
}

// Textbook planar two-link arm (links along x, hinges about y, gravity -z): M q'' + h + g = tau
// with M11 = I1 + m1 c1^2 + I2 + m2 (l1^2 + c2^2 + 2 l1 c2 cos q2), M12 = I2 + m2 (c2^2 + l1 c2 cos q2),
// M22 = I2 + m2 c2^2, h = m2 l1 c2 sin q2 [-(2 q1' q2' + q2'^2); q1'^2], and, the heights being
// -c1 sin q1 and -(l1 sin q1 + c2 sin(q1 + q2)), g = -9.81 [m1 c1 cos q1 + m2 (l1 cos q1 + c2 cos(q1 + q2)); m2 c2 cos(q1 + q2)].
// The elbow follows, q2 = 0.5 q1 + 0.1: with T = [1; 0.5], y'' = T^T (tau - h - g) / (T^T M T).
TEST(UrdfMimic, CoupledTwoLinkArmMatchesTheClosedForm) {
  const gen::Description d = load(kMimic + "/two_link.urdf", std::nullopt, kMimic + "/two_link.yaml");
  const Model& model = d.model;
  ASSERT_EQ(model.nv(), 2);
  ASSERT_EQ(d.closed_dof, 1);
  const double m1 = 1.5, m2 = 0.8, c1 = 0.2, c2 = 0.15, l1 = 0.5, I1 = 0.03, I2 = 0.01, g0 = 9.81, a = 0.5, b = 0.1;
  Data<double> data(model);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  double worst = 0, worst_closure = 0;
  for (int trial = 0; trial < 50; ++trial) {
    VecX<double> q(2);
    q << u(rng), 0.0;  // the elbow from its leader, by the closure's Newton
    ASSERT_EQ(closure_positions<double>(model, data, q).status, ClosureStatus::Converged);
    worst_closure = std::max(worst_closure, std::abs(q[1] - (a * q[0] + b)));
    const double y_dot = u(rng);
    VecX<double> vy(1), v(2), tau(2);
    vy << y_dot;
    full_velocities<double>(model, data, q, vy, v);
    tau << u(rng), u(rng);
    const double q1 = q[0], q2 = q[1], d1 = v[0], d2 = v[1];
    const double M11 = I1 + m1 * c1 * c1 + I2 + m2 * (l1 * l1 + c2 * c2 + 2 * l1 * c2 * std::cos(q2));
    const double M12 = I2 + m2 * (c2 * c2 + l1 * c2 * std::cos(q2)), M22 = I2 + m2 * c2 * c2;
    const double s = m2 * l1 * c2 * std::sin(q2);
    const double h1 = -s * (2 * d1 * d2 + d2 * d2), h2 = s * d1 * d1;
    const double g1 = -g0 * (m1 * c1 * std::cos(q1) + m2 * (l1 * std::cos(q1) + c2 * std::cos(q1 + q2)));
    const double g2 = -g0 * m2 * c2 * std::cos(q1 + q2);
    const double My = M11 + 2 * a * M12 + a * a * M22;
    const double expected = ((tau[0] - h1 - g1) + a * (tau[1] - h2 - g2)) / My;
    ASSERT_EQ(forward_dynamics_loops<double>(model, data, q, v, tau), ClosureStatus::Converged);
    worst = std::max(worst, std::abs(data.ddq[0] - expected) / std::max(1.0, std::abs(expected)));
    // The follower's acceleration is the leader's times the multiplier (q2'' = 0.5 q1'').
    EXPECT_NEAR(data.ddq[1], a * data.ddq[0], 1e-12 * std::max(1.0, std::abs(data.ddq[0])));
  }
  std::printf("  two-link mimic: closed form worst relative error %.2e, closure %.2e\n", worst, worst_closure);
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(worst_closure, 1e-14);
}

/// The LoadError that coupling the mimics of `urdf` raises.
gen::LoadError coupling_error(const std::string& urdf) {
  try {
    load(urdf, true);
  } catch (const gen::LoadError& e) {
    return e;
  }
  ADD_FAILURE() << urdf << " was accepted";
  return gen::LoadError("", 0, "", "", "");
}

TEST(UrdfMimic, ZeroMultiplierIsAnErrorNamingTheJoint) {
  const gen::LoadError e = coupling_error(kMimic + "/zero_multiplier.urdf");
  EXPECT_EQ(e.line(), 9);
  EXPECT_TRUE(contains(e.element(), "joint 'finger_2'")) << e.what();
  EXPECT_TRUE(contains(e.problem(), "has multiplier 0")) << e.what();
  EXPECT_TRUE(contains(e.fix(), "non-zero multiplier")) << e.what();
}

TEST(UrdfMimic, MimicOfAFixedJointIsAnError) {
  const gen::LoadError e = coupling_error(kMimic + "/mimics_fixed.urdf");
  EXPECT_EQ(e.line(), 8);
  EXPECT_TRUE(contains(e.problem(), "couples 'bracket', which is no moving joint of the tree")) << e.what();
}

TEST(UrdfMimic, FixedFollowerIsSkippedWithAWarning) {
  // talos_reduced fixes its grippers: their <mimic>s couple nothing, and the robot stays a tree.
  const gen::Description d = load(shared_robot("talos/talos_reduced.urdf"), true);
  EXPECT_TRUE(d.closures.empty());
  bool warned = false;
  for (const std::string& w : d.warnings) warned |= contains(w, "is fixed: its <mimic> of 'gripper_left_joint' couples nothing");
  EXPECT_TRUE(warned);
}

/// The LoadError that loading `description` with the extras text `yaml` raises.
gen::LoadError extras_error(const std::string& description, const std::string& yaml) {
  const std::string path = ::testing::TempDir() + "mbgen_mimic_key.yaml";
  std::ofstream(path) << yaml;
  try {
    load(description, std::nullopt, path);
  } catch (const gen::LoadError& e) {
    return e;
  }
  ADD_FAILURE() << yaml << " was accepted";
  return gen::LoadError("", 0, "", "", "");
}

TEST(UrdfMimic, ExtrasMimicKeyIsChecked) {
  const gen::LoadError value = extras_error(kMimic + "/two_link.urdf", "mimic: sometimes\n");
  EXPECT_EQ(value.line(), 1);
  EXPECT_EQ(value.element(), "mimic");
  EXPECT_EQ(value.problem(), "'sometimes' is not one of couple, independent");
  const gen::LoadError mjcf = extras_error(MBGEN_TEST_DATA "/mjcf/joint_coupling.xml", "mimic: couple\n");
  EXPECT_TRUE(contains(mjcf.problem(), "applies to a URDF's <mimic> elements")) << mjcf.what();
  EXPECT_TRUE(contains(mjcf.fix(), "<equality><joint>")) << mjcf.what();
}

}  // namespace
}  // namespace mbgen::test
