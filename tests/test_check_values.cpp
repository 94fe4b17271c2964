// Inertias as the loaders check them (generator/load/check_values.cpp): exporter round-off is
// accepted as zero with a note (iCub's head), real errors are refused (ixx = -1, TIAGo's antenna
// at -3.5e-8 kg m^2, Romeo's -0.021) unless the user asks for the nearest valid inertia, and a
// triangle-inequality violation beyond round-off is a warning, or repaired on request. The
// descriptions are small files written here with the values of those reports (not the upstream
// files).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <filesystem>
#include <fstream>
#include <random>

#include "load/check_values.hpp"
#include "load/load_error.hpp"
#include "test_support.hpp"

namespace mbgen {
namespace {

namespace fs = std::filesystem;

struct InertiaEntries {
  double ixx = 0, ixy = 0, ixz = 0, iyy = 0, iyz = 0, izz = 0;
};

/// A base and one link on a revolute joint; the link carries `mass` and `inertia` (line 8), and
/// a second link keeps the joint's subtree massive whatever the first one's inertia is.
fs::path arm_with(const std::string& name, double mass, const InertiaEntries& i) {
  const fs::path path = fs::temp_directory_path() / ("mbgen_test_check_values_" + name + ".urdf");
  std::ofstream(path) << "<?xml version=\"1.0\"?>\n"
                      << "<robot name=\"" << name << "\">\n"
                      << "  <link name=\"base\"/>\n"
                      << "  <joint name=\"hinge\" type=\"continuous\">\n"
                      << "    <parent link=\"base\"/><child link=\"head\"/><axis xyz=\"0 0 1\"/>\n"
                      << "  </joint>\n"
                      << "  <link name=\"head\">\n"
                      << "    <inertial><origin xyz=\"0.1 0 0\"/><mass value=\"" << mass << "\"/><inertia ixx=\"" << i.ixx
                      << "\" ixy=\"" << i.ixy << "\" ixz=\"" << i.ixz << "\" iyy=\"" << i.iyy << "\" iyz=\"" << i.iyz
                      << "\" izz=\"" << i.izz << "\"/></inertial>\n"
                      << "  </link>\n"
                      << "</robot>\n";
  return path;
}

gen::Description load(const fs::path& path, bool repair = false) {
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  options.repair_inertia = repair;
  return gen::load_description(path.string(), options);
}

std::string load_error(const fs::path& path) {
  try {
    load(path);
  } catch (const gen::LoadError& e) {
    EXPECT_EQ(e.line(), 7) << e.what();  // the <link> element
    EXPECT_EQ(e.element(), "link 'head'");
    return e.what();
  }
  ADD_FAILURE() << path << " loaded";
  return "";
}

Vec3<double> moments(const Mat3<double>& I) {
  return Eigen::SelfAdjointEigenSolver<Mat3<double>>(I, Eigen::EigenvaluesOnly).eigenvalues();
}

bool rigid_body_inertia(const Mat3<double>& I, double tolerance) {
  const Vec3<double> m = moments(I);
  return m[0] >= -tolerance && m[0] + m[1] >= m[2] - tolerance;
}

}  // namespace

// iCub's head: 1.34 kg, ixz = 2.40741e-35 and zeros elsewhere: eigenvalues +-2.4e-35, a point
// mass with round-off. Pinocchio and KDL load it; so does mbgen, with a note.
TEST(CheckValues, RoundOffBelowZeroIsZeroWithANote) {
  const gen::Description d = load(arm_with("icub_head", 1.34, {0, 0, 2.40741e-35, 0, 0, 0}));
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_NE(d.notes[0].find("link 'head' (line 7): principal moment -2.41e-35 kg m^2 is round-off"), std::string::npos)
      << d.notes[0];
  EXPECT_TRUE(d.warnings.empty());
  // The negative moment is gone: the body's inertia is positive semi-definite, still ~1e-35.
  const Mat3<double>& I = d.model.body(BodyIndex(1)).inertia.inertia_com;
  EXPECT_GE(moments(I)[0], 0.0);
  EXPECT_LT(I.cwiseAbs().maxCoeff(), 1e-34);
}

TEST(CheckValues, RoundOffRelativeToTheInertiasScale) {
  // A thin rod (moments 0, 1, 1) printed with 6 digits: -4e-7 relative is round-off.
  const gen::Description d = load(arm_with("rod", 1, {-4e-7, 0, 0, 1, 0, 1}));
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_TRUE(d.warnings.empty());
}

TEST(CheckValues, RealErrorsAreRefused) {
  EXPECT_NE(load_error(arm_with("negative_ixx", 1, {-1, 0, 0, 1, 0, 1})).find("not positive semi-definite"),
            std::string::npos);
  // TIAGo's antenna: principal moments -3.5e-8, 3.5e-8, 9.1e-8 kg m^2 (indefinite at 1e-8).
  const std::string tiago = load_error(arm_with("tiago_antenna", 0.1, {0, 3.5e-8, 0, 0, 0, 9.1e-8}));
  EXPECT_NE(tiago.find("principal moments -3.5e-08, 3.5e-08, 9.1e-08"), std::string::npos) << tiago;
  EXPECT_NE(tiago.find("--repair-inertia"), std::string::npos) << tiago;  // the fix names the opt-in
  // Romeo's small variant: -0.021.
  EXPECT_NE(load_error(arm_with("romeo", 2, {0.1, 0.121, 0, 0.1, 0, 0.3})).find("-0.021"), std::string::npos);
  // A violation of 1e-3 relative is no round-off.
  load_error(arm_with("relative_1e-3", 1, {-1e-3, 0, 0, 1, 0, 1}));
}

TEST(CheckValues, RepairOnRequestGivesARigidBodysInertiaWithANote) {
  const gen::Description d = load(arm_with("tiago_antenna_repaired", 0.1, {0, 3.5e-8, 0, 0, 0, 9.1e-8}), true);
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_NE(d.notes[0].find("inertia repaired (--repair-inertia): principal moments -3.5e-08, 3.5e-08, 9.1e-08"),
            std::string::npos)
      << d.notes[0];
  EXPECT_TRUE(rigid_body_inertia(d.model.body(BodyIndex(1)).inertia.inertia_com, 1e-20));
}

TEST(CheckValues, TriangleInequalityBeyondRoundOffWarnsOrIsRepaired) {
  const fs::path path = arm_with("triangle", 1, {0.1, 0, 0, 0.1, 0, 0.3});  // 0.1 + 0.1 < 0.3
  const gen::Description warned = load(path);
  ASSERT_EQ(warned.warnings.size(), 1u);
  EXPECT_NE(warned.warnings[0].find("breaks the triangle inequality"), std::string::npos);
  EXPECT_TRUE(warned.notes.empty());
  const gen::Description repaired = load(path, true);
  EXPECT_TRUE(repaired.warnings.empty());
  ASSERT_EQ(repaired.notes.size(), 1u);
  // The smallest equal shift: (0.1, 0.1, 0.3) -> (0.1 + 1/30, 0.1 + 1/30, 0.3 - 1/30).
  EXPECT_NEAR((moments(repaired.model.body(BodyIndex(1)).inertia.inertia_com) - Vec3<double>(0.4 / 3, 0.4 / 3, 0.8 / 3))
                  .norm(),
              0, 1e-15);
  // Round-off violations of it say nothing: moments 0, 0 and 1e-13 kg m^2 (below the floor).
  EXPECT_TRUE(load(arm_with("triangle_roundoff", 1, {0, 0, 0, 0, 0, 1e-13})).warnings.empty());
}

TEST(CheckValues, NearestValidInertiaIsValidAndLeavesValidOnesAlone) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 200; ++k) {
    Mat3<double> A;
    for (int i = 0; i < 9; ++i) A.data()[i] = u(rng);
    const Mat3<double> I = (A + A.transpose()) / 2;  // any symmetric matrix, mostly invalid
    const Mat3<double> N = gen::nearest_valid_inertia(I);
    EXPECT_TRUE(rigid_body_inertia(N, 1e-14)) << I;
    EXPECT_LT((gen::nearest_valid_inertia(N) - N).norm(), 1e-14);  // a valid inertia is its own nearest
    // Valid inertias are left alone.
    // (A^T A has moments m >= 0; adding its trace c >= m2 to each makes m0 + m1 + c >= m2.)
    const Mat3<double> AtA = A.transpose() * A;
    const Mat3<double> valid = AtA + AtA.trace() * Mat3<double>::Identity();
    EXPECT_LT((gen::nearest_valid_inertia(valid) - valid).norm(), 1e-13 * valid.norm());
  }
}

}  // namespace mbgen
