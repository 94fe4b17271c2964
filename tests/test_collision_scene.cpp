// The collision scene (generator/src/collision_scene.cpp): compounds per body and the pruned pair
// list, on tests/data/collision_arm.urdf whose answers follow from its geometry (see the file's
// comment: adjacent, never close with a closed-form distance range, always overlapping, kept),
// and on the Lola biped's scene (excluded pairs, determinism).
#include <gtest/gtest.h>

#include <cstring>
#include <map>

#include "mbgen/gen/collision_scene.hpp"
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

}  // namespace
}  // namespace mbgen::test
