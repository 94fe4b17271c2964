// Loading URDF into the tree Model: fixed-joint merging, floating vs fixed base, the "world"
// root idiom, limits, and every shared robot loading both ways.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "load/load_error.hpp"
#include "test_support.hpp"

namespace mbgen {
namespace {

using gen::BaseType;

const std::string kData = MBGEN_TEST_DATA;

TEST(LoadUrdf, FixedJointMergingLumpsInertiaAndKeepsFrames) {
  const Model model = test::load_tree(kData + "/fixed_merge.urdf", BaseType::Fixed);
  ASSERT_EQ(model.nv(), 1);
  ASSERT_EQ(model.num_bodies(), 2);  // world + link1 (tip merged into it)
  // Fixed base: the root link 'base' (5 kg) belongs to the world, not to the moving mass.
  EXPECT_DOUBLE_EQ(model.total_mass(), 3.0);

  const Body& link1 = model.body(BodyIndex(1));
  EXPECT_EQ(link1.name, "link1");
  // By hand: link1 (1 kg at (0, 0, 0.1)) + tip (2 kg at (0, 0, 0.5) + (0.1, 0, 0)).
  const Vec3<double> c(2 * 0.1 / 3, 0, (0.1 + 2 * 0.5) / 3);
  EXPECT_NEAR((link1.inertia.com - c).norm(), 0, 1e-15);
  // Parallel axis about the lumped CoM: d1 = c1 - c, d2 = c2 - c; Ixx = 0.01 + 0.02 + m1 (d1y^2 +
  // d1z^2) + m2 (d2y^2 + d2z^2); Iyy = 0.03 + m1 (d1x^2 + d1z^2) + m2 (...); Ixz = -(m1 d1x d1z + m2 d2x d2z).
  const double d1x = -0.2 / 3, d1z = 0.1 - 1.1 / 3, d2x = 0.1 - 0.2 / 3, d2z = 0.5 - 1.1 / 3;
  EXPECT_NEAR(link1.inertia.inertia_com(0, 0), 0.03 + d1z * d1z + 2 * d2z * d2z, 1e-15);
  EXPECT_NEAR(link1.inertia.inertia_com(1, 1), 0.03 + d1x * d1x + d1z * d1z + 2 * (d2x * d2x + d2z * d2z), 1e-15);
  EXPECT_NEAR(link1.inertia.inertia_com(0, 2), -(d1x * d1z + 2 * d2x * d2z), 1e-15);

  // The merged link and the fixed joint keep their frames, fixed in link1 at z = 0.5.
  for (const char* name : {"tip", "tip_joint"}) {
    auto f = model.find_frame(name);
    ASSERT_TRUE(f) << name;
    EXPECT_EQ(model.frame(*f).body, BodyIndex(1)) << name;
    EXPECT_NEAR((model.frame(*f).X_BF.translation - Vec3<double>(0, 0, 0.5)).norm(), 0, 1e-15) << name;
  }
  EXPECT_EQ(model.frame(model.frame_index("tip")).kind, FrameKind::Link);
  EXPECT_EQ(model.frame(model.frame_index("tip_joint")).kind, FrameKind::Joint);
  EXPECT_EQ(model.frame(model.frame_index("base")).body, kWorldBody);
}

/// hyq_no_sensors.urdf writes its quarter turns in decimal (rpy="1.57079632679 0 0"): 4.9e-12
/// where a 0 is meant, above the 1e-14 every rotation entry is snapped within. The extras'
/// `snap_quarter_turns: 1e-9` makes each joint's fixed rotation a signed permutation exactly; the
/// dynamics move by the rounding the URDF wrote (M within 1e-12 of the literal model's, and not
/// equal to it: the option changed the model), and nothing else in the robot changes.
TEST(LoadUrdf, SnapQuarterTurnsMakesDecimalQuarterTurnsExact) {
  const std::string urdf = test::shared_robot("hyq/hyq_no_sensors.urdf");
  gen::LoadOptions literal_options;
  literal_options.base = BaseType::Floating;
  literal_options.pick_up_robot_yaml = false;
  const Model literal = gen::load_description(urdf, literal_options).model;
  gen::LoadOptions snapped_options;
  snapped_options.extras_file = kData + "/extras/hyq_quarter_turns.yaml";
  const Model snapped = gen::load_description(urdf, snapped_options).model;
  ASSERT_EQ(literal.num_joints(), snapped.num_joints());
  auto is_signed_permutation = [](const Mat3<double>& R) {
    return R.cwiseAbs().rowwise().sum().isApprox(Vec3<double>::Ones(), 0.0) && (R.array() == 0.0 || R.array().abs() == 1.0).all();
  };
  int off_by_rounding = 0;
  for (int j = 1; j < literal.num_joints(); ++j) {
    const Mat3<double>& R = literal.joint(JointIndex(j)).X_PJ.rotation;
    const Mat3<double>& S = snapped.joint(JointIndex(j)).X_PJ.rotation;
    EXPECT_TRUE(is_signed_permutation(S)) << literal.joint(JointIndex(j)).name << "\n" << S;
    EXPECT_LE((R - S).cwiseAbs().maxCoeff(), 1e-9);
    if (!is_signed_permutation(R)) ++off_by_rounding;
    EXPECT_EQ(literal.joint(JointIndex(j)).X_PJ.translation, snapped.joint(JointIndex(j)).X_PJ.translation);
  }
  EXPECT_GT(off_by_rounding, 0) << "hyq's URDF no longer writes its quarter turns in decimal: the test checks nothing";
  Data<double> a(literal), b(snapped);
  std::mt19937_64 rng(5);
  double worst = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const VecX<double> q = random_configuration<double>(literal, rng);
    const MatX<double> Ma = crba<double>(literal, a, q), Mb = crba<double>(snapped, b, q);
    worst = std::max(worst, (Ma - Mb).cwiseAbs().maxCoeff() / Ma.cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(worst, 0.0);
  char figure[32];
  std::snprintf(figure, sizeof figure, "%.3g", worst);
  RecordProperty("mass_matrix_change", figure);
}

TEST(LoadUrdf, SnapQuarterTurnsBeyondDecimalRoundingIsRefused) {
  gen::LoadOptions options;
  options.extras_file = kData + "/extras/quarter_turns_too_loose.yaml";
  try {
    gen::load_description(test::shared_robot("hyq/hyq_no_sensors.urdf"), options);
    FAIL() << "no LoadError";
  } catch (const gen::LoadError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.element(), "snap_quarter_turns");
    EXPECT_NE(e.problem().find("outside [0, 1e-6]"), std::string::npos) << e.what();
  }
}

TEST(LoadUrdf, FloatingBaseAddsAFreeRootBody) {
  const Model model = test::load_tree(kData + "/fixed_merge.urdf", BaseType::Floating);
  EXPECT_TRUE(model.floating_base());
  EXPECT_EQ(model.nq(), 7 + 1);
  EXPECT_EQ(model.nv(), 6 + 1);
  EXPECT_EQ(model.body(BodyIndex(1)).name, "base");
  EXPECT_EQ(model.joint(JointIndex(1)).name, "root_joint");
  EXPECT_DOUBLE_EQ(model.total_mass(), 8.0);  // the base now moves too
}

TEST(LoadUrdf, WorldRootIdiomFixed) {
  const Model model = test::load_tree(kData + "/world_root.urdf", BaseType::Fixed);
  EXPECT_FALSE(model.floating_base());
  EXPECT_EQ(model.nv(), 1);
  EXPECT_EQ(model.frame(model.frame_index("world")).body, kWorldBody);
  // base is welded to the world 1 m up; the hinge sits there.
  EXPECT_EQ(model.frame(model.frame_index("base")).body, kWorldBody);
  EXPECT_NEAR(model.joint(JointIndex(1)).X_PJ.translation.z(), 1.0, 1e-15);
  EXPECT_DOUBLE_EQ(model.total_mass(), 1.0);
}

TEST(LoadUrdf, WorldRootIdiomFloatingReplacesTheWeld) {
  gen::LoadOptions options;
  options.base = BaseType::Floating;
  const gen::Description d = gen::load_description(kData + "/world_root.urdf", options);
  EXPECT_TRUE(d.model.floating_base());
  EXPECT_EQ(d.model.nv(), 7);
  EXPECT_EQ(d.model.joint(JointIndex(1)).name, "world_to_base");
  EXPECT_DOUBLE_EQ(d.model.total_mass(), 3.0);
  ASSERT_EQ(d.warnings.size(), 1u);
  EXPECT_NE(d.warnings[0].find("'world_to_base' from 'world' replaced by a floating joint"), std::string::npos);
}

TEST(LoadUrdf, WorldRootHungByAMovingJointCannotFloat) {
  gen::LoadOptions options;
  options.base = BaseType::Floating;
  const std::string path = kData + "/world_hinge.urdf";
  try {
    gen::load_description(path, options);
    ADD_FAILURE() << "a floating base was accepted for a robot hung from 'world' by a hinge";
  } catch (const gen::LoadError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), 4);
    EXPECT_EQ(e.element(), "link 'world'");
    EXPECT_NE(e.problem().find("only through moving joint(s) (hinge)"), std::string::npos) << e.what();
    EXPECT_NE(e.fix().find("--fixed"), std::string::npos) << e.what();
  }
  // Fixed, it loads as the one-joint arm it is.
  options.base = BaseType::Fixed;
  EXPECT_EQ(gen::load_description(path, options).model.nv(), 1);
}

TEST(LoadUrdf, LimitWithoutRangeIsUnboundedWithAWarning) {
  const gen::Description d = gen::load_description(kData + "/limit_without_range.urdf");
  EXPECT_FALSE(d.model.joint(JointIndex(1)).bounded);
  ASSERT_EQ(d.warnings.size(), 1u);
  EXPECT_NE(d.warnings[0].find("<limit> without lower and upper: loaded as unbounded"), std::string::npos);
  EXPECT_NE(d.warnings[0].find("spin"), std::string::npos);
}

TEST(LoadUrdf, LimitsAndLinesAreRecorded) {
  const gen::Description d = gen::load_description(kData + "/tiny_arm.urdf");
  const Joint& shoulder = d.model.joint(*d.model.find_joint("shoulder"));
  EXPECT_TRUE(shoulder.bounded);
  EXPECT_EQ(shoulder.lower, -1.0);
  EXPECT_EQ(shoulder.upper, 1.0);
  EXPECT_FALSE(d.model.joint(*d.model.find_joint("elbow")).bounded);  // continuous
  EXPECT_EQ(d.urdf_lines.line_of_link("base"), 4);
  EXPECT_EQ(d.urdf_lines.line_of_joint("shoulder"), 7);
  EXPECT_EQ(d.urdf_lines.line_of_joint("no_such_joint"), 0);
}

class EverySharedUrdf : public ::testing::TestWithParam<std::string> {};

TEST_P(EverySharedUrdf, LoadsFixedAndFloating) {
  const Model fixed = test::load_tree(GetParam(), BaseType::Fixed);
  EXPECT_GT(fixed.nv(), 0);
  // The four-bar and the slider-crank are anchored to "world" by moving joints: no base to
  // free, and asking for one is an error (WorldRootHungByAMovingJointCannotFloat).
  if (GetParam().find("/mechanisms/four_bar") != std::string::npos ||
      GetParam().find("/mechanisms/slider_crank") != std::string::npos) {
    EXPECT_THROW(test::load_tree(GetParam(), BaseType::Floating), gen::LoadError);
    return;
  }
  const Model floating = test::load_tree(GetParam(), BaseType::Floating);
  EXPECT_TRUE(floating.floating_base());
  EXPECT_EQ(floating.nv(), fixed.nv() + 6);
  EXPECT_EQ(floating.nq(), fixed.nq() + 7);
  EXPECT_GT(floating.total_mass(), 0);
  EXPECT_GE(floating.total_mass(), fixed.total_mass());
}

INSTANTIATE_TEST_SUITE_P(SharedRobots, EverySharedUrdf, ::testing::ValuesIn(test::all_urdfs()),
                         [](const auto& info) { return test::short_name(info.param); });

}  // namespace
}  // namespace mbgen
