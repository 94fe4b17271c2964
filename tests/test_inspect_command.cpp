// `mbgen inspect` end to end: the built binary (MBGEN_BINARY) on every shared URDF (with its
// robot.yaml where there is one), text and --json, and exit status 2 on bad input.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "test_support.hpp"

namespace mbgen {
namespace {

const std::string kData = MBGEN_TEST_DATA;

struct Outcome {
  int status = -1;
  std::string out, err;
};

std::string quote(const std::string& s) { return "'" + s + "'"; }

/// Runs `mbgen ARGS`, capturing stdout, stderr and the exit status.
Outcome run_mbgen(const std::string& args) {
  const std::string err_file =
      (std::filesystem::temp_directory_path() / ("mbgen_test_" + std::to_string(::getpid()) + ".err")).string();
  const std::string command = quote(MBGEN_BINARY) + " " + args + " 2>" + quote(err_file);
  Outcome run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(err_file);
  std::stringstream text;
  text << err.rdbuf();
  run.err = text.str();
  std::filesystem::remove(err_file);
  return run;
}

void expect_json_report(const Outcome& run, const std::string& what) {
  ASSERT_EQ(run.status, 0) << what << "\n" << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << what << ": not JSON";
  for (const char* key : {"dof", "nq", "nv", "bodies", "joints", "frames", "total_mass", "closures", "actuated", "drives",
                          "warnings"})
    EXPECT_TRUE(j.contains(key)) << what << ": no key " << key;
  EXPECT_EQ(j["dof"], j["nv"]);
  EXPECT_EQ(j["bodies"].size(), j["joints"].size());
  for (const auto& body : j["bodies"])
    for (const char* key : {"name", "parent", "joint", "mass"}) EXPECT_TRUE(body.contains(key)) << what << ": body " << key;
  for (const auto& joint : j["joints"])
    for (const char* key : {"name", "type", "parent", "child", "axis", "lower", "upper"})
      EXPECT_TRUE(joint.contains(key)) << what << ": joint " << key;
}

class InspectEveryUrdf : public ::testing::TestWithParam<std::string> {};

/// disney_robot's robot.yaml misspells a joint_name (a load error, test_load_extras.cpp): the
/// report runs on the copy with the 9 valid overrides.
std::string extras_option(const std::string& urdf) {
  if (urdf.find("parallel_legs/disney_robot/") == std::string::npos) return "";
  return " --extras " + quote(kData + "/parallel_legs/disney_robot_9_of_10.yaml");
}

TEST_P(InspectEveryUrdf, TextJsonFixedAndFloating) {
  const std::string urdf = quote(GetParam()) + extras_option(GetParam());
  const Outcome text = run_mbgen("inspect " + urdf);
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("verdict: OK"), std::string::npos);
  EXPECT_TRUE(text.err.empty()) << text.err;  // urdfdom's console output is captured, not printed
  expect_json_report(run_mbgen("inspect " + urdf + " --json"), GetParam());
  if (test::loadable_bases(GetParam()).size() < 2) {  // hung from "world" by moving joints
    EXPECT_EQ(run_mbgen("inspect " + urdf + " --floating --json").status, 1);
    return;
  }
  const Outcome floating = run_mbgen("inspect " + urdf + " --floating --json");
  expect_json_report(floating, GetParam() + " --floating");
  EXPECT_EQ(nlohmann::json::parse(floating.out)["base"], "floating");
}

INSTANTIATE_TEST_SUITE_P(SharedRobots, InspectEveryUrdf, ::testing::ValuesIn(test::all_urdfs()),
                         [](const auto& info) { return test::short_name(info.param); });

TEST(Inspect, RobotYamlIsPickedUpAndCanBeGivenExplicitly) {
  for (const std::string model : {"5bar_linkage", "cassie_like", "digit_like_2legs", "robot_delta", "talos_like",
                                  "wl16_like"}) {
    const std::string dir = test::shared_robot("parallel_legs/" + model);
    const Outcome picked = run_mbgen("inspect " + quote(dir + "/robot.urdf") + " --json");
    expect_json_report(picked, model);
    const Outcome given =
        run_mbgen("inspect " + quote(dir + "/robot.urdf") + " --extras " + quote(dir + "/robot.yaml") + " --json");
    expect_json_report(given, model + " --extras");
    EXPECT_EQ(picked.out, given.out) << model;  // deterministic, and the same file either way
    EXPECT_FALSE(nlohmann::json::parse(picked.out)["closures"].empty()) << model;
  }
}

TEST(Inspect, DisneyRobotYamlExitsOneNamingTheMisspeltJoint) {
  const Outcome run = run_mbgen("inspect " + quote(test::shared_robot("parallel_legs/disney_robot/robot.urdf")));
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.err.find("robot.yaml:4: error: joint_name[5]: names 'left_spherical_free_foot'"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("did you mean 'left_s\u0125erical_free_foot'?"), std::string::npos) << run.err;
}

TEST(Inspect, LoopsSubSystemsAndClosedDof) {
  // 5bar_linkage (LOOPS.md): one 6d loop of rank 3, mobility 3 = the two motors and the idle spin.
  const Outcome run = run_mbgen("inspect " + quote(test::shared_robot("parallel_legs/5bar_linkage/robot.urdf")) + " --json");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  ASSERT_EQ(j["loops"].size(), 1u);
  EXPECT_EQ(j["loops"][0]["name"], "closed_loop_1");
  EXPECT_EQ(j["loops"][0]["type"], "weld");
  EXPECT_EQ(j["loops"][0]["bodies"].front(), "sphere");
  EXPECT_EQ(j["loops"][0]["bodies"].back(), "sphere_2");
  EXPECT_EQ(j["loops"][0]["root"], "world");
  ASSERT_EQ(j["subsystems"].size(), 1u);
  const nlohmann::json& s = j["subsystems"][0];
  EXPECT_EQ(s["rank"], 3);
  EXPECT_EQ(s["rows"], 6);
  EXPECT_EQ(s["independent"].size(), 3u);
  EXPECT_EQ(s["dependent"].size(), 3u);
  for (const char* motor : {"mot1", "mot2"})
    EXPECT_NE(std::find(s["independent"].begin(), s["independent"].end(), motor), s["independent"].end()) << motor;
  EXPECT_EQ(j["closed_dof"], 3);
  EXPECT_GT(j["assembly"]["max_joint_change"].get<double>(), 0.1);
  const Outcome text = run_mbgen("inspect " + quote(test::shared_robot("parallel_legs/5bar_linkage/robot.urdf")));
  EXPECT_NE(text.out.find("closed-system DoF: 3 (tree 6 - rank 3)"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("assembly: from the zero pose; largest joint change from it"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("rank 3 (3 redundant)"), std::string::npos) << text.out;
}

// scene: contact shows in text (the sphere count) and JSON (each sphere on its body).
TEST(Inspect, GroundContactIsReported) {
  const std::string data = MBGEN_TEST_DATA;
  const Outcome text = run_mbgen("inspect " + quote(data + "/tiny_arm.urdf") + " --extras " + quote(data + "/extras/contact.yaml"));
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("ground contact: 3 spheres (the SSV vertices of tool); k 1e+06 N/m^1, damping 0.5 s/m, friction 0.3"),
            std::string::npos) << text.out;
  const Outcome run = run_mbgen("inspect " + quote(data + "/tiny_arm.urdf") + " --extras " + quote(data + "/extras/contact.yaml") + " --json");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  const nlohmann::json& c = j["scene"]["contact"];
  ASSERT_EQ(c["spheres"].size(), 3u);
  EXPECT_EQ(c["spheres"][2]["name"], "tool/1/0");
  EXPECT_EQ(c["spheres"][2]["radius"], 0.01);
  EXPECT_EQ(c["ground"]["offset"], -0.1);
}

// scene: rigid_contacts and derivatives_wrt show in text and JSON (hyq held at a foot's frame and
// two feet's points, the derivatives with respect to q and tau only).
TEST(Inspect, RigidContactsAndDerivativeInputsAreReported) {
  const std::string urdf = quote(test::shared_robot("hyq/hyq_no_sensors.urdf"));
  const std::string extras = quote(std::string(MBGEN_TEST_DATA) + "/extras/hyq_rigid_contacts_q_tau.yaml");
  const Outcome text = run_mbgen("inspect " + urdf + " --extras " + extras);
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("rigid contacts (rigid_contact_fd_derivatives): lf_foot (frame, 6 rows), rf_foot (point, 3 rows), "
                          "lh_foot (point, 3 rows)"),
            std::string::npos) << text.out;
  EXPECT_NE(text.out.find("derivatives with respect to: q, tau (the other blocks left out)"), std::string::npos) << text.out;
  const Outcome run = run_mbgen("inspect " + urdf + " --extras " + extras + " --json");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  const nlohmann::json& held = j["scene"]["rigid_contacts"];
  ASSERT_EQ(held.size(), 3u);
  EXPECT_EQ(held[0]["frame"], "lf_foot");
  EXPECT_EQ(held[0]["rows"], 6);
  EXPECT_EQ(held[2]["kind"], "point");
  EXPECT_EQ(j["scene"]["derivatives_wrt"], nlohmann::json::array({"q", "tau"}));
  // A scene without them says so by empty lists, and the text by silence.
  const Outcome plain = run_mbgen("inspect " + quote(std::string(MBGEN_TEST_DATA) + "/tiny_arm.urdf") + " --extras " +
                                  quote(std::string(MBGEN_TEST_DATA) + "/extras/contact.yaml") + " --json");
  ASSERT_EQ(plain.status, 0) << plain.err;
  const nlohmann::json p = nlohmann::json::parse(plain.out);
  EXPECT_TRUE(p["scene"]["rigid_contacts"].empty());
  EXPECT_TRUE(p["scene"]["derivatives_wrt"].empty());
}

/// Lola's legs-only scene (robots/lola/lola_legs.yaml: the upper body locked): what the lock
/// removed, the loops kept, the forward dynamics' operations before and after, and the functions
/// its two outputs leave out.
TEST(Inspect, ModelReductionsAndLeftOutFunctionsAreReported) {
  const std::string lola = std::string(MBGEN_SOURCE_DIR) + "/robots/lola/";
  const Outcome run = run_mbgen("inspect " + quote(lola + "lola.urdf") + " --extras " + quote(lola + "lola_legs.yaml") + " --samples 0");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("model reductions (scene: lock, merge_below, loops):"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("lock: welded 10 joint(s): trunk_yaw at 0, trunk_roll at 0"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("removed: 10 DoF (46 -> 36), 10 bodies (41 -> 31)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("loops: 6 closure(s), 4 sub-system(s) (whole robot: 6, 4)"), std::string::npos) << run.out;
  const std::size_t fd = run.out.find("forward_dynamics: ");
  ASSERT_NE(fd, std::string::npos) << run.out;
  EXPECT_NE(run.out.find("operations, the whole robot's", fd), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("left out by the scene: mass_matrix_factor, mass_matrix_solve, forward_kinematics, frame_poses, "
                         "frame_jacobians, centroidal_momentum_matrix, task_kinematics, self_distances, "
                         "inverse_dynamics_derivatives, forward_dynamics_derivatives, contact_forward_dynamics_derivatives, "
                         "rigid_contact_forward_dynamics_derivatives\n"),
            std::string::npos)
      << run.out;
}

TEST(Inspect, ExtrasFileIsReported) {
  const Outcome run = run_mbgen("inspect " + quote(kData + "/tiny_arm.urdf") + " --extras " +
                            quote(kData + "/extras/tiny_arm_full.yaml") + " --json");
  expect_json_report(run, "tiny_arm");
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["robot"], "tiny_arm_ns");
  EXPECT_EQ(j["closures"].size(), 2u);
  EXPECT_EQ(j["closures"][0]["parent"], "tool");
  EXPECT_EQ(j["drives"][1]["model"], "body");
  EXPECT_EQ(j["actuated"], nlohmann::json({"shoulder", "knee"}));
}

/// Shapes inside another of their link's (the panda's spheres at its cylinders' ends) are listed,
/// in the text with what holds them and in the JSON, and left out of the compounds.
TEST(Inspect, ShapesInsideAnotherOfTheirLinksAreReported) {
  const std::string panda = quote(std::string(MBGEN_SHARED_ROBOTS) + "/panda/panda_collision.urdf");
  const Outcome text = run_mbgen("inspect " + panda + " --samples 0");
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("collision shapes left out: 22, each inside another shape of its body"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("<collision> 2 of link 'panda_link1'\n    inside "), std::string::npos) << text.out;
  const Outcome json = run_mbgen("inspect " + panda + " --samples 0 --json");
  ASSERT_EQ(json.status, 0) << json.err;
  const nlohmann::json dropped = nlohmann::json::parse(json.out)["collision_pairs"]["dropped_shapes"];
  ASSERT_EQ(dropped.size(), 22u);
  EXPECT_NE(dropped[0]["inside"].get<std::string>().find("<collision> 1 of link '"), std::string::npos) << dropped[0];
}

TEST(Inspect, BadDescriptionExitsOneWithTheMessage) {
  const std::string file = kData + "/bad/negative_mass.urdf";
  const Outcome run = run_mbgen("inspect " + quote(file));
  EXPECT_EQ(run.status, 1);
  EXPECT_TRUE(run.out.empty()) << run.out;
  EXPECT_EQ(run.err.rfind(file + ":7: error: link 'arm': negative mass", 0), 0u) << run.err;
  EXPECT_NE(run.err.find("\n  fix: "), std::string::npos) << run.err;
  EXPECT_EQ(run_mbgen("inspect " + quote(file) + " --json").status, 1);
}

TEST(Inspect, BadExtrasExitsOne) {
  const Outcome run = run_mbgen("inspect " + quote(kData + "/tiny_arm.urdf") + " --extras " +
                            quote(kData + "/bad/malformed.yaml"));
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.err.find("malformed.yaml:4: error: malformed YAML"), std::string::npos) << run.err;
}

// An .xml description is read as MJCF (docs/mjcf.md), with no option needed.
TEST(Inspect, MjcfRobotsAreReadByTheirExtension) {
  const Outcome h1 = run_mbgen("inspect " + quote(test::shared_robot("unitree_h1/h1.xml")) + " --json");
  expect_json_report(h1, "h1.xml");
  EXPECT_EQ(nlohmann::json::parse(h1.out)["nv"], 25);
  const Outcome cassie = run_mbgen("inspect " + quote(test::shared_robot("cassie_mjcf/cassie.xml")) + " --json");
  expect_json_report(cassie, "cassie.xml");
  const nlohmann::json j = nlohmann::json::parse(cassie.out);
  EXPECT_EQ(j["nv"], 32);
  EXPECT_EQ(j["closures"].size(), 4u);
  const Outcome toddlerbot = run_mbgen("inspect " + quote(test::shared_robot("toddlerbot_2xc/toddlerbot_2xc.xml")));
  EXPECT_EQ(toddlerbot.status, 1);
  EXPECT_NE(toddlerbot.err.find("fixed 'waist_roll_coupling': not supported: a tendon with a range"), std::string::npos)
      << toddlerbot.err;
}

// SDFormat writes Cassie's loops as a graph: inspect says which joints the spanning tree left out
// and what closure each became, and lists the sub-systems they form.
TEST(Inspect, SdfShowsTheJointsThatBecameClosures) {
  const Outcome run = run_mbgen("inspect " + quote(test::shared_robot("cassie_sdf/cassie_v2.sdf")));
  ASSERT_EQ(run.status, 0) << run.err;
  for (const char* joint : {"left-pitch-rod-joint", "right-pitch-rod-joint", "left-plantar-foot-joint", "right-plantar-foot-joint"})
    EXPECT_NE(run.out.find(std::string("spanning tree: joint '") + joint + "' (ball) closes a loop"), std::string::npos) << joint;
  EXPECT_NE(run.out.find("sub-systems (4)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("closed-system DoF: 18"), std::string::npos) << run.out;
}

TEST(Inspect, MimicShowsTheCouplingWhenCoupledAndSaysHowOtherwise) {
  const std::string urdf = quote(kData + "/mimic/two_link.urdf");
  const Outcome coupled = run_mbgen("inspect " + urdf + " --mimic couple");
  ASSERT_EQ(coupled.status, 0) << coupled.err;
  EXPECT_NE(coupled.out.find("mimic_elbow: coupling 'elbow' = 0.5 * 'shoulder' + 0.1 ("), std::string::npos) << coupled.out;
  EXPECT_NE(coupled.out.find("mimic_elbow: coupling, 1 row: joint 'elbow' follows 'shoulder'"), std::string::npos) << coupled.out;
  EXPECT_NE(coupled.out.find("closed-system DoF: 1 (tree 2 - rank 1)"), std::string::npos) << coupled.out;
  EXPECT_EQ(coupled.out.find("mimics"), std::string::npos) << coupled.out;
  const nlohmann::json j = nlohmann::json::parse(run_mbgen("inspect " + urdf + " --mimic couple --json").out);
  ASSERT_EQ(j["closures"].size(), 1u);
  EXPECT_EQ(j["closures"][0]["type"], "coupling");
  EXPECT_EQ(j["closures"][0]["leader"], "shoulder");
  EXPECT_EQ(j["closures"][0]["follower"], "elbow");
  EXPECT_EQ(j["closures"][0]["ratio"], 0.5);
  EXPECT_EQ(j["closures"][0]["offset"], 0.1);
  const Outcome independent = run_mbgen("inspect " + urdf);
  ASSERT_EQ(independent.status, 0) << independent.err;
  EXPECT_NE(independent.out.find("joint 'elbow' mimics 'shoulder' (line 14): loaded as an independent joint"), std::string::npos)
      << independent.out;
  EXPECT_NE(independent.out.find("--mimic couple"), std::string::npos) << independent.out;
  EXPECT_EQ(run_mbgen("inspect " + urdf + " --mimic sometimes").status, 2);
}

TEST(Inspect, UsageErrorsExitTwo) {
  EXPECT_EQ(run_mbgen("inspect").status, 2);
  EXPECT_EQ(run_mbgen("inspect /no/such/file.urdf").status, 2);
  EXPECT_EQ(run_mbgen("inspect " + quote(kData + "/tiny_arm.urdf") + " --fixed --floating").status, 2);
  EXPECT_EQ(run_mbgen("").status, 2);  // a subcommand is required
}

TEST(Inspect, Version) {
  const Outcome run = run_mbgen("--version");
  EXPECT_EQ(run.status, 0);
  EXPECT_EQ(run.out.rfind("mbgen ", 0), 0u) << run.out;
}

}  // namespace
// An indefinite inertia is refused with the opt-in named; with it, the note says what changed.
TEST(InspectCommand, RepairInertiaOnRequest) {
  const std::string file = kData + "/inertia/indefinite_antenna.urdf";
  const Outcome refused = run_mbgen("inspect " + quote(file));
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.err.find("indefinite_antenna.urdf:9: error: link 'antenna': inertia is not positive semi-definite"),
            std::string::npos)
      << refused.err;
  EXPECT_NE(refused.err.find("--repair-inertia"), std::string::npos) << refused.err;
  const Outcome repaired = run_mbgen("inspect --repair-inertia " + quote(file));
  EXPECT_EQ(repaired.status, 0) << repaired.err;
  EXPECT_NE(repaired.out.find("notes (1):\n  - link 'antenna' (line 9): inertia repaired (--repair-inertia)"),
            std::string::npos)
      << repaired.out;
}

}  // namespace mbgen
