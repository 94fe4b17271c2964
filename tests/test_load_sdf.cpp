// SDFormat input (generator/load/load_sdf.cpp, docs/sdf.md): frames against libsdformat's own
// resolved poses, each joint type's axis convention against a hand-computed motion, Cassie's
// SDF with its four loops written as a graph (closed, against the O(n^3) reference and against
// the same robot written by this test as URDF + YAML closures), Cassie's SDF against its MJCF,
// and bad input.
#include <gtest/gtest.h>
#include <sdf/sdf.hh>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "load/load_error.hpp"
#include "mbgen/algorithm/closure.hpp"
#include "model/topology.hpp"
#include "test_support.hpp"

namespace mbgen {
namespace {

namespace fs = std::filesystem;
const std::string kCassie = test::shared_robot("cassie_sdf/cassie_v2.sdf");

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// Writes `text` to a file of the test's own (ctest runs tests in parallel processes).
std::string write(const std::string& leaf, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / ("mbgen_test_load_sdf_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  fs::create_directories(dir);
  std::ofstream(dir / leaf) << text;
  return (dir / leaf).string();
}

gen::Description load(const std::string& path, std::optional<gen::BaseType> base = std::nullopt, const std::string& extras = "") {
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  options.base = base;
  if (!extras.empty()) options.extras_file = extras;
  return gen::load_description(path, options);
}

/// The LoadError loading `path` raises (fails the test if it loads).
gen::LoadError load_error(const std::string& path, const std::string& extras = "") {
  try {
    load(path, std::nullopt, extras);
  } catch (const gen::LoadError& e) {
    return e;
  }
  ADD_FAILURE() << path << " loaded without error";
  return gen::LoadError("", 0, "", "", "");
}

SE3<double> to_se3(const ignition::math::Pose3d& p) {
  SE3<double> X;
  X.rotation = Eigen::Quaterniond(p.Rot().W(), p.Rot().X(), p.Rot().Y(), p.Rot().Z()).toRotationMatrix();
  X.translation = Vec3<double>(p.Pos().X(), p.Pos().Y(), p.Pos().Z());
  return X;
}

/// World poses of every frame at q.
auto frame_poses(const Model& model, const VecX<double>& q) {
  Data<double> data(model);
  forward_kinematics<double>(model, data, q);
  update_frame_placements<double>(model, data);
  return data.X_WF;
}

double pose_error(const SE3<double>& a, const SE3<double>& b) {
  return std::max((a.rotation - b.rotation).cwiseAbs().maxCoeff(), (a.translation - b.translation).cwiseAbs().maxCoeff());
}

Mat3<double> rot(const Vec3<double>& axis, double angle) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

// ---- Frames and joint conventions -------------------------------------------------------------

// SDFormat 1.9: poses relative to nested frames, an axis expressed in the model frame, an inertial
// frame rotated against its link, and one joint of each type mbgen models.
const char* kFramesSdf = R"(<?xml version="1.0"?>
<sdf version="1.9">
  <model name="frames">
    <link name="base">
      <pose>0.1 0.2 0.3 0.1 0.2 0.3</pose>
      <inertial><mass>3</mass><inertia><ixx>0.1</ixx><iyy>0.1</iyy><izz>0.1</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
    </link>
    <frame name="f1" attached_to="base"><pose relative_to="base">0.3 0 0 0 0 0.7</pose></frame>
    <frame name="f2" attached_to="f1"><pose relative_to="f1">0 0.2 0 0.4 0 0</pose></frame>
    <link name="arm">
      <pose relative_to="f2">0 0 0.1 0 0.3 0</pose>
      <inertial>
        <pose>0.05 0.01 -0.02 0.4 -0.2 0.9</pose>
        <mass>2</mass>
        <inertia><ixx>0.02</ixx><iyy>0.03</iyy><izz>0.04</izz><ixy>0.001</ixy><ixz>-0.002</ixz><iyz>0.003</iyz></inertia>
      </inertial>
    </link>
    <joint name="hinge" type="revolute">
      <pose relative_to="f1">0.05 0 0 0 0 0</pose>
      <parent>base</parent><child>arm</child>
      <axis><xyz expressed_in="__model__">0 1 1</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis>
    </joint>
    <link name="carriage">
      <pose relative_to="arm">0.2 0 0 0.3 0.1 -0.4</pose>
      <inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
    </link>
    <joint name="slider" type="prismatic">
      <parent>arm</parent><child>carriage</child>
      <axis><xyz>1 0 0</xyz><limit><lower>-0.1</lower><upper>0.1</upper></limit></axis>
    </joint>
    <link name="wrist">
      <pose relative_to="carriage">0 0 -0.1 0.2 0 0</pose>
      <inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
    </link>
    <joint name="ball" type="ball">
      <pose>0 0.02 0 0 0.5 0</pose>
      <parent>carriage</parent><child>wrist</child>
    </joint>
    <link name="hand">
      <pose relative_to="wrist">0.1 0 0 0 0 0.2</pose>
      <inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
    </link>
    <joint name="cardan" type="universal">
      <pose>0.01 0 0 0.3 0 0</pose>
      <parent>wrist</parent><child>hand</child>
      <axis><xyz>1 0 0</xyz></axis><axis2><xyz>0 1 0</xyz></axis2>
    </joint>
    <link name="tool">
      <pose relative_to="hand">0 0 0.05 0 0 0</pose>
      <inertial><mass>0.5</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
    </link>
    <joint name="flange" type="fixed"><parent>hand</parent><child>tool</child></joint>
  </model>
</sdf>
)";

/// libsdformat's own pose of a named link, joint or frame in the model frame.
SE3<double> sdf_pose(const sdf::Model& m, const std::string& name) {
  ignition::math::Pose3d p;
  sdf::Errors errors;
  if (const sdf::Link* l = m.LinkByName(name)) errors = l->SemanticPose().Resolve(p, "__model__");
  else if (const sdf::Joint* j = m.JointByName(name)) errors = j->SemanticPose().Resolve(p, "__model__");
  else errors = m.FrameByName(name)->SemanticPose().Resolve(p, "__model__");
  EXPECT_TRUE(errors.empty()) << name;
  return to_se3(p);
}

struct FramesFixture : ::testing::Test {
  FramesFixture() : path(write("frames.sdf", kFramesSdf)) { EXPECT_TRUE(root.Load(path).empty()); }
  std::string path;
  sdf::Root root;
};

TEST_F(FramesFixture, LinkJointAndFramePosesEqualLibsdformats) {
  // Fixed base: the base link is welded where the file puts it, so world = model frame.
  const gen::Description d = load(path, gen::BaseType::Fixed);
  const Model& model = d.model;
  const auto X = frame_poses(model, neutral_configuration<double>(model));
  int checked = 0;
  for (const char* name : {"base", "arm", "carriage", "wrist", "hand", "tool", "f1", "f2", "hinge", "slider", "ball", "cardan", "flange"}) {
    EXPECT_LT(pose_error(X[model.frame_index(name)], sdf_pose(*root.Model(), name)), 1e-14) << name;
    ++checked;
  }
  EXPECT_EQ(checked, 13);
  // 1 revolute + 1 prismatic + 3 (ball) + 2 (universal); the fixed joint merges 'tool' into 'hand'.
  EXPECT_EQ(model.nv(), 7);
  EXPECT_EQ(model.frame(model.frame_index("tool")).kind, FrameKind::Link);
  EXPECT_NEAR(model.total_mass(), 2 + 1 + 1 + 1 + 0.5, 1e-15);  // the fixed base's 3 kg are the world's
}

TEST_F(FramesFixture, EachJointTypeMovesItsChildAsSdformatDefinesIt) {
  const gen::Description d = load(path, gen::BaseType::Fixed);
  const Model& model = d.model;
  const sdf::Model& m = *root.Model();
  VecX<double> q = neutral_configuration<double>(model);
  auto set = [&](const std::string& joint, double value) { q[model.joint(model.find_joint(joint).value()).idx_q] = value; };
  // Each joint alone, from the file's pose: X_W(child)(q) = [R, p_J - R p_J] X_W(child)(0), with R
  // the joint's rotation about its axis in the model frame (hand-computed from the file's text).
  auto about = [](const Mat3<double>& R, const Vec3<double>& p) {
    SE3<double> T;
    T.rotation = R;
    T.translation = p - R * p;
    return T;
  };
  {  // revolute, axis expressed in the model frame
    set("hinge", 0.3);
    const SE3<double> expected = about(rot({0, 1, 1}, 0.3), sdf_pose(m, "hinge").translation) * sdf_pose(m, "arm");
    EXPECT_LT(pose_error(frame_poses(model, q)[model.frame_index("arm")], expected), 1e-14);
    set("hinge", 0);
  }
  {  // prismatic, axis in the joint frame (SDFormat 1.9's default)
    set("slider", 0.07);
    SE3<double> expected = sdf_pose(m, "carriage");
    expected.translation += 0.07 * (sdf_pose(m, "slider").rotation * Vec3<double>::UnitX());
    EXPECT_LT(pose_error(frame_poses(model, q)[model.frame_index("carriage")], expected), 1e-14);
    set("slider", 0);
  }
  {  // ball: three hinges about the joint frame's x, y, z, in that order
    set("ball_x", 0.2);
    set("ball_y", -0.4);
    set("ball_z", 0.6);
    const SE3<double> J = sdf_pose(m, "ball");
    const Mat3<double> R = J.rotation * rot(Vec3<double>::UnitX(), 0.2) * rot(Vec3<double>::UnitY(), -0.4) *
                           rot(Vec3<double>::UnitZ(), 0.6) * J.rotation.transpose();
    EXPECT_LT(pose_error(frame_poses(model, q)[model.frame_index("wrist")], about(R, J.translation) * sdf_pose(m, "wrist")), 1e-14);
    set("ball_x", 0);
    set("ball_y", 0);
    set("ball_z", 0);
  }
  {  // universal: axis (fixed in the parent), then axis2 (fixed in the child)
    set("cardan_1", 0.5);
    set("cardan_2", -0.3);
    const SE3<double> J = sdf_pose(m, "cardan");
    const Mat3<double> R = J.rotation * rot(Vec3<double>::UnitX(), 0.5) * rot(Vec3<double>::UnitY(), -0.3) * J.rotation.transpose();
    EXPECT_LT(pose_error(frame_poses(model, q)[model.frame_index("hand")], about(R, J.translation) * sdf_pose(m, "hand")), 1e-14);
    // The fixed joint's child moves with it.
    EXPECT_LT(pose_error(frame_poses(model, q)[model.frame_index("tool")], about(R, J.translation) * sdf_pose(m, "tool")), 1e-14);
  }
}

TEST_F(FramesFixture, InertialFrameRotatedAgainstItsLink) {
  const gen::Description d = load(path, gen::BaseType::Fixed);
  const Model& model = d.model;
  const Inertia<double>& I = model.body(model.frame(model.frame_index("arm")).body).inertia;
  // By hand: the inertial frame's pose in the link (<inertial><pose>), the link's in the body
  // frame (the joint frame 'hinge'); the file's inertia is about the centre of mass in the inertial frame.
  const SE3<double> X_LI = to_se3(ignition::math::Pose3d(0.05, 0.01, -0.02, 0.4, -0.2, 0.9));
  const SE3<double> X_BL = sdf_pose(*root.Model(), "hinge").inverse() * sdf_pose(*root.Model(), "arm");
  Mat3<double> I_file;
  I_file << 0.02, 0.001, -0.002, 0.001, 0.03, 0.003, -0.002, 0.003, 0.04;
  const Mat3<double> R = X_BL.rotation * X_LI.rotation;
  EXPECT_DOUBLE_EQ(I.mass, 2.0);
  EXPECT_LT((I.com - (X_BL.rotation * X_LI.translation + X_BL.translation)).norm(), 1e-15);
  EXPECT_LT((I.inertia_com - R * I_file * R.transpose()).cwiseAbs().maxCoeff(), 1e-16);
}

TEST_F(FramesFixture, FloatingUnlessStaticOrFixed) {
  EXPECT_EQ(load(path).base, gen::BaseType::Floating);  // not <static>: it floats, as in Gazebo
  std::string text = kFramesSdf;
  text.replace(text.find("<link name=\"base\">"), 0, "<static>true</static>\n    ");
  EXPECT_EQ(load(write("static.sdf", text)).base, gen::BaseType::Fixed);
}

// ---- Cassie: four loops written as a graph ---------------------------------------------------

struct CassieFixture : ::testing::Test {
  static void SetUpTestSuite() { d = new gen::Description(load(kCassie)); }
  static void TearDownTestSuite() { delete d; }
  static gen::Description* d;
};
gen::Description* CassieFixture::d = nullptr;

TEST_F(CassieFixture, FourBallJointsBecomePointClosuresAndFourSubsystems) {
  const Model& model = d->model;
  EXPECT_EQ(d->base, gen::BaseType::Floating);
  EXPECT_EQ(model.nv(), 6 + 22);  // the 22 revolute joints are the tree's
  std::set<std::string> closures;
  for (const gen::ClosureSpec& c : d->closures) {
    EXPECT_EQ(c.type, "spherical") << c.name;
    closures.insert(c.name);
  }
  EXPECT_EQ(closures, (std::set<std::string>{"left-pitch-rod-joint", "right-pitch-rod-joint", "left-plantar-foot-joint",
                                             "right-plantar-foot-joint"}));
  ASSERT_EQ(model.subsystems.size(), 4u);
  // Achilles loops: 5 coordinates, rank 3 (the rod's spring joint is skew to the leg's plane);
  // plantar loops: a planar four-bar, 3 coordinates, rank 2. 28 - 2 (3 + 2) = 18.
  EXPECT_EQ(d->closed_dof, 18);
  EXPECT_EQ(model.structure().independent_v.size(), 18u);
  // Where the loops close: the file's pose closes each by construction, to round-off.
  EXPECT_LT(d->assembly.residual, 1e-12);
  Data<double> data(model);
  EXPECT_LT(closure_residual<double>(model, data, d->assembly.q).cwiseAbs().maxCoeff(), 1e-12);
  // Total mass: the file's 23 <mass> values.
  EXPECT_NEAR(model.total_mass(), 32.94, 1e-12);
  // What is not read is said: the simulator plugin, and the four joint springs.
  int plugin = 0, springs = 0;
  for (const std::string& w : d->warnings) {
    plugin += contains(w, "<plugin> 'CassiePlugin' is not read");
    springs += contains(w, "has a spring of stiffness");
  }
  EXPECT_EQ(plugin, 1);
  EXPECT_EQ(springs, 4);
}

TEST_F(CassieFixture, ClosedLoopForwardDynamicsEqualsTheKktReference) {
  const Model& model = d->model;
  Data<double> data(model), reference_data(model);
  ConstrainedDynamicsWorkspace<double> reference(model);
  std::mt19937_64 rng(57);
  double worst = 0;
  int states = 0;
  for (int trial = 0; trial < 30 && states < 10; ++trial) {
    VecX<double> q, v;
    if (!test::consistent_state(model, d->assembly.q, rng, 0.05, q, v)) continue;
    const VecX<double> tau = random_vector<double>(model.nv(), rng, 5.0);
    ASSERT_EQ(forward_dynamics_loops<double>(model, data, q, v, tau), ClosureStatus::Converged);
    EXPECT_LT(closure_residual<double>(model, data, q).cwiseAbs().maxCoeff(), 1e-10);  // closure_positions' stopping test
    worst = std::max(worst, test::relative_error(data.ddq, forward_dynamics_kkt<double>(model, reference_data, reference, q, v, tau)));
    ++states;
  }
  std::printf("  cassie_v2.sdf: O(n) vs KKT worst relative error %.2e over %d states\n", worst, states);
  EXPECT_EQ(states, 10);
  EXPECT_LT(worst, 1e-10);
}

// The same robot written as URDF + YAML closures, by this test, from libsdformat's data: every
// URDF link frame is aligned with the model frame at the joint's origin (so no rotation is written,
// and every body frame differs from the SDF loader's, which puts it in the joint frame); axes and
// inertias are rotated into the model frame; the four ball joints are `spherical` closures.
std::string fmt3(const Vec3<double>& v, const char* separator = " ") {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, "%.17g%s%.17g%s%.17g", v.x(), separator, v.y(), separator, v.z());
  return buffer;
}

void write_cassie_as_urdf(const std::string& urdf_path, const std::string& yaml_path) {
  sdf::Root root;
  ASSERT_TRUE(root.Load(kCassie).empty());
  const sdf::Model& m = *root.Model();
  std::map<std::string, Vec3<double>> origin;  // URDF link frame's origin in the model frame
  origin["pelvis"] = sdf_pose(m, "pelvis").translation;
  ASSERT_LT((sdf_pose(m, "pelvis").rotation - Mat3<double>::Identity()).norm(), 1e-15);  // so the free joints agree
  std::string joints, yaml = "base: floating\nclosures:\n";
  for (uint64_t i = 0; i < m.JointCount(); ++i) {
    const sdf::Joint& j = *m.JointByIndex(i);
    const SE3<double> X_MJ = sdf_pose(m, j.Name());
    if (j.Type() == sdf::JointType::BALL) continue;
    origin[j.ChildLinkName()] = X_MJ.translation;
  }
  for (uint64_t i = 0; i < m.JointCount(); ++i) {
    const sdf::Joint& j = *m.JointByIndex(i);
    const SE3<double> X_MJ = sdf_pose(m, j.Name());
    const std::string parent = j.ParentLinkName(), child = j.ChildLinkName();
    if (j.Type() == sdf::JointType::BALL) {
      yaml += "  - {name: " + j.Name() + ", type: spherical, parent: " + parent + ", child: " + child +
              ", parent_origin: {xyz: [" + fmt3(X_MJ.translation - origin[parent], ", ") + "]}, child_origin: {xyz: [" +
              fmt3(X_MJ.translation - origin[child], ", ") + "]}}\n";
      continue;
    }
    ignition::math::Vector3d xyz;
    ASSERT_TRUE(j.Axis(0)->ResolveXyz(xyz, "__model__").empty());
    const bool bounded = j.Axis(0)->Lower() > -1e16;
    joints += "  <joint name=\"" + j.Name() + "\" type=\"" + (bounded ? "revolute" : "continuous") + "\">\n    <parent link=\"" +
              parent + "\"/><child link=\"" + child + "\"/>\n    <origin xyz=\"" + fmt3(origin[child] - origin[parent]) +
              "\"/><axis xyz=\"" + fmt3(Vec3<double>(xyz.X(), xyz.Y(), xyz.Z())) + "\"/>\n";
    if (bounded)
      joints += "    <limit lower=\"" + std::to_string(j.Axis(0)->Lower()) + "\" upper=\"" + std::to_string(j.Axis(0)->Upper()) +
                "\" effort=\"100\" velocity=\"10\"/>\n";
    joints += "  </joint>\n";
  }
  std::string links;
  for (uint64_t i = 0; i < m.LinkCount(); ++i) {
    const sdf::Link& l = *m.LinkByIndex(i);
    const SE3<double> X_ML = sdf_pose(m, l.Name());
    const SE3<double> X_MI = X_ML * to_se3(l.Inertial().Pose());
    Mat3<double> I;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) I(r, c) = l.Inertial().MassMatrix().Moi()(r, c);
    I = X_MI.rotation * I * X_MI.rotation.transpose();
    char inertia[512];
    std::snprintf(inertia, sizeof inertia, "ixx=\"%.17g\" ixy=\"%.17g\" ixz=\"%.17g\" iyy=\"%.17g\" iyz=\"%.17g\" izz=\"%.17g\"", I(0, 0),
                  I(0, 1), I(0, 2), I(1, 1), I(1, 2), I(2, 2));
    links += "  <link name=\"" + l.Name() + "\"><inertial><origin xyz=\"" + fmt3(X_MI.translation - origin[l.Name()]) +
             "\"/><mass value=\"" + std::to_string(l.Inertial().MassMatrix().Mass()) + "\"/><inertia " + inertia +
             "/></inertial></link>\n";
  }
  std::ofstream(urdf_path) << "<robot name=\"cassie\">\n" << links << joints << "</robot>\n";
  std::ofstream(yaml_path) << yaml;
}

TEST_F(CassieFixture, EqualsTheSameRobotWrittenAsUrdfAndYamlClosures) {
  const std::string urdf = write("cassie.urdf", ""), yaml = write("cassie.yaml", "");
  write_cassie_as_urdf(urdf, yaml);
  const gen::Description u = load(urdf, std::nullopt, yaml);
  const Model &a = d->model, &b = u.model;
  ASSERT_EQ(a.nv(), b.nv());
  ASSERT_EQ(u.closed_dof, d->closed_dof);
  EXPECT_NEAR(a.total_mass(), b.total_mass(), 1e-12);
  // The joints' coordinates mean the same in both: map them by name.
  auto index_map = [&](bool velocity) {
    std::vector<int> map(static_cast<std::size_t>(velocity ? a.nv() : a.nq()));
    for (int j = 1; j < a.num_joints(); ++j) {
      const Joint& ja = a.joint(JointIndex(j));
      const Joint& jb = b.joint(b.find_joint(ja.name).value());
      for (int k = 0; k < (velocity ? ja.nv : ja.nq); ++k)
        map[static_cast<std::size_t>((velocity ? ja.idx_v : ja.idx_q) + k)] = (velocity ? jb.idx_v : jb.idx_q) + k;
    }
    return map;
  };
  const std::vector<int> map_q = index_map(false), map_v = index_map(true);
  auto to_b = [](const VecX<double>& x, const std::vector<int>& map) {
    VecX<double> y(x.size());
    for (int i = 0; i < x.size(); ++i) y[map[static_cast<std::size_t>(i)]] = x[i];
    return y;
  };
  Data<double> data_a(a), data_b(b);
  std::mt19937_64 rng(58);
  double worst = 0;
  int states = 0;
  for (int trial = 0; trial < 30 && states < 8; ++trial) {
    VecX<double> q, v;
    if (!test::consistent_state(a, d->assembly.q, rng, 0.05, q, v)) continue;
    const VecX<double> tau = random_vector<double>(a.nv(), rng, 5.0);
    const VecX<double> qb = to_b(q, map_q);
    EXPECT_LT(closure_residual<double>(b, data_b, qb).cwiseAbs().maxCoeff(), 1e-10);  // closed there too
    ASSERT_EQ(forward_dynamics_loops<double>(a, data_a, q, v, tau), ClosureStatus::Converged);
    ASSERT_EQ(forward_dynamics_loops<double>(b, data_b, qb, to_b(v, map_v), to_b(tau, map_v)), ClosureStatus::Converged);
    worst = std::max(worst, test::relative_error(to_b(data_a.ddq, map_v), data_b.ddq));
    ++states;
  }
  std::printf("  cassie_v2.sdf vs the same as URDF + YAML: worst relative difference %.2e over %d states\n", worst, states);
  EXPECT_EQ(states, 8);
  EXPECT_LT(worst, 1e-12);
}

// The SDF (Agility's, via example-robot-data) and the MJCF (MuJoCo Menagerie's, derived from
// Agility's cassie-mujoco-sim) are two models of one robot, not one model twice. Same: the 23
// links' names and masses (but the knees'), 4 point closures, 4 sub-systems. Different: (1) the
// MJCF adds a knee-spring body (0.186 kg) welded to each knee; (2) the MJCF's achilles rod hangs
// from the hip pitch by a ball joint and meets the heel spring at a point, so it spins idle about
// its own axis (+1 DoF per leg) and only holds the distance between its ends (+1 more); the SDF's
// rod is hinged to the heel spring by a revolute joint and meets the hip pitch at a ball, which
// holds 3 coordinates of its far end. Hence 18 closed DoF against 22.
TEST_F(CassieFixture, AgainstItsMjcf) {
  const gen::Description mj = load(test::shared_robot("cassie_mjcf/cassie.xml"));
  EXPECT_EQ(mj.closures.size(), d->closures.size());
  EXPECT_EQ(mj.model.subsystems.size(), d->model.subsystems.size());
  EXPECT_EQ(d->closed_dof, 18);
  EXPECT_EQ(mj.closed_dof, d->closed_dof + 2 * 2);
  EXPECT_NEAR(mj.model.total_mass() - d->model.total_mass(), 2 * 0.186, 1e-12);
  int same = 0;
  for (int f = 0; f < d->model.num_frames(); ++f) {
    const Frame& frame = d->model.frame(FrameIndex(f));
    if (frame.kind != FrameKind::Body || frame.name == "world") continue;  // the links' frames
    const std::string name = frame.name == "pelvis" ? "cassie-pelvis" : frame.name;
    const auto other = mj.model.find_frame(name);
    ASSERT_TRUE(other.has_value()) << name;
    const double knee_spring = frame.name == "left-knee" || frame.name == "right-knee" ? 0.186 : 0.0;
    EXPECT_NEAR(mj.model.body(mj.model.frame(*other).body).inertia.mass, d->model.body(frame.body).inertia.mass + knee_spring, 1e-12)
        << name;
    ++same;
  }
  EXPECT_EQ(same, 23);
}

// ---- Options and bad input -------------------------------------------------------------------

TEST_F(CassieFixture, ClosureJointsChooseAnotherTree) {
  // Cut the achilles rods' revolute ends instead of their ball ends: the balls become tree joints
  // (three hinges each), each revolute a 5-row closure; the closed system keeps its 18 DoF.
  const std::string yaml = write("cut.yaml", "closure_joints: [left-achilles-spring-joint, right-achilles-spring-joint]\n");
  const gen::Description cut = load(kCassie, std::nullopt, yaml);
  EXPECT_EQ(cut.model.nv(), 6 + 20 + 6);
  int revolute = 0;
  for (const gen::ClosureSpec& c : cut.closures) revolute += c.type == "revolute";
  EXPECT_EQ(revolute, 2);
  EXPECT_EQ(cut.closed_dof, 18);
  EXPECT_LT(cut.assembly.residual, 1e-12);
}

const char* kTwoLinks = R"(<?xml version="1.0"?>
<sdf version="1.6">
  <model name="m">
    <link name="a"><inertial><mass>1</mass><inertia><ixx>1</ixx><iyy>1</iyy><izz>1</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial></link>
    <link name="b"><inertial><mass>1</mass><inertia><ixx>1</ixx><iyy>1</iyy><izz>1</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial></link>
    JOINTS
  </model>
</sdf>
)";

std::string two_links(const std::string& joints) {
  std::string text = kTwoLinks;
  return text.replace(text.find("JOINTS"), 6, joints);
}

TEST(LoadSdf, ALoopThatCannotCloseNamesItsJointInTheSdfFile) {
  // Cassie's right foot linkage: its axes are parallel to the file's rounding only (the crank-rod
  // joint's frame is pitched 1.364 rad where the others' are 1.3439), so the point closure's third
  // row, redundant at the file's pose, opens by ~1e-9 m a turn away; the assembly says which
  // joint and where it is written.
  const std::string yaml = write("far.yaml", "assembly: {right-foot-op: -1.6, right-tarsus-crank-joint: -1.6, right-crank-rod-joint: 1.6}\n");
  const gen::LoadError e = load_error(kCassie, yaml);
  EXPECT_TRUE(contains(e.what(), "closure 'right-plantar-foot-joint': cannot be assembled")) << e.what();
  EXPECT_EQ(e.file(), kCassie);
  EXPECT_EQ(e.line(), 1043);  // its <joint> element
  // The left foot's linkage, a parallelogram with exactly parallel axes, closes there.
  const gen::Description left = load(kCassie, std::nullopt,
                                     write("left.yaml", "assembly: {left-foot-op: -1.6, left-tarsus-crank-joint: -1.6, left-crank-rod-joint: 1.6}\n"));
  EXPECT_NEAR(left.assembly.q[left.model.joint(left.model.find_joint("left-foot-op").value()).idx_q], -1.6, 1e-4);
}

TEST(LoadSdf, MalformedFileGivesLibsdformatsErrorWithItsLine) {
  const std::string path = write("bad.sdf", "<?xml version=\"1.0\"?>\n<sdf version=\"1.6\">\n  <model name=\"m\">\n    <link name=\"a\">\n  </model>\n</sdf>\n");
  const gen::LoadError e = load_error(path);  // libsdformat says only "Unable to read file": tinyxml2 gives the line
  EXPECT_TRUE(contains(e.what(), "malformed XML: mismatched element")) << e.what();
  EXPECT_EQ(e.file(), path);
  EXPECT_EQ(e.line(), 4);
  // A file libsdformat parses but refuses: its message, prefixed.
  const gen::LoadError joint = load_error(write("bad_joint.sdf", two_links(R"(<joint name="j" type="revolute"><parent>a</parent><child>a</child><axis><xyz>0 0 1</xyz></axis></joint>)")));
  EXPECT_TRUE(contains(joint.what(), "SDFormat: ")) << joint.what();
}

TEST(LoadSdf, InertiasGoThroughMbgensChecksWithTheirLine) {
  std::string text = kTwoLinks;
  text.replace(text.find("<mass>1</mass>"), 14, "<mass>-1</mass>");
  text.replace(text.find("JOINTS"), 6, R"(<joint name="j" type="fixed"><parent>a</parent><child>b</child></joint>)");
  const gen::LoadError e = load_error(write("negative.sdf", text));
  EXPECT_TRUE(contains(e.what(), "link 'a': negative mass -1 kg")) << e.what();
  EXPECT_EQ(e.line(), 4);
}

TEST(LoadSdf, MissingChildLinkIsNamed) {
  const gen::LoadError e =
      load_error(write("missing.sdf", two_links(R"(<joint name="j" type="revolute"><parent>a</parent><child>nowhere</child><axis><xyz>0 0 1</xyz></axis></joint>)")));
  EXPECT_TRUE(contains(e.what(), "nowhere")) << e.what();
}

TEST(LoadSdf, ALoopThroughAJointMbgenCannotCutIsRefusedWithTheFix) {
  // Two joints between a and b: the universal one is left out of the tree, and a universal joint
  // cannot be a closure (its second axis is fixed in the child): name another one to cut.
  const std::string joints = R"(<joint name="hinge" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis></joint>
    <joint name="cardan" type="universal"><parent>a</parent><child>b</child><axis><xyz>1 0 0</xyz></axis><axis2><xyz>0 1 0</xyz></axis2></joint>)";
  const gen::LoadError e = load_error(write("universal.sdf", two_links(joints)));
  EXPECT_TRUE(contains(e.what(), "joint 'cardan'")) << e.what();
  EXPECT_TRUE(contains(e.what(), "closure_joints")) << e.what();
  EXPECT_GT(e.line(), 0);
}

TEST(LoadSdf, ClosureJointsThatDisconnectTheTreeAreRefused) {
  const std::string sdf = write("chain.sdf", two_links(R"(<joint name="j" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis></joint>)"));
  const gen::LoadError e = load_error(sdf, write("cut.yaml", "closure_joints: [j]\n"));
  EXPECT_TRUE(contains(e.what(), "link 'b'")) << e.what();
  const gen::LoadError unknown = load_error(sdf, write("unknown.yaml", "closure_joints: [nope]\n"));
  EXPECT_TRUE(contains(unknown.what(), "'nope'")) << unknown.what();
}

TEST(LoadSdf, ClosureJointsBelongToSdformatFilesOnly) {
  const gen::LoadError e = load_error(test::shared_robot("iiwa14/iiwa14_primitive_collision.urdf"), write("cut.yaml", "closure_joints: [a]\n"));
  EXPECT_TRUE(contains(e.what(), "closure_joints")) << e.what();
  EXPECT_TRUE(contains(e.what(), "not one")) << e.what();
}

TEST(LoadSdf, UnresolvableMeshPathSaysWhichModelAndHowToFix) {
  std::string text = two_links(R"(<joint name="j" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis></joint>)");
  text.replace(text.find("</link>"), 0, "<collision name=\"c\"><geometry><mesh><uri>model://nowhere_robot/meshes/a.stl</uri></mesh></geometry></collision>");
  const std::string path = write("mesh.sdf", text);
  const gen::Description plain = load(path);  // without fitting, the mesh is only kept
  EXPECT_EQ(plain.link_meshes.at("a").front().reference, "model://nowhere_robot/meshes/a.stl");
  // Fitting falls back to no SSV for that link, with a warning naming the model and the fix.
  const gen::Description fitted = load(path, std::nullopt, write("fit.yaml", "scene:\n  collision:\n    fit: true\n"));
  std::string warning;
  for (const std::string& w : fitted.warnings)
    if (contains(w, "nowhere_robot")) warning = w;
  EXPECT_TRUE(contains(warning, "model 'nowhere_robot' is unknown")) << warning;
  EXPECT_TRUE(contains(warning, "--package-path nowhere_robot=DIR")) << warning;
  EXPECT_EQ(fitted.ssv.count("a"), 0u);
  // A model:// URI is found where --package-path points, and fitted.
  std::string text_found = text;
  text_found.replace(text_found.find("model://nowhere_robot/meshes/a.stl"), 34, "model://example-robot-data/robots/talos_data/meshes/torso/torso_1.STL");
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  options.extras_file = write("fit_found.yaml", "scene:\n  collision:\n    fit: true\n");
  options.package_paths["example-robot-data"] = test::shared_robot("talos/meshes/example-robot-data");
  const gen::Description found = gen::load_description(write("mesh_found.sdf", text_found), options);
  ASSERT_EQ(found.ssv.count("a"), 1u);
  EXPECT_GT(found.ssv.at("a").size(), 0u);
}

TEST(LoadSdf, AWorldWithSeveralModelsIsRefusedNamingThem) {
  std::string model = two_links(R"(<joint name="j" type="fixed"><parent>a</parent><child>b</child></joint>)");
  model = model.substr(model.find("<model"), model.find("</sdf>") - model.find("<model"));
  std::string second = model;
  second.replace(second.find("name=\"m\""), 8, "name=\"n\"");
  const std::string world = "<?xml version=\"1.0\"?>\n<sdf version=\"1.6\"><world name=\"w\">" + model + second + "</world></sdf>\n";
  const gen::LoadError e = load_error(write("two.world", world));
  EXPECT_TRUE(contains(e.what(), "2 models (m, n)")) << e.what();
  // One model in a world is read, and a note says so.
  const gen::Description one = load(write("one.world", "<?xml version=\"1.0\"?>\n<sdf version=\"1.6\"><world name=\"w\">" + model + "</world></sdf>\n"));
  EXPECT_EQ(one.robot_name, "m");
}

TEST(LoadSdf, AJointFromTheWorldFixesTheBaseUnlessAFloatingOneIsAskedFor) {
  const std::string path = write("welded.sdf", two_links(R"(<joint name="weld" type="fixed"><parent>world</parent><child>a</child></joint>
    <joint name="j" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis></joint>)"));
  const gen::Description fixed = load(path);
  EXPECT_EQ(fixed.base, gen::BaseType::Fixed);
  EXPECT_EQ(fixed.model.nv(), 1);
  const gen::Description floating = load(path, gen::BaseType::Floating);
  EXPECT_EQ(floating.base, gen::BaseType::Floating);
  EXPECT_EQ(floating.model.nv(), 7);
  EXPECT_EQ(floating.model.joint(floating.model.find_joint("weld").value()).type, JointType::Floating);
  // A moving joint from the world leaves nothing to float: refused.
  const std::string hinged = write("hinged.sdf", two_links(R"(<joint name="hinge" type="revolute"><parent>world</parent><child>a</child><axis><xyz>0 0 1</xyz></axis></joint>
    <joint name="j" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis></joint>)"));
  try {
    load(hinged, gen::BaseType::Floating);
    FAIL() << "no error";
  } catch (const gen::LoadError& e) {
    EXPECT_TRUE(contains(e.what(), "joint 'hinge'")) << e.what();
  }
}

TEST(LoadSdf, NestedModelIsRefused) {
  std::string text = two_links(R"(<joint name="j" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis></joint>
    <model name="inner"><link name="c"><inertial><mass>1</mass></inertial></link></model>)");
  const gen::LoadError e = load_error(write("nested.sdf", text));
  EXPECT_TRUE(contains(e.what(), "model 'inner'")) << e.what();
  EXPECT_TRUE(contains(e.what(), "nested")) << e.what();
}

TEST(LoadSdf, MissingInertialIsAWarning) {
  const std::string text = R"(<?xml version="1.0"?>
<sdf version="1.6"><model name="m"><link name="a"/></model></sdf>
)";
  const gen::Description d = load(write("bare.sdf", text));
  bool warned = false;
  for (const std::string& w : d.warnings) warned = warned || contains(w, "no <inertial>");
  EXPECT_TRUE(warned);
}

}  // namespace
}  // namespace mbgen
