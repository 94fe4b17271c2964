// The YAML extras: mbgen's schema (docs/extras.md) on a tiny arm, and the parallel_legs
// robot.yaml convention on the seven shared closed-loop models.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "load/load_error.hpp"
#include "load/name_match.hpp"
#include "collision/contact_spheres.hpp"
#include "mbgen/joint_limits.hpp"
#include "test_support.hpp"

namespace mbgen {
namespace {

using gen::BaseType;
using gen::Description;
using gen::LoadError;
using gen::LoadOptions;

const std::string kData = MBGEN_TEST_DATA;

Description load_with(const std::string& urdf, const std::string& extras) {
  LoadOptions options;
  options.extras_file = extras;
  return gen::load_description(urdf, options);
}

/// The LoadError a load throws (fails the test if none).
LoadError load_error(const std::string& urdf, const std::string& extras) {
  try {
    load_with(urdf, extras);
  } catch (const LoadError& e) {
    return e;
  }
  ADD_FAILURE() << "no LoadError for " << extras;
  return LoadError("", 0, "", "", "");
}

TEST(LoadExtras, CouplingClosureIsTheSameModelAsTheMimicItWrites) {
  // two_link.urdf's elbow mimics its shoulder (0.5, 0.1); the extras say the same as a closure,
  // and the mimic itself stays independent (a warning). Same rows, same closed dynamics, bit for bit.
  const Description yaml = load_with(kData + "/mimic/two_link.urdf", kData + "/mimic/two_link_gear.yaml");
  const Description mimic = load_with(kData + "/mimic/two_link.urdf", kData + "/mimic/two_link.yaml");
  ASSERT_EQ(yaml.closures.size(), 1u);
  EXPECT_EQ(yaml.closures[0].type, "coupling");
  EXPECT_EQ(yaml.closures[0].source_line, 4);
  EXPECT_EQ(yaml.closed_dof, 1);
  const Model& a = yaml.model;
  const Model& b = mimic.model;
  Data<double> da(a), db(b);
  VecX<double> q(2), v(2), tau(2);
  q << 0.4, 0.3;  // closed: 0.5 * 0.4 + 0.1
  v << 0.8, 0.4;
  tau << 1.5, -0.3;
  ASSERT_EQ(forward_dynamics_loops<double>(a, da, q, v, tau), ClosureStatus::Converged);
  ASSERT_EQ(forward_dynamics_loops<double>(b, db, q, v, tau), ClosureStatus::Converged);
  EXPECT_EQ(da.ddq, db.ddq);
  EXPECT_EQ(closure_residual<double>(a, da, q), closure_residual<double>(b, db, q));
}

TEST(LoadExtras, CouplingWithAFrameKeyIsAnError) {
  const LoadError e = load_error(kData + "/mimic/two_link.urdf", kData + "/extras/bad_coupling.yaml");
  EXPECT_EQ(e.line(), 7);
  EXPECT_EQ(e.element(), "closure 'gear': axis");
  EXPECT_NE(e.problem().find("does not apply to a coupling"), std::string::npos) << e.what();
  const LoadError zero = load_error(kData + "/mimic/two_link.urdf", kData + "/extras/zero_ratio_coupling.yaml");
  EXPECT_EQ(zero.line(), 2);
  EXPECT_EQ(zero.element(), "closure 'gear': ratio");
  EXPECT_NE(zero.problem().find("is 0: the child would be held constant"), std::string::npos) << zero.what();
}

TEST(LoadExtras, EveryKeyOfTheSchema) {
  const Description d = load_with(kData + "/tiny_arm.urdf", kData + "/extras/tiny_arm_full.yaml");
  EXPECT_EQ(d.robot_name, "tiny_arm_ns");
  EXPECT_EQ(d.base, BaseType::Floating);
  EXPECT_TRUE(d.model.floating_base());

  ASSERT_EQ(d.closures.size(), 2u);
  const gen::ClosureSpec& rod = d.closures[0];
  EXPECT_EQ(rod.name, "tool_to_leg");
  EXPECT_EQ(rod.type, "revolute");
  EXPECT_EQ(rod.frame_a, "tool");
  EXPECT_EQ(rod.frame_b, "leg");
  EXPECT_NEAR((rod.X_AC.translation - Vec3<double>(0, 0, -0.4)).norm(), 0, 1e-15);
  EXPECT_NEAR((rod.X_AC.rotation * Vec3<double>::UnitX() - Vec3<double>::UnitY()).norm(), 0, 1e-15);  // yaw 90°
  EXPECT_NEAR(rod.X_BC.translation.norm(), 0, 1e-15);  // xyz defaults to 0 when only rpy is given
  EXPECT_NEAR((rod.X_BC.rotation * Vec3<double>::UnitX() - Vec3<double>::UnitY()).norm(), 0, 1e-15);
  EXPECT_NEAR((rod.axis - Vec3<double>::UnitX()).norm(), 0, 1e-15);  // normalised
  EXPECT_EQ(rod.source_line, 8);
  // Joint names resolve to their child bodies' frames.
  const gen::ClosureSpec& ball = d.closures[1];
  EXPECT_EQ(ball.type, "spherical");
  EXPECT_EQ(d.model.frame(ball.resolved_a).name, "lower");
  EXPECT_EQ(d.model.frame(ball.resolved_b).name, "leg");

  EXPECT_EQ(d.actuated_joints, (std::vector<std::string>{"shoulder", "knee"}));
  ASSERT_EQ(d.drives.size(), 2u);
  EXPECT_EQ(d.drives[0].joint, "shoulder");
  EXPECT_EQ(d.drives[0].gear_ratio, 100);
  EXPECT_EQ(d.drives[0].rotor_inertia, 1.2e-4);
  EXPECT_EQ(d.drives[0].model, "armature");
  EXPECT_EQ(d.drives[1].model, "body");

  ASSERT_EQ(d.ssv.size(), 2u);
  ASSERT_EQ(d.ssv.at("tool").size(), 2u);
  EXPECT_EQ(d.ssv.at("tool")[0].kind, gen::SsvPrimitive::Kind::Point);
  EXPECT_EQ(d.ssv.at("tool")[1].kind, gen::SsvPrimitive::Kind::Triangle);
  EXPECT_EQ(d.ssv.at("tool")[1].points.size(), 3u);
  EXPECT_EQ(d.ssv.at("upper")[0].kind, gen::SsvPrimitive::Kind::Line);
  EXPECT_EQ(d.ssv.at("upper")[0].radius, 0.05);

  ASSERT_TRUE(d.scene);
  EXPECT_EQ(d.scene->outputs,
            (std::vector<std::string>{"forward_dynamics", "mass_matrix", "jacobians", "distances"}));
  EXPECT_EQ(d.scene->jacobian_frames, (std::vector<std::string>{"tool", "leg"}));
  EXPECT_EQ(d.scene->collision_margin, 0.05);
  ASSERT_EQ(d.scene->collision_exclude.size(), 1u);
  EXPECT_EQ(d.scene->collision_exclude[0], (std::pair<std::string, std::string>{"upper", "base"}));
  EXPECT_EQ(d.scene->prune_samples, 2000);
  EXPECT_EQ(d.scene->scalar, "float");
}

TEST(LoadExtras, CommandLineBaseOverridesTheExtras) {
  LoadOptions options;
  options.extras_file = kData + "/extras/tiny_arm_full.yaml";
  options.base = BaseType::Fixed;
  EXPECT_FALSE(gen::load_description(kData + "/tiny_arm.urdf", options).model.floating_base());
}

TEST(LoadExtras, UnknownTopLevelKeySuggestsTheClosest) {
  const LoadError e = load_error(kData + "/tiny_arm.urdf", kData + "/extras/unknown_top_key.yaml");
  EXPECT_EQ(e.line(), 2);  // 1-based, though yaml-cpp counts from 0
  EXPECT_EQ(e.element(), "key 'closure'");
  EXPECT_NE(e.fix().find("did you mean 'closures'?"), std::string::npos) << e.what();
}

TEST(LoadExtras, UnknownClosureLinkSuggestsTheClosest) {
  const LoadError e = load_error(kData + "/tiny_arm.urdf", kData + "/extras/unknown_closure_link.yaml");
  EXPECT_EQ(e.line(), 4);
  EXPECT_NE(e.problem().find("names 'tol'"), std::string::npos) << e.what();
  EXPECT_NE(e.fix().find("did you mean 'tool'?"), std::string::npos) << e.what();
}

TEST(LoadExtras, BadEnumValueSuggestsTheClosest) {
  const LoadError e = load_error(kData + "/tiny_arm.urdf", kData + "/extras/bad_base.yaml");
  EXPECT_EQ(e.line(), 2);
  EXPECT_NE(e.fix().find("did you mean 'floating'?"), std::string::npos) << e.what();
}

TEST(LoadExtras, DuplicateKeyIsAnError) {
  const LoadError e = load_error(kData + "/tiny_arm.urdf", kData + "/extras/duplicate_key.yaml");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.element(), "key 'base'");
  EXPECT_EQ(e.problem(), "is given twice");
}

// scene: contact (docs/extras.md): the values as given, the plane's normal normalised, and a
// sphere per SSV vertex of the listed links (a line gives 2, a point 1), in the body frame.
TEST(LoadExtras, ContactSceneIsRead) {
  const Description d = load_with(kData + "/tiny_arm.urdf", kData + "/extras/contact.yaml");
  ASSERT_TRUE(d.scene && d.scene->contact);
  const gen::ContactSpec& c = *d.scene->contact;
  EXPECT_EQ(c.links, std::vector<std::string>{"tool"});
  EXPECT_EQ(c.parameters.stiffness, 1e6);
  EXPECT_EQ(c.parameters.damping, 0.5);
  EXPECT_EQ(c.parameters.exponent, 1.0);
  EXPECT_EQ(c.parameters.friction, 0.3);
  EXPECT_EQ(c.parameters.stiction_velocity, 0.01);
  EXPECT_EQ(c.ground.normal, Vec3<double>(0, 0, 1));
  EXPECT_EQ(c.ground.offset, -0.1);
  const std::vector<ContactSphere> spheres = gen::contact_spheres(d);
  ASSERT_EQ(spheres.size(), 3u);
  EXPECT_EQ(spheres[1].name, "tool/0/1");
  EXPECT_EQ(spheres[2].radius, 0.01);
  const Frame& tool = d.model.frame(d.model.frame_index("tool"));
  EXPECT_EQ(spheres[1].body, tool.body);
  EXPECT_LT((spheres[1].center - tool.X_BF.act(Vec3<double>(0.1, 0, 0))).norm(), 1e-15);
}

TEST(LoadExtras, ContactLinkWithoutSsvIsAnErrorWithTheFix) {
  const LoadError e = load_error(kData + "/tiny_arm.urdf", kData + "/extras/contact_link_without_ssv.yaml");
  EXPECT_EQ(e.line(), 5);
  EXPECT_NE(e.problem().find("'lower' has no swept-sphere volume"), std::string::npos) << e.what();
  EXPECT_NE(e.fix().find("ssv:"), std::string::npos) << e.what();
}

TEST(LoadExtras, ContactParametersOutOfRangeAreErrors) {
  LoadError e = load_error(kData + "/tiny_arm.urdf", kData + "/extras/contact_negative_stiffness.yaml");
  EXPECT_EQ(e.line(), 6);
  EXPECT_EQ(e.element(), "scene: contact: stiffness");
  e = load_error(kData + "/tiny_arm.urdf", kData + "/extras/contact_zero_normal.yaml");
  EXPECT_EQ(e.element(), "scene: contact: ground: normal");
  EXPECT_EQ(e.problem(), "is zero");
}

// scene: derivatives_wrt (docs/extras.md): the inputs as given; an empty list, an unknown input or
// one named twice are errors at their line.
TEST(LoadExtras, DerivativesWrtIsRead) {
  const Description d = load_with(kData + "/tiny_arm.urdf", kData + "/extras/derivatives_q_tau.yaml");
  ASSERT_TRUE(d.scene);
  EXPECT_EQ(d.scene->derivatives_wrt, (std::vector<std::string>{"q", "tau"}));
  EXPECT_TRUE(load_with(kData + "/tiny_arm.urdf", kData + "/extras/contact.yaml").scene->derivatives_wrt.empty());
}

TEST(LoadExtras, DerivativesWrtThatIsEmptyUnknownOrRepeatedIsAnError) {
  const std::string path = (std::filesystem::temp_directory_path() / "mbgen_test_derivatives_wrt.yaml").string();
  const auto error_for = [&](const std::string& list) {
    std::ofstream(path) << "scene:\n  outputs: [fd_derivatives]\n  derivatives_wrt: " << list << "\n";
    return load_error(kData + "/tiny_arm.urdf", path);
  };
  LoadError e = error_for("[]");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.problem(), "is empty");
  e = error_for("[q, qdd]");
  EXPECT_EQ(e.element(), "scene: derivatives_wrt");
  EXPECT_NE(e.problem().find("'qdd' is not one of q, v, tau"), std::string::npos) << e.what();
  e = error_for("[q, tau, q]");
  EXPECT_EQ(e.problem(), "names q twice");
  e = error_for("q");
  EXPECT_EQ(e.element(), "scene: derivatives_wrt");
}

// scene: rigid_contacts (docs/extras.md): each frame and kind as given (kind frame when left out, a
// moving joint naming its child link); an empty list, an unknown frame (with a suggestion), a frame
// fixed in the world, a frame named twice or an unknown kind are errors at their line.
TEST(LoadExtras, RigidContactsAreRead) {
  const std::string path = (std::filesystem::temp_directory_path() / "mbgen_test_rigid_contacts.yaml").string();
  std::ofstream(path) << "scene:\n  rigid_contacts: [{frame: tool, kind: point}, {frame: knee}]\n";
  const Description d = load_with(kData + "/tiny_arm.urdf", path);
  ASSERT_TRUE(d.scene);
  ASSERT_EQ(d.scene->rigid_contacts.size(), 2u);
  EXPECT_EQ(d.scene->rigid_contacts[0].frame, "tool");
  EXPECT_EQ(d.scene->rigid_contacts[0].kind, "point");
  EXPECT_EQ(d.scene->rigid_contacts[1].frame, "leg");  // the prismatic joint's child
  EXPECT_EQ(d.scene->rigid_contacts[1].kind, "frame");
  EXPECT_EQ(d.scene->rigid_contacts[1].line, 2);
}

TEST(LoadExtras, RigidContactsThatAreEmptyUnknownFixedOrRepeatedAreErrors) {
  const std::string path = (std::filesystem::temp_directory_path() / "mbgen_test_rigid_contacts_bad.yaml").string();
  const auto error_for = [&](const std::string& list) {
    std::ofstream(path) << "scene:\n  outputs: [rigid_contact_fd_derivatives]\n  rigid_contacts: " << list << "\n";
    return load_error(kData + "/tiny_arm.urdf", path);
  };
  LoadError e = error_for("[]");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.problem(), "is empty");
  e = error_for("[{frame: tol}]");
  EXPECT_EQ(e.element(), "scene: rigid_contacts[0]: frame");
  EXPECT_NE(e.problem().find("'tol'"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("tool"), std::string::npos) << e.what();  // did you mean
  e = error_for("[{frame: base}]");
  EXPECT_EQ(e.problem(), "'base' is fixed in the world");
  e = error_for("[{frame: tool}, {frame: tool, kind: point}]");
  EXPECT_EQ(e.element(), "scene: rigid_contacts[1]: frame");
  EXPECT_EQ(e.problem(), "names 'tool' twice");
  e = error_for("[{frame: tool, kind: line}]");
  EXPECT_EQ(e.element(), "scene: rigid_contacts[0]: kind");
  e = error_for("[{kind: point}]");
  EXPECT_EQ(e.problem(), "has no frame");
  e = error_for("[{frame: tool, mu: 1}]");
  EXPECT_EQ(e.element(), "scene: rigid_contacts[0]: key 'mu'");
}

// scene: joint_limits (docs/extras.md): the law's numbers and the per-joint exceptions as given;
// `false` turns the stops off; absent, the defaults (on).
TEST(LoadExtras, JointLimitsSceneIsRead) {
  const Description d = load_with(kData + "/tiny_arm.urdf", kData + "/extras/joint_limits.yaml");
  ASSERT_TRUE(d.scene);
  const JointStopParameters& p = d.scene->joint_limits;
  EXPECT_TRUE(p.enabled);
  EXPECT_EQ(p.frequency, 50);
  EXPECT_EQ(p.damping, 1.5);
  EXPECT_EQ(p.exponent, 1.5);
  EXPECT_EQ(p.max_damping_ratio, 0.5);
  ASSERT_EQ(p.joints.size(), 2u);
  ASSERT_NE(p.setting("knee"), nullptr);
  EXPECT_TRUE(p.setting("knee")->free);
  ASSERT_NE(p.setting("shoulder"), nullptr);
  EXPECT_FALSE(p.setting("shoulder")->free);
  EXPECT_EQ(p.setting("shoulder")->stiffness, 2e4);
  EXPECT_EQ(p.setting("shoulder")->damping, 4);
  EXPECT_FALSE(load_with(kData + "/tiny_arm.urdf", kData + "/extras/joint_limits_off.yaml").scene->joint_limits.enabled);
  EXPECT_TRUE(load_with(kData + "/tiny_arm.urdf", kData + "/extras/contact.yaml").scene->joint_limits.enabled);
}

TEST(LoadExtras, JointLimitsOnAJointWithoutRangeOrOutOfRangeAreErrors) {
  LoadError e = load_error(kData + "/tiny_arm.urdf", kData + "/extras/joint_limits_without_range.yaml");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.element(), "scene: joint_limits: free");
  EXPECT_NE(e.problem().find("'elbow', which has no position range"), std::string::npos) << e.what();
  e = load_error(kData + "/tiny_arm.urdf", kData + "/extras/joint_limits_bad_numbers.yaml");
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.element(), "scene: joint_limits: joints: shoulder: stiffness");
  EXPECT_EQ(e.problem(), "is out of range");
}

TEST(LoadExtras, DriveOnAFixedJointIsAnError) {
  const LoadError e = load_error(kData + "/tiny_arm.urdf", kData + "/extras/fixed_joint_drive.yaml");
  EXPECT_NE(e.problem().find("'tool_joint', a fixed joint"), std::string::npos) << e.what();
}

TEST(LoadExtras, SnapQuarterTurnsIsRefusedForAnMjcf) {
  const LoadError e = load_error(test::shared_robot("cassie_mjcf/cassie.xml"), kData + "/extras/hyq_quarter_turns.yaml");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.element(), "snap_quarter_turns");
  EXPECT_NE(e.problem().find("is an MJCF"), std::string::npos) << e.what();
}

// snap_quarter_turns and mimic apply to a URDF only: each other format is refused, naming it.
TEST(LoadExtras, UrdfOnlyKeysAreRefusedForTheOtherFormats) {
  const std::string sdf = test::shared_robot("cassie_sdf/cassie_v2.sdf"), mjcf = test::shared_robot("cassie_mjcf/cassie.xml");
  const std::string dir = ::testing::TempDir();
  std::ofstream(dir + "snap.yaml") << "snap_quarter_turns: 1e-9\n";
  std::ofstream(dir + "mimic.yaml") << "mimic: couple\n";
  struct Case {
    std::string description, extras, element, problem;
  };
  for (const Case& c : {Case{sdf, "snap.yaml", "snap_quarter_turns", "is an SDFormat file"},
                        Case{mjcf, "snap.yaml", "snap_quarter_turns", "is an MJCF"},
                        Case{sdf, "mimic.yaml", "mimic", "is an SDFormat file"},
                        Case{mjcf, "mimic.yaml", "mimic", "is an MJCF"}}) {
    const LoadError e = load_error(c.description, dir + c.extras);
    EXPECT_EQ(e.element(), c.element) << c.description;
    EXPECT_EQ(e.line(), 1) << e.what();
    EXPECT_NE(e.problem().find(c.problem), std::string::npos) << e.what();
  }
}

TEST(LoadExtras, MixingTheTwoSchemasIsAnError) {
  const LoadError e = load_error(kData + "/tiny_arm.urdf", kData + "/extras/mixed_schemas.yaml");
  EXPECT_NE(e.problem().find("mixes the keys of the two schemas"), std::string::npos) << e.what();
}

TEST(NameMatch, CountsCodePointsNotBytes) {
  EXPECT_EQ(gen::edit_distance("cafe", "caf\u00e9"), 1);  // 2 in bytes
  EXPECT_EQ(gen::edit_distance("left_spherical_free_foot", "left_s\u0125erical_free_foot"), 2);  // "ph" -> "ĥ"
  EXPECT_EQ(gen::edit_distance("kitten", "sitting"), 3);
  EXPECT_EQ(gen::edit_distance("", "abc"), 3);
  EXPECT_EQ(gen::closest_name("elbw", {"knee", "elbow", "shoulder"}), "elbow");
  EXPECT_FALSE(gen::closest_name("torso", {"knee", "elbow"}));
}

// ---- parallel_legs robot.yaml --------------------------------------------------------------

struct LegsCase {
  std::string model;
  int tree_dof;  ///< with joint_name/joint_type applied
  int closures;
  int motors;
  std::string extras = "";  ///< instead of the robot.yaml beside the URDF
};

// Expected figures from /work/shared/robots/LOOPS.md ("Figures at the assembled pose"), computed
// there with an independent rigid-body library. Tree DoF there counts a SPHERICAL override as 3
// DoF and a UJOINT_XY as 2, as the loader's revolute chains do. disney_robot's robot.yaml
// misspells a joint (an error, below): its figures are for the 9 valid overrides, a copy of the
// file without the misspelt entry (tests/data/parallel_legs).
const std::vector<LegsCase> kLegsCases = {
    {"5bar_linkage", 6, 1, 2},      {"cassie_like", 19, 2, 5},       {"robot_delta", 14, 3, 2},
    {"talos_like", 13, 1, 6},       {"wl16_like", 42, 5, 6},         {"digit_like_2legs", 48, 6, 12},
    {"disney_robot", 50, 6, 12, kData + "/parallel_legs/disney_robot_9_of_10.yaml"},
};

class ParallelLegs : public ::testing::TestWithParam<LegsCase> {};

TEST_P(ParallelLegs, RobotYamlBesideTheUrdfIsPickedUp) {
  const LegsCase& c = GetParam();
  const std::string urdf = test::shared_robot("parallel_legs/" + c.model + "/robot.urdf");
  const Description d = c.extras.empty() ? gen::load_description(urdf) : load_with(urdf, c.extras);
  EXPECT_EQ(d.extras_file, c.extras.empty() ? test::shared_robot("parallel_legs/" + c.model + "/robot.yaml") : c.extras);
  ASSERT_EQ(static_cast<int>(d.closures.size()), c.closures);
  for (const gen::ClosureSpec& closure : d.closures) {
    EXPECT_EQ(closure.type, "6d");
    EXPECT_TRUE(closure.resolved_a.valid() && closure.resolved_b.valid());
    EXPECT_NE(d.model.frame(closure.resolved_a).body, d.model.frame(closure.resolved_b).body);
  }
  EXPECT_EQ(static_cast<int>(d.actuated_joints.size()), c.motors);
  EXPECT_EQ(d.model.nv(), c.tree_dof);
}

TEST_P(ParallelLegs, NoPickUpWhenDisabled) {
  LoadOptions options;
  options.pick_up_robot_yaml = false;
  const Description d =
      gen::load_description(test::shared_robot("parallel_legs/" + GetParam().model + "/robot.urdf"), options);
  EXPECT_TRUE(d.extras_file.empty());
  EXPECT_TRUE(d.closures.empty());
}

INSTANTIATE_TEST_SUITE_P(SharedRobots, ParallelLegs, ::testing::ValuesIn(kLegsCases),
                         [](const auto& info) { return info.param.model; });

TEST(ParallelLegsConvention, JointNamesResolveToTheirChildFrames) {
  const Description d = gen::load_description(test::shared_robot("parallel_legs/5bar_linkage/robot.urdf"));
  ASSERT_EQ(d.closures.size(), 1u);
  // closedloop1_A and closedloop1_B are revolute joints; their child links are sphere, sphere_2.
  EXPECT_EQ(d.model.frame(d.closures[0].resolved_a).name, "sphere");
  EXPECT_EQ(d.model.frame(d.closures[0].resolved_b).name, "sphere_2");
  EXPECT_EQ(d.actuated_joints, (std::vector<std::string>{"mot1", "mot2"}));
}

TEST(ParallelLegsConvention, JointTypesBecomeRevoluteChains) {
  // SPHERICAL: <joint>_x, _y, _z; UJOINT_XY: <joint>_x, _y; massless links between; the last
  // joint moves the original child body (topology.hpp).
  const Description d = gen::load_description(test::shared_robot("parallel_legs/digit_like_2legs/robot.urdf"));
  ASSERT_EQ(d.joint_type_overrides.size(), 12u);
  EXPECT_EQ(d.joint_type_overrides.at("spherical_free_hip"), "SPHERICAL");
  EXPECT_EQ(d.joint_type_overrides.at("spherical_free_knee_left"), "UJOINT_XY");
  const Model& m = d.model;
  EXPECT_FALSE(m.find_joint("spherical_free_hip"));
  for (const char* axis : {"x", "y", "z"}) {
    auto j = m.find_joint(std::string("spherical_free_hip_") + axis);
    ASSERT_TRUE(j) << axis;
    EXPECT_EQ(m.joint(*j).type, JointType::Revolute);
    EXPECT_EQ(m.joint(*j).axis, Vec3<double>::Unit(std::string("xyz").find(axis)));
  }
  EXPECT_FALSE(m.find_joint("spherical_free_knee_left_z"));
  const Joint& y = m.joint(*m.find_joint("spherical_free_knee_left_y"));
  const Body& x_link = m.body(y.parent);
  EXPECT_EQ(x_link.name, "spherical_free_knee_left_x_link");
  EXPECT_EQ(x_link.inertia.mass, 0.0);
  EXPECT_EQ(m.joint(x_link.joint).name, "spherical_free_knee_left_x");
  EXPECT_TRUE(m.find_frame("spherical_free_knee_left_x_link"));
}

TEST(ParallelLegsConvention, DisneyMisspeltJointNameIsAnErrorWithTheSuggestion) {
  // LOOPS.md: disney_robot's robot.yaml names 'left_spherical_free_foot', the URDF joint is
  // 'left_s\u0125erical_free_foot'. Skipping the override would load another mechanism.
  const std::string urdf = test::shared_robot("parallel_legs/disney_robot/robot.urdf");
  const LoadError e = load_error(urdf, test::shared_robot("parallel_legs/disney_robot/robot.yaml"));
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.element(), "joint_name[5]");
  EXPECT_NE(e.problem().find("names 'left_spherical_free_foot', which is no moving joint"), std::string::npos) << e.what();
  EXPECT_NE(e.fix().find("did you mean 'left_s\u0125erical_free_foot'?"), std::string::npos) << e.what();
  // The corrected copy loads with all 10 overrides.
  const Description d = load_with(urdf, kData + "/parallel_legs/disney_robot_corrected.yaml");
  EXPECT_EQ(d.joint_type_overrides.size(), 10u);
  EXPECT_EQ(d.model.nv(), 52);
}

TEST(ParallelLegsConvention, UnknownMotorIsAnErrorWithSuggestion) {
  const LoadError e = load_error(kData + "/tiny_arm.urdf", kData + "/bad/unknown_joint.yaml");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.element(), "name_mot[1]");
  EXPECT_NE(e.fix().find("did you mean 'elbow'?"), std::string::npos) << e.what();
}

}  // namespace
}  // namespace mbgen
