// One test per bad input (issue 2, item 4): each checks the message's file, line, element and
// problem. The inputs are the tiny files in tests/data/bad/.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "load/load_error.hpp"
#include "test_support.hpp"

namespace mbgen {
namespace {

using gen::LoadError;

const std::string kData = MBGEN_TEST_DATA;
const std::string kBad = kData + "/bad/";

struct Expected {
  std::string file;  ///< the file the message must name
  int line;          ///< 0: none
  std::string element;
  std::string problem;  ///< a part of the problem text
};

/// Loads and expects a LoadError as described; returns its text for further checks.
std::string expect_error(const std::string& urdf, const std::string& extras, const Expected& expected) {
  gen::LoadOptions options;
  if (!extras.empty()) options.extras_file = extras;
  options.pick_up_robot_yaml = false;
  try {
    gen::load_description(urdf, options);
  } catch (const LoadError& e) {
    EXPECT_EQ(e.file(), expected.file);
    EXPECT_EQ(e.line(), expected.line) << e.what();
    EXPECT_EQ(e.element(), expected.element) << e.what();
    EXPECT_NE(e.problem().find(expected.problem), std::string::npos) << e.what();
    EXPECT_FALSE(e.fix().empty()) << e.what();
    // The text the CLI prints starts with file:line and names the element.
    const std::string where = expected.line > 0 ? expected.file + ":" + std::to_string(expected.line) : expected.file;
    EXPECT_EQ(std::string(e.what()).rfind(where + ": error: ", 0), 0u) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no LoadError for " << urdf << " " << extras;
  return "";
}

std::string urdf_error(const std::string& name, int line, const std::string& element, const std::string& problem) {
  return expect_error(kBad + name, "", {kBad + name, line, element, problem});
}

std::string yaml_error(const std::string& name, int line, const std::string& element, const std::string& problem) {
  return expect_error(kData + "/tiny_arm.urdf", kBad + name, {kBad + name, line, element, problem});
}

TEST(Validate, MalformedXml) { urdf_error("malformed.urdf", 4, "", "malformed XML: mismatched element"); }

// Hostile nesting (a generated file gone wrong): tinyxml2's depth limit, said as such.
TEST(Validate, NestingDeeperThanTheXmlReadersLimit) {
  const std::string path = testing::TempDir() + "mbgen_deep.urdf";
  std::string text = "<?xml version=\"1.0\"?>\n<robot name=\"deep\"><link name=\"a\">";
  for (int i = 0; i < 10000; ++i) text += "<x>";
  for (int i = 0; i < 10000; ++i) text += "</x>";
  std::ofstream(path) << text << "</link></robot>\n";
  const std::string message = expect_error(path, "", {path, 2, "", "malformed XML: element depth exceeded"});
  EXPECT_NE(message.find("limit of 100 levels"), std::string::npos) << message;
}

// An MJCF body under the .urdf extension: the extension decides the reader (.xml is MJCF).
TEST(Validate, NotAUrdf) { urdf_error("not_urdf.urdf", 1, "", "not a URDF: the root element is <mujoco>"); }

TEST(Validate, MalformedYaml) { yaml_error("malformed.yaml", 4, "", "malformed YAML"); }

TEST(Validate, NegativeMass) { urdf_error("negative_mass.urdf", 7, "link 'arm'", "negative mass -1 kg"); }

TEST(Validate, InertiaNotPositiveSemiDefinite) {
  urdf_error("not_psd.urdf", 7, "link 'arm'", "inertia is not positive semi-definite");
}

TEST(Validate, JointMovingNoMass) {
  const std::string text = urdf_error("massless_joint.urdf", 10, "joint 'wrist'", "moves no mass or inertia");
  EXPECT_NE(text.find("drives: [{joint: wrist, gear_ratio: 1, rotor_inertia: 1e-6}]"), std::string::npos) << text;
}

// The fix works: the drive's armature (or rotor body) makes the wrist's row of M regular.
TEST(Validate, JointMovingNoMassLoadsWithADrive) {
  for (const char* model : {"armature", "body"}) {
    gen::LoadOptions options;
    options.pick_up_robot_yaml = false;
    const std::string extras = testing::TempDir() + "massless_wrist_" + model + ".yaml";
    std::ifstream in(kData + "/extras/massless_wrist_drive.yaml");
    std::stringstream yaml;
    yaml << in.rdbuf();
    std::string text = yaml.str();
    text.replace(text.find("rotor_inertia: 1e-6}"), 20, std::string("rotor_inertia: 1e-6, model: ") + model + "}");
    std::ofstream(extras) << text;
    options.extras_file = extras;
    const gen::Description d = gen::load_description(kBad + "massless_joint.urdf", options);
    EXPECT_EQ(d.model.nv(), 2) << model;
  }
}

// A joint naming a missing link: said with the line of the <parent> and a suggestion (urdfdom's
// own message had no line, and on this error it leaks the half-built model: a fuzzer finding).
TEST(Validate, JointNamesAMissingLink) {
  const std::string text = urdf_error("missing_link.urdf", 5, "joint 'hinge'", "its parent link 'base' is not a link of the robot");
  EXPECT_NE(text.find("did you mean 'bawe'?"), std::string::npos) << text;
}

TEST(Validate, SecondRootLink) {
  urdf_error("two_roots.urdf", 11, "link 'camera'", "is a second root: no joint has it as child, nor 'base' (line 3)");
}

TEST(Validate, LinkDefinedTwice) {
  urdf_error("duplicate_link.urdf", 11, "link 'arm'", "is defined twice (first on line 8)");
}

TEST(Validate, ZeroJointAxis) { urdf_error("zero_axis.urdf", 6, "joint 'hinge'", "joint axis is zero"); }

TEST(Validate, LowerLimitAboveUpper) {
  urdf_error("lower_above_upper.urdf", 4, "joint 'hinge'", "lower limit 1.5 is above upper limit -1.5");
}

TEST(Validate, NoMovingJoint) { urdf_error("no_moving_joint.urdf", 0, "robot 'no_moving_joint'", "has no moving joint"); }

TEST(Validate, NoMovingJointIsFineWithAFloatingBase) {
  gen::LoadOptions options;
  options.base = gen::BaseType::Floating;
  EXPECT_EQ(gen::load_description(kBad + "no_moving_joint.urdf", options).model.nv(), 6);
}

TEST(Validate, LinkWithTwoParents) {
  urdf_error("two_parents.urdf", 12, "link 'a'", "has two parent joints, 'left' and 'close'");
}

TEST(Validate, ClosureNamingOneLinkTwice) {
  yaml_error("closure_same_link.yaml", 3, "closure 'self_loop'", "names 'leg' twice");
}

TEST(Validate, ClosureJoiningOneBodyToItself) {
  yaml_error("closure_same_body.yaml", 2, "closure 'welded'", "fixed in the same body 'lower'");
}

TEST(Validate, UnknownJointInExtras) {
  const std::string text = yaml_error("unknown_joint.yaml", 3, "name_mot[1]", "names 'elbw'");
  EXPECT_NE(text.find("did you mean 'elbow'?"), std::string::npos);
}

TEST(Validate, TriangleInequalityIsAWarningNamingTheLink) {
  const gen::Description d = gen::load_description(kBad + "triangle_inequality.urdf");
  ASSERT_EQ(d.warnings.size(), 1u);
  EXPECT_NE(d.warnings[0].find("link 'arm' (line 7): inertia breaks the triangle inequality"), std::string::npos)
      << d.warnings[0];
}

TEST(Validate, MimicJointIsAWarning) {
  const gen::Description d = gen::load_description(kBad + "mimic.urdf");
  ASSERT_EQ(d.warnings.size(), 1u);
  EXPECT_NE(d.warnings[0].find("joint 'finger_2' mimics 'finger_1'"), std::string::npos) << d.warnings[0];
}

TEST(Validate, RealRobotsWithBadTrianglesLoadWithWarnings) {
  for (const char* robot : {"hyq/hyq_no_sensors.urdf", "talos/talos_reduced.urdf"}) {
    const gen::Description d = gen::load_description(test::shared_robot(robot));
    bool found = false;
    for (const std::string& w : d.warnings) found |= w.find("triangle inequality") != std::string::npos;
    EXPECT_TRUE(found) << robot;
  }
}

}  // namespace
}  // namespace mbgen
