// Loading MJCF into the tree Model: one tiny file per rule under tests/data/mjcf/ (angle units,
// eulerseq, quaternion order, default classes, joint anchors and ref, ball joints, several joints
// in a body, free joints, connect closures, error messages by their text), the shared MJCF
// robots, and one closed-form check (a pendulum hinged off its body origin).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <iterator>

#include "load/load_error.hpp"
#include "model/topology.hpp"
#include "test_support.hpp"

namespace mbgen {
namespace {

const std::string kMjcf = std::string(MBGEN_TEST_DATA) + "/mjcf";
constexpr double kPi = 3.14159265358979323846;

gen::Description load(const std::string& file) {
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  return gen::load_description(kMjcf + "/" + file, options);
}

Mat3<double> rot(const Vec3<double>& axis, double angle) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

/// World pose of a frame at configuration q.
SE3<double> frame_pose(const Model& model, const std::string& frame, const VecX<double>& q) {
  Data<double> data(model);
  forward_kinematics<double>(model, data, q);
  update_frame_placements<double>(model, data);
  return data.X_WF[model.frame_index(frame)];
}

/// The LoadError a file raises (fails the test if it loads).
gen::LoadError load_error(const std::string& file) {
  try {
    load(file);
  } catch (const gen::LoadError& e) {
    return e;
  }
  ADD_FAILURE() << file << " loaded without error";
  return gen::LoadError("", 0, "", "", "");
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// ---- Orientation and angle units ------------------------------------------------------------

TEST(LoadMjcf, OrientationAttributesInDegreesAndQuatScalarFirst) {
  const Model model = load("orientations.xml").model;
  const Vec3<double> x = Vec3<double>::UnitX(), y = Vec3<double>::UnitY(), z = Vec3<double>::UnitZ();
  const struct {
    const char* frame;
    Mat3<double> expected;
  } cases[] = {{"by_euler", rot(x, kPi / 2)},     // degrees, not radians (90 rad would be far off)
               {"by_axisangle", rot(z, kPi / 2)},
               {"by_quat", rot(z, kPi / 2)},      // w x y z: read as x y z w it would be a turn about x
               {"by_xyaxes", rot(z, kPi / 2)},
               {"by_zaxis", rot(y, kPi / 2)}};
  for (const auto& c : cases) {
    const Frame& f = model.frame(model.frame_index(c.frame));
    EXPECT_EQ(f.body, kWorldBody) << c.frame;  // welded to the world, kept as a frame
    EXPECT_EQ(f.kind, FrameKind::Link) << c.frame;
    EXPECT_NEAR((f.X_BF.rotation - c.expected).norm(), 0, 1e-15) << c.frame;
  }
}

TEST(LoadMjcf, EulerSequenceLowerCaseIsIntrinsicUpperCaseExtrinsic) {
  const Vec3<double> x = Vec3<double>::UnitX(), y = Vec3<double>::UnitY(), z = Vec3<double>::UnitZ();
  // zyx on moving axes: first z, then the new y, then the newest x: R = Rz(a) Ry(b) Rx(c).
  const Model intrinsic = load("euler_intrinsic.xml").model;
  EXPECT_NEAR((intrinsic.frame(intrinsic.frame_index("rotated")).X_BF.rotation - rot(z, 0.3) * rot(y, 0.5) * rot(x, 0.7)).norm(), 0, 1e-15);
  // ZYX on fixed axes: the last rotation is applied last, on the left: R = Rx(c) Ry(b) Rz(a).
  const Model extrinsic = load("euler_extrinsic.xml").model;
  EXPECT_NEAR((extrinsic.frame(extrinsic.frame_index("rotated")).X_BF.rotation - rot(x, 0.7) * rot(y, 0.5) * rot(z, 0.3)).norm(), 0, 1e-15);
}

// ---- Joints ------------------------------------------------------------------------------------

TEST(LoadMjcf, JointRefMakesQEqualQposAndDegreesConvertRange) {
  const Model model = load("joint_ref.xml").model;
  const Joint& j = model.joint(*model.find_joint("j"));
  EXPECT_TRUE(j.bounded);
  EXPECT_NEAR(j.lower, -kPi / 2, 1e-15);
  EXPECT_NEAR(j.upper, kPi / 2, 1e-15);
  // At q = ref (30 deg) the body is where the file puts it: the identity.
  VecX<double> q(1);
  q << kPi / 6;
  EXPECT_NEAR((frame_pose(model, "arm", q).rotation - Mat3<double>::Identity()).norm(), 0, 1e-15);
  q << 0;
  EXPECT_NEAR((frame_pose(model, "arm", q).rotation - rot(Vec3<double>::UnitZ(), -kPi / 6)).norm(), 0, 1e-15);
}

TEST(LoadMjcf, AnchorOffsetPendulumMatchesClosedForm) {
  // Hinge about y at (0, 0, 2.5) in the world; CoM 1 m below it; I_yy about the CoM 0.2; m = 2.
  // Closed form: M = I_yy + m d^2 = 0.2 + 2 * 1^2; gravity torque dV/dq = m g d sin q (V = -m g d cos q).
  const gen::Description d = load("pendulum_anchor.xml");
  const Model& model = d.model;
  ASSERT_EQ(model.nv(), 1);
  Data<double> data(model);
  for (double angle : {0.0, 0.4, -1.3, 2.9}) {
    VecX<double> q(1), zero = VecX<double>::Zero(1);
    q << angle;
    EXPECT_NEAR(crba<double>(model, data, q)(0, 0), 0.2 + 2.0 * 1.0, 1e-14) << angle;
    EXPECT_NEAR(rnea<double>(model, data, q, zero, zero)[0], 2.0 * 9.81 * 1.0 * std::sin(angle), 1e-13) << angle;
    // The body origin (0.5 m below the anchor) and the site swing about the anchor.
    const Mat3<double> R = rot(Vec3<double>::UnitY(), angle);
    const Vec3<double> anchor(0, 0, 2.5);
    EXPECT_NEAR((frame_pose(model, "pendulum", q).translation - (anchor + R * Vec3<double>(0, 0, -0.5))).norm(), 0, 1e-15);
    EXPECT_NEAR((frame_pose(model, "tip", q).translation - (anchor + R * Vec3<double>(0, 0, -1.5))).norm(), 0, 1e-15);
  }
  EXPECT_EQ(model.frame(model.frame_index("tip")).kind, FrameKind::User);
  EXPECT_EQ(model.frame(model.frame_index("swing")).kind, FrameKind::Joint);
  EXPECT_EQ(d.urdf_lines.line_of_joint("swing"), 6);
  EXPECT_EQ(d.urdf_lines.line_of_link("pendulum"), 5);
}

TEST(LoadMjcf, BallJointIsAnXyzHingeChain) {
  const Model model = load("ball.xml").model;
  ASSERT_EQ(model.nv(), 3);
  const char* axes = "xyz";
  for (int k = 0; k < 3; ++k) {
    const Joint& j = model.joint(JointIndex(k + 1));
    EXPECT_EQ(j.name, std::string("socket_") + axes[k]);
    EXPECT_EQ(j.type, JointType::Revolute);
    EXPECT_EQ(j.axis, Vec3<double>::Unit(k));
    EXPECT_FALSE(j.bounded);
    EXPECT_EQ(j.armature, 0.1);
  }
  EXPECT_EQ(model.body(BodyIndex(1)).name, "rod/socket_x");  // massless intermediates
  EXPECT_EQ(model.body(BodyIndex(1)).inertia.mass, 0.0);
  EXPECT_EQ(model.body(BodyIndex(3)).name, "rod");
  EXPECT_EQ(model.body(BodyIndex(3)).inertia.mass, 1.0);
  // At zero angles the chain's rates are the angular velocity in the rod's frame.
  Data<double> data(model);
  VecX<double> q = VecX<double>::Zero(3), v(3);
  v << 0.3, -0.2, 0.7;
  forward_kinematics<double>(model, data, q, v);
  EXPECT_NEAR((data.v[BodyIndex(3)].angular - v).norm(), 0, 1e-15);
}

TEST(LoadMjcf, SeveralJointsInABodyComposeAboutTheirAnchors) {
  // MuJoCo: X_WB = X_PB T(p1) R(a1, q1) T(-p1) T(p2) T(a2 q2) T(-p2).
  const Model model = load("two_joints.xml").model;
  ASSERT_EQ(model.nv(), 2);
  EXPECT_EQ(model.joint(JointIndex(1)).name, "first");
  EXPECT_EQ(model.joint(JointIndex(2)).type, JointType::Prismatic);
  SE3<double> X_PB;
  X_PB.translation = Vec3<double>(0.1, 0.2, 0.3);
  X_PB.rotation = rot(Vec3<double>::UnitX(), 0.1) * rot(Vec3<double>::UnitY(), 0.2) * rot(Vec3<double>::UnitZ(), 0.3);
  auto translation = [](const Vec3<double>& p) {
    SE3<double> X;
    X.translation = p;
    return X;
  };
  const Vec3<double> p1(0, 0, 0.2), p2(0.3, 0, 0), a2 = Vec3<double>(0, 1, 1).normalized();
  VecX<double> q(2);
  q << 0.8, -0.35;
  SE3<double> R1;
  R1.rotation = rot(Vec3<double>::UnitX(), q[0]);
  const SE3<double> X_WB = X_PB * translation(p1) * R1 * translation(-p1) * translation(p2) * translation(a2 * q[1]) * translation(-p2);
  const SE3<double> X = frame_pose(model, "b", q);
  EXPECT_NEAR((X.translation - X_WB.translation).norm(), 0, 1e-15);
  EXPECT_NEAR((X.rotation - X_WB.rotation).norm(), 0, 1e-15);
  // Each joint's frame sits at its anchor, fixed in the body it moves.
  SE3<double> first = X_PB * translation(p1) * R1;
  EXPECT_NEAR((frame_pose(model, "first", q).translation - first.translation).norm(), 0, 1e-15);
  EXPECT_EQ(model.frame(model.frame_index("first")).body, BodyIndex(1));
  EXPECT_NEAR((frame_pose(model, "second", q).translation - X_WB.act(p2)).norm(), 0, 1e-15);
  EXPECT_EQ(model.body(BodyIndex(1)).name, "b/first");
  const SE3<double> site = frame_pose(model, "s", q);
  EXPECT_NEAR((site.translation - X_WB.act(Vec3<double>(0.2, 0.1, 0))).norm(), 0, 1e-15);
  // The inertia stays with the MJCF body: its CoM lands where MuJoCo puts it.
  Data<double> data(model);
  forward_kinematics<double>(model, data, q);
  const BodyIndex last(2);
  EXPECT_NEAR((data.X_WB[last].act(model.body(last).inertia.com) - X_WB.act(Vec3<double>(0.1, 0, -0.1))).norm(), 0, 1e-15);
}

TEST(LoadMjcf, FreeJointMakesAFloatingBaseWithGravityAndActuators) {
  const gen::Description d = load("free.xml");
  EXPECT_EQ(d.base, gen::BaseType::Floating);
  EXPECT_TRUE(d.model.floating_base());
  EXPECT_EQ(d.model.nq(), 8);
  EXPECT_EQ(d.model.joint(JointIndex(1)).name, "float");
  EXPECT_EQ(d.model.gravity, Vec3<double>(0, 0, -3.7));
  EXPECT_EQ(d.actuated_joints, std::vector<std::string>{"hip"});
  // --fixed welds the free body where the file puts it.
  gen::LoadOptions options;
  options.base = gen::BaseType::Fixed;
  options.pick_up_robot_yaml = false;
  const gen::Description fixed = gen::load_description(kMjcf + "/free.xml", options);
  EXPECT_EQ(fixed.model.nv(), 1);
  EXPECT_NEAR((fixed.model.joint(JointIndex(1)).X_PJ.translation - Vec3<double>(0, 0, 0.8)).norm(), 0, 1e-15);
}

// ---- Default classes -----------------------------------------------------------------------

TEST(LoadMjcf, DefaultClassesNestAndChildclassInherits) {
  const gen::Description d = load("defaults.xml");
  const Model& model = d.model;
  const Joint& b = model.joint(*model.find_joint("inherits_b"));  // childclass b: b's damping, a's armature
  EXPECT_EQ(b.damping, 3.0);
  EXPECT_EQ(b.armature, 0.5);
  const Joint& a = model.joint(*model.find_joint("class_a"));  // class a beats the inherited childclass b
  EXPECT_EQ(a.damping, 1.0);
  EXPECT_EQ(a.armature, 0.5);
  const Joint& own = model.joint(*model.find_joint("own_value"));  // its own attribute beats the class
  EXPECT_EQ(own.damping, 7.0);
  EXPECT_EQ(own.armature, 0.5);
  const Joint& main = model.joint(*model.find_joint("main_only"));
  EXPECT_EQ(main.damping, 1.0);
  EXPECT_EQ(main.armature, 0.0);
  // Only the geom whose class turns contype on collides: the capsule, from its class's size.
  ASSERT_EQ(d.ssv.size(), 1u);
  const std::vector<gen::SsvPrimitive>& upper = d.ssv.at("upper");
  ASSERT_EQ(upper.size(), 1u);
  EXPECT_EQ(upper[0].kind, gen::SsvPrimitive::Kind::Line);
  EXPECT_EQ(upper[0].radius, 0.05);
  EXPECT_NEAR((upper[0].points[0] - Vec3<double>(0, 0, -0.7)).norm(), 0, 1e-15);
  EXPECT_NEAR((upper[0].points[1] - Vec3<double>(0, 0, -0.3)).norm(), 0, 1e-15);
}

// ---- Closures ------------------------------------------------------------------------------

TEST(LoadMjcf, ConnectIsAPointClosureWithTheBody2PointAtQpos0) {
  const gen::Description d = load("connect.xml");
  ASSERT_EQ(d.closures.size(), 1u);
  const gen::ClosureSpec& c = d.closures[0];
  EXPECT_EQ(c.name, "loop");
  EXPECT_EQ(c.type, "spherical");
  EXPECT_EQ(c.frame_a, "coupler");
  EXPECT_EQ(c.frame_b, "rocker");
  EXPECT_EQ(d.model.frame(c.resolved_a).name, "coupler");
  EXPECT_EQ(d.model.frame(c.resolved_b).name, "rocker");
  EXPECT_NEAR((c.X_AC.translation - Vec3<double>(1, 0, 0)).norm(), 0, 1e-15);
  // The anchor sits at (1, 1, 0) in the world at qpos0; the rocker (at (2, 0, 0), turned 90 deg
  // about z) sees it at (1, 1, 0).
  EXPECT_NEAR((c.X_BC.translation - Vec3<double>(1, 1, 0)).norm(), 0, 1e-15);
  EXPECT_EQ(c.source_line, 19);
  // Both points coincide at q = 0 (= qpos0 here).
  const VecX<double> q = VecX<double>::Zero(3);
  const SE3<double> A = frame_pose(d.model, "coupler", q) * c.X_AC, B = frame_pose(d.model, "rocker", q) * c.X_BC;
  EXPECT_NEAR((A.translation - B.translation).norm(), 0, 1e-15);
}

TEST(LoadMjcf, SiteConnectAndWeldToTheWorld) {
  const gen::Description d = load("sites_and_weld.xml");
  ASSERT_EQ(d.closures.size(), 2u);
  const gen::ClosureSpec& pin = d.closures[0];
  EXPECT_EQ(pin.name, "connect_1");
  EXPECT_EQ(pin.type, "spherical");
  EXPECT_EQ(d.model.frame(pin.resolved_a).name, "arm_end");
  EXPECT_EQ(d.model.frame(pin.resolved_b).name, "ground_pin");
  EXPECT_EQ(d.model.frame(pin.resolved_b).body, kWorldBody);
  EXPECT_TRUE(pin.X_AC.translation.isZero(0.0));  // the site origins themselves
  EXPECT_TRUE(pin.X_BC.translation.isZero(0.0));
  // The weld holds hand to the world (body2 omitted) at the pose of qpos0: X_BC = X_W,hand(qpos0).
  const gen::ClosureSpec& weld = d.closures[1];
  EXPECT_EQ(weld.name, "weld_2");
  EXPECT_EQ(weld.type, "weld");
  EXPECT_EQ(weld.frame_b, "world");
  const SE3<double> X_W_hand = frame_pose(d.model, "hand", VecX<double>::Zero(2));
  EXPECT_NEAR((weld.X_BC.translation - X_W_hand.translation).norm(), 0, 1e-15);
  EXPECT_NEAR((weld.X_BC.rotation - X_W_hand.rotation).norm(), 0, 1e-15);
  EXPECT_NEAR((weld.X_BC.rotation - rot(Vec3<double>::UnitX(), 0.2)).norm(), 0, 1e-15);
}

// <frame>s compile away onto their children (mjcf_frames.cpp): frames.xml nests three (one in
// <worldbody>, two in a body, one with a childclass) around a body, sites and geoms;
// frames_flat.xml is the same model with the poses composed by hand. Every frame's world pose
// at random joint values, the inertias and the geoms' SSV points agree to 1e-15.
TEST(LoadMjcf, FramesComposeOntoTheirChildren) {
  const gen::Description framed = load("frames.xml"), flat = load("frames_flat.xml");
  ASSERT_EQ(framed.model.nq(), 2);
  ASSERT_EQ(flat.model.nq(), 2);
  ASSERT_EQ(framed.model.num_bodies(), flat.model.num_bodies());
  for (int i = 1; i < framed.model.num_bodies(); ++i) {
    const BodyIndex b(i);
    const Inertia<double>& a = framed.model.body(b).inertia;
    const Inertia<double>& c = flat.model.body(b).inertia;
    EXPECT_NEAR(a.mass, c.mass, 1e-15);
    EXPECT_NEAR((a.com - c.com).norm(), 0, 1e-15) << framed.model.body(b).name;
    EXPECT_NEAR((a.inertia_com - c.inertia_com).norm(), 0, 1e-15) << framed.model.body(b).name;
  }
  for (const VecX<double>& q : {VecX<double>(VecX<double>::Zero(2)), VecX<double>(Eigen::Vector2d(0.7, -1.3))})
    for (const char* frame : {"base", "arm", "j1", "j2", "tip", "hand"}) {
      const SE3<double> a = frame_pose(framed.model, frame, q), b = frame_pose(flat.model, frame, q);
      EXPECT_NEAR((a.translation - b.translation).norm(), 0, 1e-15) << frame;
      EXPECT_NEAR((a.rotation - b.rotation).norm(), 0, 1e-15) << frame;
    }
  // The site took the frame's childclass (euler 0 0 30 after the frame's quarter turn about x).
  EXPECT_NEAR((frame_pose(framed.model, "tip", VecX<double>::Zero(2)).rotation -
               rot(Vec3<double>::UnitZ(), kPi / 2) * rot(Vec3<double>::UnitX(), kPi / 2) * rot(Vec3<double>::UnitZ(), kPi / 6)).norm(),
              0, 1e-15);
  EXPECT_FALSE(framed.model.find_frame("outer"));  // a frame leaves no frame of its own
  ASSERT_EQ(framed.ssv.at("base").size(), 2u);
  ASSERT_EQ(flat.ssv.at("base").size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const gen::SsvPrimitive &a = framed.ssv.at("base")[k], &b = flat.ssv.at("base")[k];
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.radius, b.radius);  // the capsule's radius from the frame's childclass
    ASSERT_EQ(a.points.size(), b.points.size());
    for (std::size_t i = 0; i < a.points.size(); ++i) EXPECT_NEAR((a.points[i] - b.points[i]).norm(), 0, 1e-15) << k;
  }
}

// ---- Errors, by their text -------------------------------------------------------------------

TEST(LoadMjcf, JointInsideAFrameIsAnError) {
  const gen::LoadError e = load_error("bad/frame.xml");
  EXPECT_EQ(e.line(), 6);
  EXPECT_EQ(e.element(), "<joint>");
  EXPECT_EQ(e.problem(), "not supported: <joint> inside a <frame>");
  EXPECT_TRUE(contains(e.fix(), "put it in the body itself")) << e.what();
}

// Mesh assets: two meshes under one name (the second takes its file's stem), and a geom naming
// a mesh no asset gives, are errors naming the line.
TEST(LoadMjcf, MeshNamesMustBeUniqueAndKnown) {
  const gen::LoadError taken = load_error("bad/mesh_names.xml");
  EXPECT_EQ(taken.line(), 4);
  EXPECT_TRUE(contains(taken.problem(), "mesh name 'part' is taken (line 3")) << taken.what();
  const gen::LoadError unknown = load_error("bad/mesh_unknown.xml");
  EXPECT_EQ(unknown.line(), 9);
  EXPECT_TRUE(contains(unknown.problem(), "names mesh 'prat', which no <asset> <mesh> gives a file")) << unknown.what();
}

TEST(LoadMjcf, MissingInertialIsAnErrorWithAFix) {
  const gen::LoadError e = load_error("bad/no_inertial.xml");
  EXPECT_EQ(e.file(), kMjcf + "/bad/no_inertial.xml");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.element(), "body 'link'");
  EXPECT_TRUE(contains(e.problem(), "has no <inertial>: MuJoCo would infer its mass and inertia from its geoms")) << e.what();
  EXPECT_TRUE(contains(e.fix(), "add an <inertial")) << e.what();
}

TEST(LoadMjcf, TendonThatCarriesForcesIsAnError) {
  const gen::LoadError e = load_error("bad/tendon.xml");
  EXPECT_EQ(e.line(), 9);
  EXPECT_EQ(e.element(), "fixed 't'");
  EXPECT_EQ(e.problem(), "not supported: stiffness on a tendon (the tendon carries forces of its own)");
  EXPECT_TRUE(contains(e.fix(), "remove stiffness")) << e.what();
}

/// A coupling as read: follower = ratio leader + offset, from the element on `line`.
void expect_coupling(const gen::ClosureSpec& c, const std::string& leader, const std::string& follower, double ratio,
                     double offset, int line) {
  EXPECT_EQ(c.type, "coupling");
  EXPECT_EQ(c.frame_a, leader);
  EXPECT_EQ(c.frame_b, follower);
  EXPECT_DOUBLE_EQ(c.ratio, ratio);
  EXPECT_NEAR(c.offset, offset, 1e-16);
  EXPECT_EQ(c.source_line, line);
}

TEST(LoadMjcf, TendonEqualityOverThreeJointsIsAnError) {
  const gen::LoadError e = load_error("bad/tendon_three_joints.xml");
  EXPECT_EQ(e.line(), 11);
  EXPECT_EQ(e.problem(), "tendon 'differential' has 3 joint(s): an equality on its length couples more than two joints");
  EXPECT_TRUE(contains(e.fix(), "exactly two joints")) << e.what();
}

TEST(LoadMjcf, TendonEqualityCouplesItsTwoJoints) {
  // 0.5 (q1 - 0.005) - 0.25 (q2 - 0.002) = 0.001: q2 = 2 q1 - 0.012, the second joint following.
  const gen::Description d = load("tendon_coupling.xml");
  ASSERT_EQ(d.closures.size(), 1u);
  EXPECT_EQ(d.closures[0].name, "split_held");
  expect_coupling(d.closures[0], "finger_joint1", "finger_joint2", 2.0, -0.012, 28);
  EXPECT_EQ(d.closed_dof, 2);
}

TEST(LoadMjcf, JointEqualityIsACouplingWithMujocosOffset) {
  // q1 - ref1 = c0 + c1 (q2 - ref2): fingers 0 + 0.002 - 1 * 0.01; thumb -0.1 + 0.05 - 0.7 * 0.
  const gen::Description d = load("joint_coupling.xml");
  ASSERT_EQ(d.closures.size(), 2u);
  expect_coupling(d.closures[0], "left_slide", "right_slide", 1.0, -0.008, 30);
  expect_coupling(d.closures[1], "thumb_base", "thumb_tip", 0.7, -0.05, 31);
  // The followers are the dependent coordinates: five joints, three of them the closed system's.
  EXPECT_EQ(d.model.nv(), 5);
  EXPECT_EQ(d.closed_dof, 3);
  std::vector<std::string> dependent;
  for (const SubSystem& s : d.model.subsystems)
    for (int z : s.dependent) dependent.push_back(gen::coordinate_name(d.model, z));
  EXPECT_EQ(dependent, (std::vector<std::string>{"right_slide", "thumb_tip"}));
  // The assembled pose keeps the file's pose where it is closed (the fingers at their refs are
  // not: right = 0.01 - 0.008) and satisfies both rows.
  const VecX<double>& q = d.assembly.q;
  const auto at = [&](const char* joint) { return q[d.model.joint(*d.model.find_joint(joint)).idx_q]; };
  EXPECT_NEAR(at("right_slide"), at("left_slide") - 0.008, 1e-12);
  EXPECT_NEAR(at("thumb_tip"), 0.7 * at("thumb_base") - 0.05, 1e-12);
}

TEST(LoadMjcf, NonlinearJointCouplingIsAnError) {
  const gen::LoadError e = load_error("bad/joint_coupling.xml");
  EXPECT_EQ(e.line(), 13);
  EXPECT_EQ(e.element(), "<joint> (unnamed)");
  EXPECT_TRUE(contains(e.problem(), "is a polynomial of degree 2: mbgen couples joints linearly")) << e.what();
  EXPECT_TRUE(contains(e.fix(), "polycoef=\"c0 c1 0 0 0\"")) << e.what();
}

TEST(LoadMjcf, JointHeldConstantIsAnErrorPointingToLock) {
  const gen::LoadError e = load_error("bad/joint_held.xml");
  EXPECT_EQ(e.line(), 9);
  EXPECT_TRUE(contains(e.problem(), "holds 'ja' at a constant position (no joint2): not a coupling")) << e.what();
  EXPECT_TRUE(contains(e.fix(), "scene: lock")) << e.what();
}

TEST(LoadMjcf, UnknownClassIsNamed) {
  const gen::LoadError e = load_error("bad/unknown_class.xml");
  EXPECT_EQ(e.line(), 7);
  EXPECT_EQ(e.element(), "joint 'j'");
  EXPECT_EQ(e.problem(), "uses class 'amr', which no <default> defines");
  EXPECT_TRUE(contains(e.fix(), "define it with <default class=")) << e.what();
}

TEST(LoadMjcf, BadJointTypeIsNamed) {
  const gen::LoadError e = load_error("bad/joint_type.xml");
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.element(), "joint 'j'");
  EXPECT_EQ(e.problem(), "joint type 'revolute' is unknown");
  EXPECT_TRUE(contains(e.fix(), "type=\"hinge\"")) << e.what();
}

TEST(LoadMjcf, FluidMediumIsNotSupported) {
  const gen::LoadError e = load_error("bad/fluid.xml");
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.element(), "<option>");
  EXPECT_EQ(e.problem(), "not supported: density (fluid forces)");
}

TEST(LoadMjcf, UnknownAttributeIsAnError) {
  const gen::LoadError e = load_error("bad/unknown_attribute.xml");
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.problem(), "attribute 'springstiffness' is not supported");
}

// ---- The shared MJCF robots -------------------------------------------------------------------

int count_joints(const Model& model, JointType type) {
  int n = 0;
  for (int j = 1; j < model.num_joints(); ++j) n += model.joint(JointIndex(j)).type == type;
  return n;
}

TEST(LoadMjcf, CassieLoadsWithItsClosures) {
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  const gen::Description d = gen::load_description(test::shared_robot("cassie_mjcf/cassie.xml"), options);
  const Model& model = d.model;
  // free + 20 hinges + 2 balls (3 hinges each) = 32 tree coordinates.
  EXPECT_EQ(d.base, gen::BaseType::Floating);
  EXPECT_EQ(model.nv(), 32);
  EXPECT_EQ(model.nq(), 33);
  EXPECT_EQ(count_joints(model, JointType::Floating), 1);
  EXPECT_EQ(count_joints(model, JointType::Revolute), 20 + 6);
  // 25 MJCF bodies: 23 moving, 2 (the knee springs) welded and merged; 4 massless ball links.
  int body_frames = 0;
  for (int f = 0; f < model.num_frames(); ++f) {
    const Frame& frame = model.frame(FrameIndex(f));
    body_frames += (frame.kind == FrameKind::Body || frame.kind == FrameKind::Link) && frame.name != "world";
  }
  EXPECT_EQ(body_frames, 25);
  EXPECT_EQ(model.num_bodies(), 1 + 23 + 4);
  EXPECT_EQ(model.frame(model.frame_index("left-knee-spring")).kind, FrameKind::Link);
  EXPECT_NEAR(model.total_mass(), 33.312, 1e-12);  // the sum of the file's 25 masses
  ASSERT_EQ(d.closures.size(), 4u);
  for (const gen::ClosureSpec& c : d.closures) EXPECT_EQ(c.type, "spherical");
  EXPECT_EQ(d.actuated_joints.size(), 10u);
  // Capsule SSVs: pelvis 2, hip pitch 1, shin 3, tarsus 3, foot 1, per side; the ellipsoid is counted.
  int lines = 0;
  for (const auto& [body, compound] : d.ssv)
    for (const gen::SsvPrimitive& p : compound) lines += p.kind == gen::SsvPrimitive::Kind::Line;
  EXPECT_EQ(lines, 2 + 2 * (1 + 3 + 3 + 1));
  EXPECT_EQ(d.collision_geometry_not_modelled.at("ellipsoid"), 1);
  int stiffness = 0;  // the four springs; the assembly adds its own warnings (joints outside their limits)
  for (const std::string& w : d.warnings) stiffness += w.find("has stiffness") != std::string::npos;
  EXPECT_EQ(stiffness, 4);
  EXPECT_EQ(d.model.closures.size(), 4u);
  EXPECT_EQ(d.model.subsystems.size(), 4u);
  // 32 tree DoF, four point closures of rank 2 (plantar rods, planar loops) and 3 (achilles rods):
  // SOURCES.md's mobility 20 plus the two achilles rods' idle spins about their own axes.
  EXPECT_EQ(d.closed_dof, 22);
}

// The file's `home` keyframe (standing, every joint in its range) starts the assembly
// (mjcf_keyframe.cpp): its hinge values are the seed as written, the achilles rods' quaternions
// become their three hinges' angles, and the closed pose kept is near it with every bounded
// joint inside its range (from the zero pose the knees closed outside theirs).
TEST(LoadMjcf, CassieAssemblesFromItsKeyframeInsideItsRanges) {
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  const gen::Description d = gen::load_description(test::shared_robot("cassie_mjcf/cassie.xml"), options);
  EXPECT_TRUE(contains(d.assembly_seed_source, "keyframe 'home'")) << d.assembly_seed_source;
  EXPECT_EQ(d.assembly_seed.at("left-knee"), -1.1997);
  EXPECT_EQ(d.assembly_seed.at("right-tarsus"), 1.42671);
  EXPECT_EQ(d.assembly_seed.at("left-foot"), -1.59681);
  const Mat3<double> R = rot(Vec3<double>::UnitX(), d.assembly_seed.at("left-achilles-rod_x")) *
                         rot(Vec3<double>::UnitY(), d.assembly_seed.at("left-achilles-rod_y")) *
                         rot(Vec3<double>::UnitZ(), d.assembly_seed.at("left-achilles-rod_z"));
  const Mat3<double> expected = Eigen::Quaterniond(0.97861, -0.0164104, 0.0177766, -0.204298).normalized().toRotationMatrix();
  EXPECT_NEAR((R - expected).norm(), 0, 1e-12);
  const Model& model = d.model;
  ASSERT_EQ(d.assembly.q.size(), model.nq());
  EXPECT_LT(d.assembly.residual, 1e-12);
  EXPECT_EQ(d.assembly.outside_ranges, 0);
  int bounded = 0;
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    if (joint.nq != 1) continue;
    const double x = d.assembly.q[joint.idx_q];
    if (joint.bounded) {
      ++bounded;
      EXPECT_GE(x, joint.lower) << joint.name;
      EXPECT_LE(x, joint.upper) << joint.name;
    }
    if (d.assembly_seed.count(joint.name)) {
      EXPECT_NEAR(x, d.assembly_seed.at(joint.name), 0.05) << joint.name;
    }
  }
  EXPECT_EQ(bounded, 16);
}

TEST(LoadMjcf, CassieWithoutItsKeyframeSaysToSeedTheAssembly) {
  // From the zero pose no closed pose tried keeps the knees and feet within their ranges: each
  // joint outside is named, with what to do.
  std::ifstream in(test::shared_robot("cassie_mjcf/cassie.xml"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t begin = text.find("<keyframe>"), end = text.find("</keyframe>");
  ASSERT_NE(begin, std::string::npos);
  text.erase(begin, end + std::string("</keyframe>").size() - begin);
  const std::string path = ::testing::TempDir() + "mbgen_cassie_without_keyframe.xml";
  std::ofstream(path) << text;
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  const gen::Description d = gen::load_description(path, options);
  EXPECT_TRUE(d.assembly_seed.empty());
  EXPECT_GT(d.assembly.outside_ranges, 0);
  int named = 0;
  for (const std::string& w : d.warnings)
    named += contains(w, "outside its limits") && contains(w, "seed the assembly nearer one (`assembly:` in the extras, or an MJCF keyframe)");
  EXPECT_EQ(named, d.assembly.outside_ranges);
}

TEST(LoadMjcf, KeyframeOfTheWrongLengthIsAnError) {
  const gen::LoadError e = load_error("bad/keyframe_length.xml");
  EXPECT_EQ(e.line(), 9);
  EXPECT_TRUE(contains(e.problem(), "qpos has 2 numbers; the joints need 1")) << e.what();
}

TEST(LoadMjcf, H1Loads) {
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  const gen::Description d = gen::load_description(test::shared_robot("unitree_h1/h1.xml"), options);
  EXPECT_EQ(count_joints(d.model, JointType::Floating), 1);
  EXPECT_EQ(count_joints(d.model, JointType::Revolute), 19);
  EXPECT_EQ(d.model.nv(), 25);
  EXPECT_EQ(d.actuated_joints.size(), 19u);
  EXPECT_EQ(d.model.joint(*d.model.find_joint("left_knee")).armature, 0.1);  // class h1 via childclass
  EXPECT_EQ(d.collision_geometry_not_modelled.at("box"), 1);
  EXPECT_TRUE(d.closures.empty());
  // The feet: three capsules whose size and fromto come from the classes foot1..3 under foot.
  const std::vector<gen::SsvPrimitive>& foot = d.ssv.at("left_ankle_link");
  ASSERT_EQ(foot.size(), 3u);
  for (const gen::SsvPrimitive& p : foot) EXPECT_EQ(p.radius, 0.014);
  EXPECT_NEAR((foot[2].points[0] - Vec3<double>(0.14, -0.03, -0.056)).norm(), 0, 1e-15);
  // Visual meshes (class visual: contype = conaffinity = 0) are no collision geometry.
  EXPECT_EQ(d.collision_geometry_not_modelled.count("mesh"), 0u);
}

TEST(LoadMjcf, ToddlerbotTendonIsReported) {
  try {
    gen::load_description(test::shared_robot("toddlerbot_2xc/toddlerbot_2xc.xml"));
    ADD_FAILURE() << "toddlerbot's tendons were accepted";
  } catch (const gen::LoadError& e) {
    // Its waist tendons have ranges: their limits carry forces that no coupling stands for.
    EXPECT_EQ(e.line(), 589);
    EXPECT_EQ(e.element(), "fixed 'waist_roll_coupling'");
    EXPECT_EQ(e.problem(), "not supported: a tendon with a range (its limit carries forces)");
  }
}

}  // namespace
}  // namespace mbgen
