// Compound distances and distance Jacobians (runtime/include/mbgen/collision/compound_distance.hpp):
//  - bounding-sphere skipping changes nothing: the distance equals the minimum over every shape
//    pair (exactly: the winner is computed by the same code);
//  - the distance Jacobian n^T (J_p2 - J_p1) against central differences of the distance, away
//    from feature switches (where the closest shapes or features change, d is not differentiable:
//    such samples are recognised by one-sided differences that disagree, and skipped);
//    tolerance 1e-6 relative to max(1, |J|) with h = 1e-6 (central differences: O(h^2) truncation
//    and eps/h round-off, both below 1e-8 here);
//  - continuity of d along a path that crosses switches: |d(q_k+1) - d(q_k)| <= 2 L |dq| with
//    L the largest Jacobian norm seen (a jump would show as a difference of order the shapes' size);
//  - the near set: equal to the full computation below its threshold, a lower bound above it;
//  - no allocation.
// Robots: panda_collision (URDF cylinders and spheres -> capsules, points), iiwa14 (cylinders)
// and the Lola biped (its extras' SSVs, including a floating base).
#include <gtest/gtest.h>

#include <random>

#include "malloc_guard.hpp"
#include "mbgen/collision/compound_distance.hpp"
#include "collision/collision_scene.hpp"
#include "model/load_description.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

using namespace mbgen::collision;

struct SceneCase {
  std::string name, urdf, extras;
  gen::BaseType base;
};
void PrintTo(const SceneCase& c, std::ostream* os) { *os << c.name; }

class CompoundDistanceTest : public ::testing::TestWithParam<SceneCase> {
 protected:
  void SetUp() override {
    gen::LoadOptions options;
    options.base = GetParam().base;
    options.pick_up_robot_yaml = false;
    if (!GetParam().extras.empty()) options.extras_file = GetParam().extras;
    description_ = gen::load_description(GetParam().urdf, options);
    gen::CollisionSceneOptions scene_options;
    scene_options.samples = 0;  // every non-adjacent pair
    scene_ = gen::build_collision_scene(description_, scene_options).model;
    ASSERT_FALSE(scene_.pairs.empty());
  }
  const Model& model() const { return description_.model; }
  gen::Description description_;
  CollisionModel scene_;
};

TEST_P(CompoundDistanceTest, BoundingSpheresChangeNothing) {
  Data<double> data(model());
  CollisionData<double> cd(model(), scene_);
  std::mt19937_64 rng(31);
  int skipped = 0, total = 0;
  for (int trial = 0; trial < 50; ++trial) {
    forward_kinematics<double>(model(), data, random_configuration<double>(model(), rng));
    compute_distances<double>(model(), data, scene_, cd);
    for (std::size_t k = 0; k < scene_.pairs.size(); ++k) {
      const Compound& a = scene_.compounds[static_cast<std::size_t>(scene_.pairs[k].first)];
      const Compound& b = scene_.compounds[static_cast<std::size_t>(scene_.pairs[k].second)];
      double brute = std::numeric_limits<double>::infinity();
      for (const Shape& sa : a.shapes)
        for (const Shape& sb : b.shapes)
          brute = std::min(brute, collision::detail::shape_distance<double>(sa, data.X_WB[a.body], sb, data.X_WB[b.body]).distance);
      ASSERT_EQ(cd.distances[k].result.distance, brute) << a.name << " - " << b.name;
      skipped += static_cast<int>(a.shapes.size() * b.shapes.size()) - cd.distances[k].shape_pairs_computed;
      total += static_cast<int>(a.shapes.size() * b.shapes.size());
    }
  }
  std::printf("  %s: bounding spheres skipped %d of %d shape pairs\n", GetParam().name.c_str(), skipped, total);
}

TEST_P(CompoundDistanceTest, JacobianMatchesFiniteDifferences) {
  Data<double> data(model());
  CollisionData<double> cd(model(), scene_), cd_plus(model(), scene_), cd_minus(model(), scene_);
  std::mt19937_64 rng(37);
  const double h = 1e-6;
  double worst = 0;
  int checked = 0, skipped = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const VecX<double> q = random_configuration<double>(model(), rng);
    compute_joint_jacobians<double>(model(), data, q);
    compute_distances<double>(model(), data, scene_, cd);
    compute_distance_jacobians<double>(model(), data, scene_, cd);
    for (int c = 0; c < model().nv(); ++c) {
      VecX<double> e = VecX<double>::Zero(model().nv());
      e[c] = 1.0;
      const CentralPair qs = central_pair(model(), q, e, h);
      forward_kinematics<double>(model(), data, qs.plus);
      compute_distances<double>(model(), data, scene_, cd_plus);
      forward_kinematics<double>(model(), data, qs.minus);
      compute_distances<double>(model(), data, scene_, cd_minus);
      for (std::size_t k = 0; k < scene_.pairs.size(); ++k) {
        const double d0 = cd.distances[k].result.distance;
        const double forward = (cd_plus.distances[k].result.distance - d0) / h;
        const double backward = (d0 - cd_minus.distances[k].result.distance) / h;
        const double analytic = cd.jacobian(static_cast<int>(k), c);
        const double scale = std::max(1.0, cd.jacobian.row(static_cast<int>(k)).norm());
        if (std::abs(forward - backward) > 1e-4 * scale || cd_plus.distances[k].shape_first != cd.distances[k].shape_first ||
            cd_plus.distances[k].shape_second != cd.distances[k].shape_second) {
          ++skipped;  // a feature switch within +-h
          continue;
        }
        worst = std::max(worst, std::abs(0.5 * (forward + backward) - analytic) / scale);
        ++checked;
      }
    }
  }
  std::printf("  %s: distance Jacobian worst error %.2e over %d entries (%d at switches skipped)\n", GetParam().name.c_str(), worst,
              checked, skipped);
  EXPECT_GT(checked, 10 * skipped);  // switches are rare: the check really runs
  EXPECT_LT(worst, 1e-6);
}

TEST_P(CompoundDistanceTest, DistanceIsContinuousAcrossSwitches) {
  Data<double> data(model());
  CollisionData<double> cd(model(), scene_);
  std::mt19937_64 rng(41);
  const VecX<double> q0 = random_configuration<double>(model(), rng);
  const VecX<double> direction = random_vector<double>(model().nv(), rng).normalized();
  const int steps = 2000;
  const double step = 2.0 / steps;  // 2 rad (or m) of travel
  std::vector<double> previous;
  double worst_ratio = 0, lipschitz = 0;
  int switches = 0;
  std::vector<int> previous_shapes;
  for (int s = 0; s <= steps; ++s) {
    VecX<double> q(model().nq());
    integrate<double>(model(), q0, direction * (s * step), q);
    compute_joint_jacobians<double>(model(), data, q);
    compute_distances<double>(model(), data, scene_, cd);
    compute_distance_jacobians<double>(model(), data, scene_, cd);
    for (int k = 0; k < cd.jacobian.rows(); ++k) lipschitz = std::max(lipschitz, cd.jacobian.row(k).norm());
    if (!previous.empty())
      for (std::size_t k = 0; k < scene_.pairs.size(); ++k) {
        worst_ratio = std::max(worst_ratio, std::abs(cd.distances[k].result.distance - previous[k]) / step);
        const int shapes = cd.distances[k].shape_first * 1000 + cd.distances[k].shape_second;
        switches += shapes != previous_shapes[k];
      }
    previous.clear();
    previous_shapes.clear();
    for (const auto& d : cd.distances) {
      previous.push_back(d.result.distance);
      previous_shapes.push_back(d.shape_first * 1000 + d.shape_second);
    }
  }
  std::printf("  %s: |delta d| / |delta q| <= %.3g (Jacobian norms <= %.3g), %d switches of closest shapes crossed\n",
              GetParam().name.c_str(), worst_ratio, lipschitz, switches);
  EXPECT_LE(worst_ratio, 2.0 * lipschitz);
}

// The near set (compute_near_distances) over 1e5 random poses, each with its own threshold drawn
// from overlap (-5 cm) to far (40 cm): every near pair has exactly the full computation's result
// and Jacobian row (the same code) and is closer than the threshold; every far pair's reported
// lower bound is at least the threshold and at most its computed distance (exactly: the bound
// allows for the rounding of both, sphere_lower_bound), and its row is zero. So a pair closer than the threshold is
// never missed, and no pair at or beyond it gets a row.
TEST_P(CompoundDistanceTest, NearSetEqualsFullBelowTheThresholdAndBoundsTheRest) {
  Data<double> data(model());
  CollisionData<double> full(model(), scene_), near(model(), scene_);
  std::mt19937_64 rng(53);
  std::uniform_real_distribution<double> threshold_of(-0.05, 0.4);
  long near_pairs = 0, far_pairs = 0;
  long shapes_full = 0, shapes_near = 0;  // shape pairs computed where the near set computes any
  double excess = -1e300;
  const int poses = 100000;
  for (int trial = 0; trial < poses; ++trial) {
    const VecX<double> q = random_configuration<double>(model(), rng);
    const double threshold = threshold_of(rng);
    const bool jacobians = trial % 100 == 0;  // the rows on 1 % of the poses (the distances on all)
    if (jacobians) {
      compute_joint_jacobians<double>(model(), data, q);
    } else {
      forward_kinematics<double>(model(), data, q);
    }
    compute_distances<double>(model(), data, scene_, full);
    compute_near_distances<double>(model(), data, scene_, threshold, near);
    if (jacobians) {
      compute_distance_jacobians<double>(model(), data, scene_, full);
      compute_distance_jacobians<double>(model(), data, scene_, near);
    }
    int i = 0;
    for (std::size_t k = 0; k < scene_.pairs.size(); ++k) {
      const double d = full.distances[k].result.distance, reported = near.distances[k].result.distance;
      if (near.distances[k].shape_pairs_computed > 0) {
        shapes_full += full.distances[k].shape_pairs_computed;
        shapes_near += near.distances[k].shape_pairs_computed;
      }
      if (i < near.num_near && near.near[static_cast<std::size_t>(i)] == static_cast<int>(k)) {
        ++i;
        ++near_pairs;
        ASSERT_EQ(reported, d) << "pair " << k;
        ASSERT_LT(d, threshold) << "pair " << k;
        ASSERT_EQ(near.distances[k].shape_first, full.distances[k].shape_first);
        if (jacobians) {
          ASSERT_TRUE(near.jacobian.row(static_cast<int>(k)) == full.jacobian.row(static_cast<int>(k))) << "pair " << k;
        }
      } else {
        ++far_pairs;
        ASSERT_GE(reported, threshold) << "pair " << k;
        excess = std::max(excess, reported - d);
        if (jacobians) {
          ASSERT_TRUE(near.jacobian.row(static_cast<int>(k)).isZero(0.0)) << "pair " << k;
        }
      }
    }
    ASSERT_EQ(i, near.num_near) << "the near list is not ascending";
  }
  EXPECT_LE(excess, 0.0) << "a far pair's lower bound exceeds its distance";
  EXPECT_GT(near_pairs, 0);
  EXPECT_GT(far_pairs, 0);
  // The threshold is the shape pairs' limit too (ClosestShapes): it spares SSV calls wherever a
  // pair has more than one shape pair (iiwa14's links are one capsule each: nothing to spare).
  bool several = false;
  for (const collision::CollisionPair& p : scene_.pairs)
    several = several || scene_.compounds[static_cast<std::size_t>(p.first)].shapes.size() *
                                 scene_.compounds[static_cast<std::size_t>(p.second)].shapes.size() >
                             1;
  if (several) {
    EXPECT_LT(shapes_near, shapes_full);
  } else {
    EXPECT_EQ(shapes_near, shapes_full);
  }
  std::printf("  %s: %d poses, %ld near and %ld far pairs; largest lower bound - distance %.3g m; shape pairs computed %ld "
              "(full set: %ld)\n",
              GetParam().name.c_str(), poses, near_pairs, far_pairs, excess, shapes_near, shapes_full);
}

TEST_P(CompoundDistanceTest, DoesNotAllocate) {
  Data<double> data(model());
  CollisionData<double> cd(model(), scene_);
  std::mt19937_64 rng(43);
  const VecX<double> q = random_configuration<double>(model(), rng);
  {
    MallocGuard guard;
    compute_joint_jacobians<double>(model(), data, q);
    compute_distances<double>(model(), data, scene_, cd);
    compute_distance_jacobians<double>(model(), data, scene_, cd);
    compute_near_distances<double>(model(), data, scene_, 0.05, cd);
    compute_distance_jacobians<double>(model(), data, scene_, cd);
    EXPECT_EQ(guard.count(), 0u);
  }
  EXPECT_TRUE(cd.jacobian.allFinite());
}

INSTANTIATE_TEST_SUITE_P(
    Robots, CompoundDistanceTest,
    ::testing::Values(SceneCase{"panda_collision", shared_robot("panda/panda_collision.urdf"), "", gen::BaseType::Fixed},
                      SceneCase{"iiwa14", shared_robot("iiwa14/iiwa14_primitive_collision.urdf"), "", gen::BaseType::Fixed},
                      SceneCase{"lola", MBGEN_SOURCE_DIR "/robots/lola/lola.urdf", MBGEN_SOURCE_DIR "/robots/lola/lola.yaml",
                                gen::BaseType::Floating}),
    [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace mbgen::test
