// URDF numbers checked at the source (generator/load/urdf_numbers.cpp): every numeric attribute
// mbgen reads, with every kind of bad value, is a LoadError naming the file, the line of the
// element, the link or joint, the attribute and the problem; before this check urdfdom read
// <mass value="nan"/> or "abc" as a silent 0. Table-driven: the attributes come from
// urdf_numeric_attributes(), the URDF is written here with a marker per attribute.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "load/load_error.hpp"
#include "load/parse_numbers.hpp"
#include "load/urdf_numbers.hpp"
#include "test_support.hpp"

namespace mbgen {
namespace {

namespace fs = std::filesystem;
using gen::UrdfNumericAttribute;

/// A two-joint arm that uses every attribute of the table; @owner/path/attribute@ marks where
/// each value goes (one element per line, so the line of a marker is the element's line).
const char* kTemplate = R"(<?xml version="1.0"?>
<robot name="numbers">
  <link name="base"/>
  <joint name="hinge" type="revolute">
    <parent link="base"/>
    <child link="arm"/>
    <origin xyz="@joint/origin/xyz@" rpy="@joint/origin/rpy@"/>
    <axis xyz="@joint/axis/xyz@"/>
    <limit lower="@joint/limit/lower@" upper="@joint/limit/upper@" effort="@joint/limit/effort@" velocity="@joint/limit/velocity@"/>
    <dynamics damping="@joint/dynamics/damping@" friction="@joint/dynamics/friction@"/>
  </joint>
  <link name="arm">
    <inertial>
      <origin xyz="@link/inertial/origin/xyz@" rpy="@link/inertial/origin/rpy@"/>
      <mass value="@link/inertial/mass/value@"/>
      <inertia ixx="@link/inertial/inertia/ixx@" ixy="@link/inertial/inertia/ixy@" ixz="@link/inertial/inertia/ixz@" iyy="@link/inertial/inertia/iyy@" iyz="@link/inertial/inertia/iyz@" izz="@link/inertial/inertia/izz@"/>
    </inertial>
    <collision>
      <origin xyz="@link/collision/origin/xyz@" rpy="@link/collision/origin/rpy@"/>
      <geometry><sphere radius="@link/collision/geometry/sphere/radius@"/></geometry>
    </collision>
    <collision>
      <geometry><cylinder radius="@link/collision/geometry/cylinder/radius@" length="@link/collision/geometry/cylinder/length@"/></geometry>
    </collision>
    <collision>
      <geometry><box size="@link/collision/geometry/box/size@"/></geometry>
    </collision>
    <collision>
      <geometry><mesh filename="arm.stl" scale="@link/collision/geometry/mesh/scale@"/></geometry>
    </collision>
  </link>
  <joint name="follower" type="revolute">
    <parent link="arm"/>
    <child link="tip"/>
    <axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="10" velocity="3"/>
    <mimic joint="hinge" multiplier="@joint/mimic/multiplier@" offset="@joint/mimic/offset@"/>
  </joint>
  <link name="tip">
    <inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
</robot>
)";

std::string key(const UrdfNumericAttribute& a) { return std::string(a.owner) + "/" + a.path + "/" + a.attribute; }

/// The URDF with `bad` for attribute `target` (empty target: all good), and the line of each marker.
std::string make_urdf(const std::string& target, const std::string& bad, std::map<std::string, int>* lines = nullptr) {
  std::string text = kTemplate;
  int line = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') ++line;
    if (text[i] != '@') continue;
    const std::size_t end = text.find('@', i + 1);
    const std::string marker = text.substr(i + 1, end - i - 1);
    std::string value;
    for (const auto& a : gen::urdf_numeric_attributes())
      if (key(a) == marker) value = marker == target ? bad : a.example;
    if (lines) (*lines)[marker] = line;
    text.replace(i, end - i + 1, value);
  }
  return text;
}

fs::path write_urdf(const std::string& text) {
  // One file per test: ctest runs this binary's tests in parallel processes.
  const fs::path path = fs::temp_directory_path() /
                        (std::string("mbgen_test_urdf_numbers_") +
                         ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".urdf");
  std::ofstream(path) << text;
  return path;
}

gen::Description load(const fs::path& path) {
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  return gen::load_description(path.string(), options);
}

}  // namespace

TEST(UrdfNumbers, EveryAttributeOfTheTableIsInTheTestFile) {
  std::map<std::string, int> lines;
  make_urdf("", "", &lines);
  for (const auto& a : gen::urdf_numeric_attributes()) EXPECT_TRUE(lines.count(key(a))) << key(a);
  EXPECT_EQ(lines.size(), gen::urdf_numeric_attributes().size());
  // With the examples, it loads: the table's examples are good values.
  const gen::Description d = load(write_urdf(make_urdf("", "")));
  EXPECT_EQ(d.model.nv(), 2);
}

TEST(UrdfNumbers, EachBadValueOfEachAttributeIsALoadErrorWithItsLine) {
  // Bad values for one number, and the problem text each gives; lists of three get the same
  // tokens in one place, and wrong counts.
  const std::vector<std::pair<std::string, std::string>> bad_one = {
      {"nan", "'nan' is not a finite number"},        {"NaN", "'NaN' is not a finite number"},
      {"inf", "'inf' is not a finite number"},        {"-inf", "'-inf' is not a finite number"},
      {"infinity", "'infinity' is not a finite number"}, {"abc", "'abc' is not a number"},
      {"1.5abc", "'1.5abc' is not a number"},         {"1e400", "'1e400' overflows a double"},
      {"-1e400", "'-1e400' overflows a double"},      {"0x10", "'0x10' is not a decimal number"},
      {"1,5", "'1,5' is not a number"},
  };
  std::map<std::string, int> lines;
  make_urdf("", "", &lines);
  int cases = 0;
  for (const auto& a : gen::urdf_numeric_attributes()) {
    std::vector<std::pair<std::string, std::string>> cases_here;
    for (const auto& [token, problem] : bad_one) {
      std::string value = token;
      if (a.count == 3) value = "0 " + token + " 1";  // a bad token in the middle of a list
      cases_here.push_back({value, problem});
    }
    const std::string expected_count = a.count == 1 ? "1 expected" : "3 expected";
    cases_here.push_back({"", "0 numbers, " + expected_count});
    cases_here.push_back({a.count == 1 ? "1 2" : "1 2", "2 numbers, " + expected_count});
    if (a.count == 3) cases_here.push_back({"1 2 3 4", "4 numbers, 3 expected"});
    for (const auto& [value, problem] : cases_here) {
      SCOPED_TRACE(key(a) + "=\"" + value + "\"");
      const fs::path path = write_urdf(make_urdf(key(a), value));
      try {
        load(path);
        ADD_FAILURE() << "loaded";
      } catch (const gen::LoadError& e) {
        EXPECT_EQ(e.file(), path.string());
        EXPECT_EQ(e.line(), lines.at(key(a))) << e.what();
        const std::string owner = std::string(a.owner) == "link" ? "link 'arm'"
                                  : std::string(a.path) == "mimic"  ? "joint 'follower'"
                                                                    : "joint 'hinge'";
        EXPECT_EQ(e.element(), owner) << e.what();
        EXPECT_NE(e.problem().find(std::string(a.attribute) + "=\"" + value + "\""), std::string::npos) << e.what();
        EXPECT_NE(e.problem().find(problem), std::string::npos) << e.what();
        EXPECT_NE(e.fix().find(std::string(a.attribute) + "=\"" + a.example + "\""), std::string::npos) << e.what();
      }
      ++cases;
    }
  }
  EXPECT_GT(cases, 350);
}

// The issue's report: iiwa14 with <mass value="nan"/> on a moving link loaded as massless.
TEST(UrdfNumbers, TheReportedIiwaMassIsRefused) {
  std::ifstream in(test::shared_robot("iiwa14/iiwa14_primitive_collision.urdf"));
  std::stringstream s;
  s << in.rdbuf();
  std::string text = s.str();
  const std::regex first_mass(R"(<mass value="[^"]*")");
  for (const char* bad : {"nan", "inf", "abc", "1e400"}) {
    const std::string changed = std::regex_replace(text, first_mass, std::string("<mass value=\"") + bad + "\"",
                                                   std::regex_constants::format_first_only);
    ASSERT_NE(changed, text);
    EXPECT_THROW(load(write_urdf(changed)), gen::LoadError) << bad;
  }
}

TEST(UrdfNumbers, ZeroAxisOfAFixedJointIsIgnored) {
  std::string text = make_urdf("", "");
  const auto replace = [&](const std::string& from, const std::string& to) {
    ASSERT_NE(text.find(from), std::string::npos) << from;
    text.replace(text.find(from), from.size(), to);
  };
  replace("<joint name=\"follower\" type=\"revolute\">", "<joint name=\"follower\" type=\"fixed\">");
  replace("<axis xyz=\"0 1 0\"/>", "<axis xyz=\"0 0 0\"/>");
  EXPECT_NO_THROW(load(write_urdf(text)));
}

TEST(ParseNumbers, ReadsPlainDecimalsAndNamesTheFirstBadToken) {
  EXPECT_EQ(gen::parse_numbers(" 1 -2.5e-3\t+4 ").values, (std::vector<double>{1, -2.5e-3, 4}));
  EXPECT_TRUE(gen::parse_numbers("").values.empty());
  EXPECT_EQ(gen::parse_numbers("1e-400").problem, "");  // underflow: a (sub)normal or 0, a value
  EXPECT_EQ(gen::parse_numbers("1 nan inf").problem, "'nan' is not a finite number");
}

}  // namespace mbgen
