// The scene behind a page of `mbgen view` (generator/view/view_scene.cpp, trajectory_csv.cpp,
// view_page.cpp): its poses are the generated forward kinematics' (1e-12), a trajectory of N rows
// gives N frames, the near pairs and their witness points are the runtime's distances, the
// closures and contact spheres sit where the model has them, a missing mesh is a warning, and a
// trajectory that does not fit the robot is refused naming the column.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <random>

#include "collision/contact_spheres.hpp"
#include "load/load_error.hpp"
#include "mbgen/algorithm/configuration.hpp"
#include "mbgen/sim/trajectory_csv.hpp"
#include "test_support.hpp"
#include "view/base64.hpp"
#include "view/trajectory_csv.hpp"
#include "view/view_page.hpp"
#include "view/view_scene.hpp"
#include "lola.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mbgen;
using Json = nlohmann::json;

fs::path scratch(const std::string& leaf) {
  const fs::path dir = fs::temp_directory_path() / "mbgen_test_view_scene";
  fs::create_directories(dir);
  return dir / leaf;
}

const gen::Description& lola() {
  static const gen::Description d = test::load_lola();
  return d;
}

/// Random configurations of Lola: joints within +-0.5 rad of the assembled pose, a random base.
std::vector<VecX<double>> random_poses(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  std::vector<VecX<double>> poses;
  for (int k = 0; k < n; ++k) {
    VecX<double> q = view::nominal_pose(lola());
    for (int i = 0; i < q.size(); ++i) q[i] += u(rng);
    q.segment<4>(3).normalize();
    poses.push_back(q);
  }
  return poses;
}

/// The largest difference between the scene's frame k and the generated forward_kinematics at q.
double pose_error(const Json& scene, std::size_t k, const VecX<double>& q) {
  std::vector<double> X(12 * lola::num_bodies);
  lola::forward_kinematics(q.data(), X.data());
  const Json& shown = scene["frames"]["X_WB"][k];
  EXPECT_EQ(shown.size(), X.size());
  double worst = 0;
  for (std::size_t i = 0; i < X.size(); ++i) worst = std::max(worst, std::abs(shown[i].get<double>() - X[i]));
  return worst;
}

/// A trajectory file of these poses, written as mbgen_sim and mbgen_walk write theirs.
fs::path write_trajectory(const std::string& leaf, const std::vector<VecX<double>>& poses, double dt = 0.01) {
  const fs::path path = scratch(leaf);
  sim::TrajectoryCsvWriter out(path.string(), lola().model);
  for (std::size_t k = 0; k < poses.size(); ++k) out.write(dt * static_cast<double>(k), poses[k].data());
  return path;
}

/// The JSON a written page holds.
Json scene_of_page(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"mbgen-scene\">";
  const std::size_t begin = page.find(open) + open.size(), end = page.find("</script>", begin);
  return Json::parse(page.substr(begin, end - begin));
}

view::ViewOptions options_every_row() {
  view::ViewOptions o;
  o.fps = 0;
  return o;
}

TEST(ViewScene, TheAssembledPoseIsTheGeneratedForwardKinematics) {
  std::vector<std::string> warnings;
  const Json scene = view::view_scene(lola(), nullptr, view::ViewOptions{}, warnings);
  ASSERT_EQ(scene["frames"]["t"].size(), 1u);
  ASSERT_EQ(scene["bodies"].size(), static_cast<std::size_t>(lola::num_bodies));
  for (int b = 0; b < lola::num_bodies; ++b) EXPECT_EQ(scene["bodies"][static_cast<std::size_t>(b)], lola::body_names[b]);
  EXPECT_LE(pose_error(scene, 0, lola().assembly.q), 1e-12);
  EXPECT_EQ(scene["closures"].size(), lola().model.closures.size());  // Lola's loops are all spatial
  EXPECT_EQ(scene["pairs"].size(), static_cast<std::size_t>(lola::num_distance_pairs));
}

TEST(ViewScene, ATrajectoryOfNRowsHasNPoseSetsEachTheGeneratedKinematics) {
  const std::vector<VecX<double>> poses = random_poses(7, 3);
  const view::Trajectory t = view::read_trajectory_csv(write_trajectory("seven.csv", poses).string(), lola().model, {});
  ASSERT_EQ(t.q.size(), 7u);
  std::vector<std::string> warnings;
  const Json scene = view::view_scene(lola(), &t, options_every_row(), warnings);
  ASSERT_EQ(scene["frames"]["X_WB"].size(), 7u);
  ASSERT_EQ(scene["frames"]["near"].size(), 7u);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    EXPECT_LE(pose_error(scene, k, poses[k]), 1e-12) << "frame " << k;
    EXPECT_DOUBLE_EQ(scene["frames"]["t"][k].get<double>(), 0.01 * static_cast<double>(k));
  }
  // Through the page's text: the numbers survive the JSON round trip.
  const view::ViewerAssets assets{"<meta name=\"generator\" content=\"mbgen view\">@@TITLE@@ @@THREE@@ @@ORBIT_CONTROLS@@ "
                                  "<script type=\"application/json\" id=\"mbgen-scene\">@@SCENE@@</script>@@VIEWER@@",
                                  "viewer", "three", "orbit"};
  const Json again = scene_of_page(view::view_page(scene, assets));
  for (std::size_t k = 0; k < poses.size(); ++k) EXPECT_LE(pose_error(again, k, poses[k]), 1e-12) << "frame " << k;
}

TEST(ViewScene, TheFrameRateKeepsTheRowsNearestEachTick) {
  const std::vector<double> t = {0, 0.001, 0.002, 0.01, 0.02, 0.021, 0.05, 0.051};
  EXPECT_EQ(view::resample(t, 0), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(view::resample(t, 100), (std::vector<int>{0, 3, 4, 6, 7}));  // ticks 0, .01, .02, .03 -> .05, then the last row
  EXPECT_EQ(view::resample({1.0}, 30), (std::vector<int>{0}));
}

TEST(ViewScene, NearPairsAreTheRuntimesDistancesWithTheirWitnessPoints) {
  std::vector<std::string> warnings;
  view::ViewOptions o;
  o.near_threshold = 0.03;
  const Json scene = view::view_scene(lola(), nullptr, o, warnings);
  // The generated self_distances at the same pose: every pair below the threshold is listed, with its distance.
  std::vector<double> distance(lola::num_distance_pairs), normal(3 * lola::num_distance_pairs), witness(6 * lola::num_distance_pairs),
      jacobian(static_cast<std::size_t>(lola::num_distance_pairs * lola::nv));
  lola::self_distances(lola().assembly.q.data(), distance.data(), normal.data(), witness.data(), jacobian.data());
  std::size_t expected = 0;
  for (double d : distance) expected += d < 0.03;
  const Json& near = scene["frames"]["near"][0];
  ASSERT_EQ(near.size(), expected);
  ASSERT_GT(expected, 0u);
  for (const Json& n : near) {
    const std::size_t pair = n[0].get<std::size_t>();
    EXPECT_NEAR(n[1].get<double>(), distance[pair], 1e-12);
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(n[2 + static_cast<std::size_t>(k)].get<double>(), witness[6 * pair + static_cast<std::size_t>(k)], 1e-12);
    // The pair's bodies are the generated pair's.
    const Json& bodies = scene["pairs"][pair];
    EXPECT_EQ(scene["bodies"][bodies[0].get<std::size_t>()], lola::distance_pair_names[pair][0]);
    EXPECT_EQ(scene["bodies"][bodies[1].get<std::size_t>()], lola::distance_pair_names[pair][1]);
  }
  // A smaller threshold lists fewer pairs: the hip rolls at 16 mm go at 1 cm.
  o.near_threshold = 0.01;
  const Json tight = view::view_scene(lola(), nullptr, o, warnings);
  EXPECT_LT(tight["frames"]["near"][0].size(), expected);
}

TEST(ViewScene, ClosureFramesMeetAtTheAssembledPose) {
  std::vector<std::string> warnings;
  const Json scene = view::view_scene(lola(), nullptr, view::ViewOptions{}, warnings);
  const Json& X = scene["frames"]["X_WB"][0];
  const auto world = [&](const Json& body, const Json& p) {
    const std::size_t o = 12 * body.get<std::size_t>();
    Vec3<double> x;
    for (int i = 0; i < 3; ++i) {
      x[i] = X[o + 4 * static_cast<std::size_t>(i) + 3].get<double>();
      for (int j = 0; j < 3; ++j) x[i] += X[o + 4 * static_cast<std::size_t>(i) + static_cast<std::size_t>(j)].get<double>() * p[static_cast<std::size_t>(j)].get<double>();
    }
    return x;
  };
  for (const Json& c : scene["closures"])
    EXPECT_LE((world(c["body_a"], c["point_a"]) - world(c["body_b"], c["point_b"])).norm(), 1e-9) << c["name"];
}

TEST(ViewScene, ContactForcesComeInTheScenesSphereOrder) {
  std::vector<std::string> names;
  for (const ContactSphere& s : gen::contact_spheres(lola())) names.push_back(s.name);
  ASSERT_GE(names.size(), 2u);
  // Two of the spheres' columns, in reverse order: each force lands on its own sphere.
  const fs::path path = scratch("forces.csv");
  {
    sim::TrajectoryCsvWriter out(path.string(), lola().model, {names[1], names[0]});
    const double forces[2] = {11.0, 22.0};
    out.write(0.0, lola().assembly.q.data(), forces);
  }
  const view::Trajectory t = view::read_trajectory_csv(path.string(), lola().model, names);
  std::vector<std::string> warnings;
  const Json scene = view::view_scene(lola(), &t, view::ViewOptions{}, warnings);
  const Json& f = scene["frames"]["forces"][0];
  ASSERT_EQ(f.size(), names.size());
  EXPECT_EQ(f[0].get<double>(), 22.0);
  EXPECT_EQ(f[1].get<double>(), 11.0);
  for (std::size_t k = 2; k < names.size(); ++k) EXPECT_EQ(f[k].get<double>(), 0.0);
  EXPECT_EQ(scene["contacts"][0]["name"], names[0]);
}

/// The error read_trajectory_csv throws for a file of these lines.
std::string refusal(const std::string& leaf, const std::string& text, const std::vector<std::string>& contacts = {}) {
  const fs::path path = scratch(leaf);
  std::ofstream(path) << text;
  try {
    view::read_trajectory_csv(path.string(), lola().model, contacts);
  } catch (const gen::LoadError& e) {
    return e.what();
  }
  return "accepted";
}

std::string header() {
  std::string h = "t";
  for (const std::string& c : sim::configuration_columns(lola().model)) h += "," + c;
  return h;
}

std::string row(double t, const VecX<double>& q) {
  std::string r = std::to_string(t);
  for (int i = 0; i < q.size(); ++i) r += fmt::format(",{:.17g}", q[i]);
  return r;
}

TEST(ViewScene, ATrajectoryThatDoesNotFitTheRobotIsRefusedNamingTheColumn) {
  const VecX<double> q = lola().assembly.q;
  // Two joints swapped: the first wrong column is named, with what it should be.
  std::vector<std::string> columns = sim::configuration_columns(lola().model);
  std::swap(columns[8], columns[9]);
  std::string swapped = "t";
  for (const std::string& c : columns) swapped += "," + c;
  const std::string e = refusal("swapped.csv", swapped + "\n" + row(0, q) + "\n");
  EXPECT_NE(e.find("swapped.csv:1"), std::string::npos) << e;
  EXPECT_NE(e.find(fmt::format("column 10 ('{}')", columns[8])), std::string::npos) << e;
  EXPECT_NE(e.find(fmt::format("named '{}'", columns[9])), std::string::npos) << e;
  // Too few columns, a value that is not a number, time backwards, a non-unit quaternion, an unknown force.
  EXPECT_NE(refusal("short.csv", "t,root_joint[0]\n0,0\n").find("robot 'lola' has nq = 47"), std::string::npos);
  std::string bad = row(0, q);
  bad.replace(bad.find(',') + 1, 1, "x");
  EXPECT_NE(refusal("nan.csv", header() + "\n" + bad + "\n").find("nan.csv:2: error: column 2 ('root_joint[0]'): holds 'x'"), std::string::npos)
      << refusal("nan.csv", header() + "\n" + bad + "\n");
  EXPECT_NE(refusal("back.csv", header() + "\n" + row(1, q) + "\n" + row(0.5, q) + "\n").find("back.csv:3: error: column 1 ('t'): goes back in time"),
            std::string::npos);
  VecX<double> long_quaternion = q;
  long_quaternion[6] *= 1.5;
  EXPECT_NE(refusal("quaternion.csv", header() + "\n" + row(0, long_quaternion) + "\n").find("not 1"), std::string::npos);
  EXPECT_NE(refusal("force.csv", header() + ",force:nowhere\n" + row(0, q) + ",1\n", {"foot_body_l/0/0"}).find("names no contact sphere"),
            std::string::npos);
  EXPECT_NE(refusal("empty.csv", header() + "\n").find("has a header and no rows"), std::string::npos);
  EXPECT_NE(refusal("fields.csv", header() + "\n" + row(0, q) + ",3\n").find("has 49 fields; the header has 48"), std::string::npos);
  EXPECT_EQ(refusal("good.csv", header() + "\n" + row(0, q) + "\n"), "accepted");
}

TEST(ViewScene, AMissingMeshIsAWarningAndItsLinkKeepsItsSsvs) {
  const fs::path urdf = scratch("two_links.urdf");
  std::ofstream(urdf) << R"(<robot name="two_links">
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.1 0.2 0.3"/></geometry></collision></link>
  <link name="arm"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><mesh filename="missing_arm.stl"/></geometry></collision>
    <collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <link name="hand"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="arm"/><child link="hand"/><origin xyz="0 0 0.5"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>)";
  gen::LoadOptions load;
  load.base = gen::BaseType::Floating;
  const gen::Description d = gen::load_description(urdf.string(), load);
  std::vector<std::string> warnings;
  const Json scene = view::view_scene(d, nullptr, view::ViewOptions{}, warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("missing_arm.stl"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("link 'arm' is drawn with its SSVs only"), std::string::npos) << warnings[0];
  // The base's and the hand's boxes are drawn (12 triangles each, in their bodies' frames); the arm keeps its sphere.
  ASSERT_EQ(scene["meshes"].size(), 2u);
  for (const Json& m : scene["meshes"]) EXPECT_NE(m["link"], "arm");
  const Json& hand = scene["meshes"][1];
  EXPECT_EQ(hand["link"], "hand");
  EXPECT_EQ(hand["indices"].get<std::string>().size(), 4u * (12 * 3 * 4) / 3);  // 12 triangles of 3 uint32, in base64
  bool sphere = false;
  for (const Json& s : scene["ssv"]) sphere |= s["kind"] == "point" && scene["bodies"][s["body"].get<std::size_t>()] == "arm";
  EXPECT_TRUE(sphere);
  // Without meshes asked for, none, and no warning.
  view::ViewOptions no_meshes;
  no_meshes.meshes = false;
  warnings.clear();
  EXPECT_TRUE(view::view_scene(d, nullptr, no_meshes, warnings)["meshes"].empty());
  EXPECT_TRUE(warnings.empty());
}

TEST(ViewScene, Base64IsRfc4648) {
  EXPECT_EQ(view::base64(""), "");
  EXPECT_EQ(view::base64("f"), "Zg==");
  EXPECT_EQ(view::base64("fo"), "Zm8=");
  EXPECT_EQ(view::base64("foo"), "Zm9v");
  EXPECT_EQ(view::base64("foobar"), "Zm9vYmFy");
  const unsigned char bytes[] = {0xff, 0xfe, 0x00};
  EXPECT_EQ(view::base64(bytes, 3), "//4A");
}

TEST(ViewScene, TalosMeshesResolveThroughThePackagePath) {
  gen::LoadOptions load;
  load.base = gen::BaseType::Floating;
  load.package_paths["example-robot-data"] = test::shared_robot("talos/meshes/example-robot-data");
  const gen::Description d = gen::load_description(test::shared_robot("talos/talos_reduced.urdf"), load);
  view::ViewOptions o;
  o.package_paths = load.package_paths;
  std::vector<std::string> warnings;
  const Json scene = view::view_scene(d, nullptr, o, warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_GE(scene["meshes"].size(), 25u);
  // Without the package path, each link with a mesh file is a warning and is drawn without it;
  // links of boxes alone are drawn still.
  std::size_t with_files = 0;
  for (const auto& [link, geometries] : d.link_meshes)
    with_files += std::any_of(geometries.begin(), geometries.end(), [](const gen::MeshGeometry& g) { return !g.box; });
  ASSERT_LT(with_files, d.link_meshes.size());
  view::ViewOptions lost;
  warnings.clear();
  EXPECT_EQ(view::view_scene(d, nullptr, lost, warnings)["meshes"].size(), d.link_meshes.size() - with_files);
  EXPECT_EQ(warnings.size(), with_files);
}

TEST(ViewPage, TheJsonCannotCloseItsScriptAndEveryPlaceholderIsFilled) {
  Json scene = {{"robot", "a</script><b>"}, {"frames", {{"t", {0}}}}};
  const view::ViewerAssets assets{"<title>@@TITLE@@</title>@@THREE@@ @@ORBIT_CONTROLS@@ <script id=\"mbgen-scene\">@@SCENE@@</script><script>@@VIEWER@@</script>",
                                  "viewer();", "three", "orbit"};
  const std::string page = view::view_page(scene, assets);
  EXPECT_EQ(page.find("@@"), std::string::npos);
  EXPECT_EQ(page.find("a</script>"), std::string::npos) << page;
  EXPECT_NE(page.find("<title>a&lt;/script&gt;&lt;b&gt; — mbgen view</title>"), std::string::npos) << page;
  EXPECT_NE(page.find(view::base64("three")), std::string::npos);
  EXPECT_EQ(Json::parse(page.substr(page.find("\"mbgen-scene\">") + 14, page.find("</script><script>") - page.find("\"mbgen-scene\">") - 14))["robot"],
            "a</script><b>");
}

}  // namespace
