// The collision scene (generator/collision/collision_scene.cpp): compounds per body and the pruned pair
// list, on tests/data/collision_arm.urdf whose answers follow from its geometry (see the file's
// comment: adjacent, never close with a closed-form distance range, always overlapping, kept),
// and on the Lola biped's scene (excluded pairs, determinism). Robots with loops are sampled in
// closed poses only (ConfigurationSampler): every sample closes its loops, the discarded draws
// are counted, and the four-bar shows a verdict that the open-loop sampling got wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>

#include "mbgen/collision/compound_distance.hpp"
#include "collision/collision_scene.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

using gen::PairVerdict;

std::map<std::pair<std::string, std::string>, gen::PairDecision> by_names(const gen::CollisionScene& scene) {
  std::map<std::pair<std::string, std::string>, gen::PairDecision> out;
  for (const gen::PairDecision& p : scene.decisions)
    out[{scene.model.compounds[static_cast<std::size_t>(p.first)].name, scene.model.compounds[static_cast<std::size_t>(p.second)].name}] = p;
  return out;
}

gen::Description load(const std::string& path, const std::string& extras = "") {
  gen::LoadOptions options;
  if (!extras.empty()) options.extras_file = extras;
  options.pick_up_robot_yaml = false;
  return gen::load_description(path, options);
}

gen::Description load_lola() {
  const std::string dir = MBGEN_SOURCE_DIR "/robots/lola/";
  return load(dir + "lola.urdf", dir + "lola.yaml");
}

/// Largest |Phi| over every closure row (redundant rows included) at q.
double closure_error(const Model& model, const VecX<double>& q) {
  Data<double> data(model);
  return closure_residual<double>(model, data, q).cwiseAbs().maxCoeff();
}

/// Checks the samples of a robot with loops: each closes to 1e-10 (every closure row, redundant
/// ones included), has its independent coordinates within their limits and the floating base at
/// the origin, and the report adds up.
void expect_closed_samples(const gen::Description& d, int draws, const std::string& what, bool some_close = true) {
  const Model& model = d.model;
  gen::CollisionSceneOptions options;
  options.samples = draws;
  gen::SamplingReport report;
  const std::vector<VecX<double>> samples = gen::collision_sample_configurations(d, options, &report);
  EXPECT_TRUE(report.loops) << what;
  EXPECT_EQ(report.drawn, draws) << what;
  EXPECT_EQ(report.used(), static_cast<int>(samples.size())) << what;
  EXPECT_EQ(report.used() + report.discarded(), draws) << what;
  EXPECT_EQ(report.used(), report.closed) << what;
  EXPECT_LE(report.beyond_limits, report.used()) << what;
  EXPECT_LE(report.refined, report.used()) << what;
  if (some_close) {
    EXPECT_FALSE(samples.empty()) << what;
  }
  double worst = 0;
  int beyond = 0;
  for (const VecX<double>& q : samples) {
    ASSERT_EQ(q.size(), model.nq());
    worst = std::max(worst, closure_error(model, q));
    bool out = false;
    for (int j = 1; j < model.num_joints(); ++j) {
      const Joint& joint = model.joint(JointIndex(j));
      if (joint.nq != 1 || !joint.bounded || !(joint.upper > joint.lower)) continue;
      const double x = q[joint.idx_q];
      if (model.structure().column_of_v[static_cast<std::size_t>(joint.idx_v)] >= 0) {  // independent: drawn within the limits
        EXPECT_GE(x, joint.lower) << what << ": " << joint.name;
        EXPECT_LE(x, joint.upper) << what << ": " << joint.name;
      } else if (x < joint.lower - 1e-9 || x > joint.upper + 1e-9) {
        out = true;
      }
    }
    beyond += out;
    if (model.floating_base()) {
      EXPECT_EQ(q.head<7>(), (VecX<double>(7) << 0, 0, 0, 0, 0, 0, 1).finished()) << what;
    }
  }
  EXPECT_EQ(beyond, report.beyond_limits) << what;
  EXPECT_LT(worst, 1e-10) << what;
}

TEST(CollisionScene, VerdictsFollowTheGeometry) {
  const gen::Description d = load(MBGEN_TEST_DATA "/collision_arm.urdf");
  gen::CollisionSceneOptions options;
  options.samples = 2000;
  const gen::CollisionScene scene = gen::build_collision_scene(d, options);
  ASSERT_EQ(scene.model.compounds.size(), 5u);  // world (the base link), link1, link2, link3, side
  auto pairs = by_names(scene);
  ASSERT_EQ(pairs.size(), 10u);
  EXPECT_EQ((pairs[{"world", "link1"}].verdict), PairVerdict::Adjacent);
  EXPECT_EQ((pairs[{"link1", "link2"}].verdict), PairVerdict::Adjacent);
  EXPECT_EQ((pairs[{"link1", "side"}].verdict), PairVerdict::AlwaysOverlapping);
  EXPECT_DOUBLE_EQ((pairs[{"link1", "side"}].max_distance), -0.2);  // two r 0.1 spheres, same centre
  // base - link2: centres 0.3 .. 0.9 apart (closed form), radii 0.1 + 0.05.
  const gen::PairDecision& far = pairs[std::make_pair(std::string("world"), std::string("link2"))];
  EXPECT_EQ(far.verdict, PairVerdict::NeverClose);
  EXPECT_GE(far.min_distance, 0.15 - 1e-12);
  EXPECT_LT(far.min_distance, 0.16);  // 2000 samples come close to the bound
  EXPECT_EQ((pairs[{"world", "link3"}].verdict), PairVerdict::Kept);
  EXPECT_LT((pairs[{"world", "link3"}].min_distance), 0.05);
  EXPECT_EQ(scene.model.pairs.size(), 3u);  // world-link3, link1-link3, link3-side
}

TEST(CollisionScene, NoSamplingKeepsEveryNonAdjacentPair) {
  const gen::Description d = load(MBGEN_TEST_DATA "/collision_arm.urdf");
  gen::CollisionSceneOptions options;
  options.samples = 0;
  const gen::CollisionScene scene = gen::build_collision_scene(d, options);
  EXPECT_EQ(scene.model.pairs.size(), 6u);  // 10 pairs, 4 adjacent
}

TEST(CollisionScene, IncludeAndExcludeListsWin) {
  const gen::Description d = load(MBGEN_TEST_DATA "/collision_arm.urdf", MBGEN_TEST_DATA "/extras/collision_arm_scene.yaml");
  const gen::CollisionSceneOptions options = gen::collision_scene_options(d);
  EXPECT_EQ(options.margin, 0.02);
  EXPECT_EQ(options.samples, 300);
  auto pairs = by_names(gen::build_collision_scene(d, options));
  EXPECT_EQ((pairs[{"link1", "side"}].verdict), PairVerdict::Included);  // always overlapping, but asked for
  EXPECT_EQ((pairs[{"world", "link3"}].verdict), PairVerdict::Excluded);  // the base link is the world body
  EXPECT_EQ((pairs[{"link1", "link3"}].verdict), PairVerdict::Kept);
}

TEST(CollisionScene, LolaHonoursExcludesAndIsDeterministic) {
  const std::string dir = MBGEN_SOURCE_DIR "/robots/lola/";
  const gen::Description d = load(dir + "lola.urdf", dir + "lola.yaml");
  ASSERT_TRUE(d.scene);
  gen::CollisionSceneOptions options = gen::collision_scene_options(d);
  EXPECT_EQ(options.margin, 0.05);   // lola.yaml: margin 0.05
  EXPECT_EQ(options.samples, 20000); // lola.yaml: prune_samples 20000
  options.samples = 500;
  const gen::CollisionScene a = gen::build_collision_scene(d, options), b = gen::build_collision_scene(d, options);
  auto pairs = by_names(a);
  EXPECT_EQ((pairs[{"pelvis", "torso"}].verdict), PairVerdict::Excluded);
  EXPECT_EQ((pairs[{"pelvis", "thigh_l"}].verdict), PairVerdict::Excluded);
  int kept = 0, never = 0;
  for (const gen::PairDecision& p : a.decisions) {
    kept += p.verdict == PairVerdict::Kept;
    never += p.verdict == PairVerdict::NeverClose;
  }
  EXPECT_GT(kept, 0);
  EXPECT_GT(never, 0);
  ASSERT_EQ(a.decisions.size(), b.decisions.size());
  for (std::size_t k = 0; k < a.decisions.size(); ++k) {
    EXPECT_EQ(a.decisions[k].verdict, b.decisions[k].verdict);
    // Bit-identical (NaN for pairs decided without sampling).
    EXPECT_EQ(std::memcmp(&a.decisions[k].min_distance, &b.decisions[k].min_distance, sizeof(double)), 0);
  }
}

/// The ROS capsule idiom (a cylinder and a sphere of its radius at each end): the spheres lie in
/// the cylinder's line SSV and are left out of the compound, each listed with its container.
/// Lola's drive rods and housings (10 links) and franka's panda (every link but the hand's).
TEST(CollisionScene, SpheresAtTheEndsOfACylinderAreLeftOut) {
  const gen::Description lola = load_lola();
  gen::CollisionSceneOptions options;
  options.samples = 0;
  const gen::CollisionScene scene = gen::build_collision_scene(lola, options);
  ASSERT_EQ(scene.dropped_shapes.size(), 20u);
  for (const gen::DroppedShape& s : scene.dropped_shapes) {
    const bool end_sphere = s.source.find("<collision> 2 of link '" + s.compound + "'") != std::string::npos ||
                            s.source.find("<collision> 3 of link '" + s.compound + "'") != std::string::npos;
    EXPECT_TRUE(end_sphere) << s.source;
    EXPECT_NE(s.container_source.find("<collision> 1 of link '" + s.compound + "'"), std::string::npos) << s.container_source;
    EXPECT_LE(s.protrusion, 1e-12) << s.source;
  }
  int shape_pairs = 0;
  for (const collision::Compound& c : scene.model.compounds) {
    if (c.name.find("_rod_") != std::string::npos || c.name.find("_housing_") != std::string::npos) {
      ASSERT_EQ(c.shapes.size(), 1u) << c.name;
      EXPECT_EQ(c.shapes[0].kind, collision::Shape::Kind::Line) << c.name;
    }
  }
  const gen::CollisionScene pruned = gen::build_collision_scene(lola, gen::collision_scene_options(lola));
  for (const collision::CollisionPair& p : pruned.model.pairs)
    shape_pairs += static_cast<int>(pruned.model.compounds[static_cast<std::size_t>(p.first)].shapes.size() *
                                    pruned.model.compounds[static_cast<std::size_t>(p.second)].shapes.size());
  EXPECT_EQ(pruned.model.pairs.size(), 178u);
  EXPECT_EQ(shape_pairs, 247) << "Lola's 178 pairs held 711 shape pairs with the spheres";

  const gen::Description panda = load(shared_robot("panda/panda_collision.urdf"));
  EXPECT_EQ(gen::build_collision_scene(panda, options).dropped_shapes.size(), 22u);
}

}  // namespace
}  // namespace mbgen::test

namespace mbgen::test {
namespace {

TEST(CollisionSceneLoops, LolaSamplesAreClosedPoses) {
  const gen::Description d = load_lola();
  ASSERT_FALSE(d.model.subsystems.empty());
  expect_closed_samples(d, 400, "lola");
}

TEST(CollisionSceneLoops, MechanismAndParallelLegSamplesAreClosedPoses) {
  const std::string mechanisms = MBGEN_SOURCE_DIR "/robots/mechanisms/";
  for (const char* name : {"four_bar", "slider_crank", "ankle_2dof"})
    expect_closed_samples(load(mechanisms + name + ".urdf", mechanisms + name + ".yaml"), 300, name);
  // wl16_like: a small Newton basin (closure_positions.hpp, max_step) and unbounded motors, so that few
  // draws close at all; those that do must be closed poses.
  const std::string wl16 = shared_robot("parallel_legs/wl16_like/");
  if (std::filesystem::exists(wl16))
    expect_closed_samples(load(wl16 + "robot.urdf", wl16 + "robot.yaml"), 300, "wl16_like", /*some_close=*/false);
}

TEST(CollisionSceneLoops, SamplesAndPairsAreDeterministic) {
  const gen::Description d = load_lola();
  gen::CollisionSceneOptions options;
  options.samples = 200;
  gen::SamplingReport ra, rb;
  const std::vector<VecX<double>> a = gen::collision_sample_configurations(d, options, &ra);
  const std::vector<VecX<double>> b = gen::collision_sample_configurations(d, options, &rb);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k)
    EXPECT_EQ(std::memcmp(a[k].data(), b[k].data(), sizeof(double) * static_cast<std::size_t>(a[k].size())), 0) << k;
  EXPECT_EQ(ra.closed, rb.closed);
  EXPECT_EQ(ra.refined, rb.refined);
  EXPECT_EQ(ra.not_closed, rb.not_closed);
  EXPECT_EQ(ra.beyond_limits, rb.beyond_limits);
  // The scene evaluates exactly these samples.
  const gen::CollisionScene scene = gen::build_collision_scene(d, options);
  EXPECT_EQ(scene.sampling.used(), static_cast<int>(a.size()));
  EXPECT_EQ(scene.sampling.drawn, 200);
  // Another seed draws other samples.
  options.seed = 2;
  const std::vector<VecX<double>> c = gen::collision_sample_configurations(d, options);
  ASSERT_FALSE(c.empty());
  EXPECT_NE(c.front(), a.front());
}

TEST(CollisionSceneLoops, TreeSamplingIsTheDrawItself) {
  // A tree robot: every draw is used, as before the loops were closed (same RNG sequence).
  const gen::Description d = load(MBGEN_TEST_DATA "/collision_arm.urdf");
  ASSERT_TRUE(d.model.subsystems.empty());
  gen::CollisionSceneOptions options;
  options.samples = 50;
  gen::SamplingReport report;
  const std::vector<VecX<double>> samples = gen::collision_sample_configurations(d, options, &report);
  EXPECT_FALSE(report.loops);
  EXPECT_EQ(report.used(), 50);
  EXPECT_EQ(report.discarded(), 0);
  std::mt19937_64 rng(options.seed);
  for (const VecX<double>& q : samples) EXPECT_EQ(q, random_configuration<double>(d.model, rng));
  const gen::CollisionScene scene = gen::build_collision_scene(d, options);
  EXPECT_TRUE(scene.warnings.empty());
  EXPECT_EQ(gen::sampling_summary(scene), "50 configurations sampled");
}

TEST(CollisionSceneLoops, DrawsOutsideTheWorkspaceAreDiscardedCountedAndWarnedAbout) {
  // The slider drives the slider-crank: only slider_joint in (-0.04, 0.06) of its limits
  // [-0.2, 0.2] closes the loop (robots/mechanisms/README.md), a quarter of the draws.
  const gen::Description d = load(MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.urdf",
                                  MBGEN_TEST_DATA "/mechanisms/slider_crank_slider_driven_ssv.yaml");
  gen::CollisionSceneOptions options;
  options.samples = 400;
  const gen::CollisionScene scene = gen::build_collision_scene(d, options);
  const gen::SamplingReport& r = scene.sampling;
  EXPECT_TRUE(r.loops);
  EXPECT_EQ(r.drawn, 400);
  EXPECT_GT(r.not_closed, 250);
  EXPECT_GT(r.used(), 60);
  EXPECT_LT(r.used(), 140);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_NE(scene.warnings[0].find("robot 'slider_crank'"), std::string::npos) << scene.warnings[0];
  EXPECT_NE(scene.warnings[0].find("only " + std::to_string(r.used()) + " of the 400"), std::string::npos) << scene.warnings[0];
  const std::string summary = gen::sampling_summary(scene);
  EXPECT_EQ(r.discarded(), r.not_closed);
  EXPECT_NE(summary.find(std::to_string(r.discarded()) + " discarded (not closed)"), std::string::npos) << summary;
  // Every used sample has the slider inside the stroke.
  const int slider = d.model.joint(*d.model.find_joint("slider_joint")).idx_q;
  for (const VecX<double>& q : gen::collision_sample_configurations(d, options)) {
    EXPECT_GT(q[slider], -0.04 - 1e-9);
    EXPECT_LT(q[slider], 0.06 + 1e-9);
  }
}

TEST(CollisionSceneLoops, SamplesStayInTheNominalAssemblyMode) {
  // Crank-driven slider-crank: each crank angle closes twice, the slider right of the crank axis
  // (the nominal pose: slider_joint = x - 0.12 in [-0.04, 0.06]) or mirrored left of it (x in
  // [-0.18, -0.08]). A Newton solve straight from the nominal pose to a far crank angle lands in
  // the mirrored mode for some draws; the walk keeps every sample in the nominal one.
  const std::string dir = MBGEN_SOURCE_DIR "/robots/mechanisms/";
  const gen::Description d = load(dir + "slider_crank.urdf", dir + "slider_crank.yaml");
  gen::CollisionSceneOptions options;
  options.samples = 1000;
  gen::SamplingReport report;
  const std::vector<VecX<double>> samples = gen::collision_sample_configurations(d, options, &report);
  EXPECT_EQ(report.used(), 1000);
  EXPECT_EQ(report.beyond_limits, 0);
  const int crank = d.model.joint(*d.model.find_joint("crank_joint")).idx_q;
  const int slider = d.model.joint(*d.model.find_joint("slider_joint")).idx_q;
  for (const VecX<double>& q : samples) {
    // Closed form (robots/mechanisms/README.md): x = r cos(theta) + sqrt(l^2 - r^2 sin^2(theta)), theta = 90 deg + q_crank.
    const double theta = M_PI / 2 + q[crank], r = 0.05, l = 0.13;
    const double x = r * std::cos(theta) + std::sqrt(l * l - r * r * std::sin(theta) * std::sin(theta));
    EXPECT_NEAR(q[slider], x - 0.12, 1e-9) << "crank " << q[crank];
  }
}

TEST(CollisionSceneLoops, FourBarClosedSamplingPrunesWhatOpenSamplingKept) {
  // Four-bar crank-rocker (robots/mechanisms/four_bar, the URDF's capsules): open, the rocker
  // (0.122 m from O4, 0.19 m from the crank axis O2) swings over the whole circle and reaches
  // the crank, so crank - rocker looks close; closed, it only swings 86.5 .. 136.4 deg and
  // stays more than the default margin (0.05 m) from it.
  const std::string dir = MBGEN_SOURCE_DIR "/robots/mechanisms/";
  const gen::Description d = load(dir + "four_bar.urdf", dir + "four_bar.yaml");
  gen::CollisionSceneOptions options;
  options.samples = 2000;
  const gen::CollisionScene closed = gen::build_collision_scene(d, options);
  options.close_loops = false;
  const gen::CollisionScene open = gen::build_collision_scene(d, options);
  auto closed_pairs = by_names(closed), open_pairs = by_names(open);
  const std::pair<std::string, std::string> crank_rocker{"crank", "rocker"};
  ASSERT_TRUE(closed_pairs.count(crank_rocker));
  EXPECT_EQ(open_pairs[crank_rocker].verdict, PairVerdict::Kept);
  EXPECT_LT(open_pairs[crank_rocker].min_distance, 0.0);  // the open rocker passes through the crank
  EXPECT_EQ(closed_pairs[crank_rocker].verdict, PairVerdict::NeverClose);
  EXPECT_GT(closed_pairs[crank_rocker].min_distance, options.margin);
  EXPECT_EQ(closed.sampling.used(), 2000);  // a crank-rocker closes at every crank angle
  EXPECT_FALSE(open.sampling.loops);
  EXPECT_EQ(closed.model.pairs.size() + 1, open.model.pairs.size());
}

}  // namespace
}  // namespace mbgen::test

namespace mbgen::test {
namespace {

TEST(CollisionSceneLola, NominalPoseHasNoOverlappingKeptPair) {
  // The pairs the generator keeps for Lola (the scene's own options: margin, prune_samples), at
  // the assembled nominal pose: none may overlap (the hip drive blocks did, by 4 cm, when their
  // collision capsules reached past the mid-plane; robots/lola/README.md).
  const gen::Description d = load_lola();
  const gen::CollisionScene scene = gen::build_collision_scene(d, gen::collision_scene_options(d));
  ASSERT_GT(scene.model.pairs.size(), 100u);
  VecX<double> q = d.assembly.q;
  q.head<7>() << 0, 0, 0, 0, 0, 0, 1;
  EXPECT_LT(closure_error(d.model, q), 1e-10);
  Data<double> data(d.model);
  forward_kinematics<double>(d.model, data, q);
  double closest = std::numeric_limits<double>::infinity();
  std::string closest_pair;
  for (const auto& [i, j] : scene.model.pairs) {
    const collision::Compound& a = scene.model.compounds[static_cast<std::size_t>(i)];
    const collision::Compound& b = scene.model.compounds[static_cast<std::size_t>(j)];
    const double dist = collision::compound_distance<double>(a, data.X_WB[a.body], b, data.X_WB[b.body]).result.distance;
    EXPECT_GT(dist, 0.0) << a.name << " - " << b.name;
    if (dist < closest) {
      closest = dist;
      closest_pair = a.name + " - " + b.name;
    }
  }
  std::printf("closest kept pair at the nominal pose: %s at %.4f m\n", closest_pair.c_str(), closest);
  // The hip drive blocks: 0.18 m apart, spheres of 0.082 m.
  auto pairs = by_names(scene);
  const gen::PairDecision& hips = pairs[{"hip_roll_link_l", "hip_roll_link_r"}];
  EXPECT_EQ(hips.verdict, PairVerdict::Kept);  // they can come close (hip roll and yaw)
  const collision::Compound& l = scene.model.compounds[static_cast<std::size_t>(hips.first)];
  const collision::Compound& r = scene.model.compounds[static_cast<std::size_t>(hips.second)];
  EXPECT_NEAR(collision::compound_distance<double>(l, data.X_WB[l.body], r, data.X_WB[r.body]).result.distance,
              0.18 - 2 * 0.082, 1e-12);
}

}  // namespace
}  // namespace mbgen::test
