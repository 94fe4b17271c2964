// Generated self_distances equals the generic compute_distances + compute_distance_jacobians on
// the same scene (gen::build_collision_scene with the description's options, as the generator
// builds it). Compiled once and linked into every test_generated_<robot>, as test_generated.cpp.
//
// Tolerances.
// double: 1e-12 (m for distances and witnesses, absolute for unit normals, relative to the
//   largest Jacobian entry for rows). The generated code places the points and builds the
//   Jacobian columns with the traced generic operations minus exact ones, then calls the same
//   SSV primitives in the same order, so the two differ by round-off in the placed points only.
// float: against the double generic. Placed points carry the forward-kinematics error of
//   test_generated.cpp's bound, delta ~ c * d * u * L with depth d <= 10, u = 6e-8, reach L <= 3 m
//   (base within 1 m), plus the primitives' own 16 u * scale (docs/ssv.md): delta <= 64 u * 3 m
//   ~ 1e-5 m. The distance is 1-Lipschitz in the points: bound 1e-5 m for every pair (measured on
//   Lola: 4e-7). A normal is a direction between points known to delta, so its error grows as
//   2 delta / core distance: normals and Jacobian rows (relative) are compared only where the cores
//   are more than 1 cm apart, bound 2e-3 (measured 3e-4 / 2e-4). Witness points add the radius
//   (<= 0.2 m) times the normal error (4e-4) and, for near-parallel segments, the sliding of their
//   closest points by delta / sin(angle): bound 1e-3 m where the cores are 1 cm apart (allows
//   angles down to ~1e-2 rad; measured 1.4e-4), and everywhere the consistency
//   |point2 - point1 - distance * normal| <= 1e-5 m.
#include <gtest/gtest.h>

#include <random>

#include "generated_robot.hpp"
#include "malloc_guard.hpp"
#include "mbgen/collision/compound_distance.hpp"
#include "collision/collision_scene.hpp"
#include "model/load_description.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

class GeneratedSelfDistances : public ::testing::Test {
 protected:
  GeneratedSelfDistances() : description(load()), model(description.model), scene(make_scene(description)) {}

  static gen::Description load() {
    gen::LoadOptions options;
    const generated::Robot& robot = generated::robot();
    options.base = robot.load_floating ? gen::BaseType::Floating : gen::BaseType::Fixed;
    if (std::string(robot.extras).size() > 0) options.extras_file = robot.extras;
    return gen::load_description(robot.description, options);
  }
  static collision::CollisionModel make_scene(const gen::Description& d) {
    return gen::build_collision_scene(d, gen::collision_scene_options(d)).model;
  }

  struct Worst {
    double distance = 0, normal = 0, witness = 0, jacobian = 0, consistency = 0;
    int compared_directions = 0;
    int not_unique = 0;  ///< pairs whose witnesses were not compared (witness_not_unique)
  };

  /// Whether the pair's witness points are not unique, so that round-off in the placed points
  /// may legitimately move them: the closest shapes are two segments parallel to within 1e-6 rad
  /// (any pair along their overlap is closest; the primitives pick one by a rule on rounding-level
  /// cross products, docs/ssv.md), or another shape pair is as close to within 1e-9 m (panda's
  /// fingers: parallel capsules with spheres along them, by construction). Distance, normal and
  /// Jacobian are compared there too; witnesses are not.
  bool witness_not_unique(const Data<double>& data, const collision::CompoundDistance<double>& d,
                          const collision::CollisionPair& pair) const {
    const collision::Compound& ca = scene.compounds[static_cast<std::size_t>(pair.first)];
    const collision::Compound& cb = scene.compounds[static_cast<std::size_t>(pair.second)];
    const SE3<double>& Xa = data.X_WB[ca.body];
    const SE3<double>& Xb = data.X_WB[cb.body];
    for (std::size_t i = 0; i < ca.shapes.size(); ++i)
      for (std::size_t j = 0; j < cb.shapes.size(); ++j) {
        if (static_cast<int>(i) == d.shape_first && static_cast<int>(j) == d.shape_second) continue;
        if (collision::detail::shape_distance<double>(ca.shapes[i], Xa, cb.shapes[j], Xb).distance <= d.result.distance + 1e-9)
          return true;
      }
    const collision::Shape& a = ca.shapes[static_cast<std::size_t>(d.shape_first)];
    const collision::Shape& b = cb.shapes[static_cast<std::size_t>(d.shape_second)];
    if (a.kind != collision::Shape::Kind::Line || b.kind != collision::Shape::Kind::Line) return false;
    const Vec3<double> da = Xa.rotation * (a.points[1] - a.points[0]);
    const Vec3<double> db = Xb.rotation * (b.points[1] - b.points[0]);
    return da.cross(db).norm() <= 1e-6 * da.norm() * db.norm();
  }

  template <typename T> Worst compare(int trials, double min_core_distance) {
    std::mt19937_64 rng(7);
    const int np = robot.num_distance_pairs, nv = model.nv();
    std::vector<T> distance(np), normal(3 * np), witness(6 * np), jacobian(np * nv);
    Data<double> data(model);
    collision::CollisionData<double> cd(model, scene);
    Worst w;
    for (int trial = 0; trial < trials; ++trial) {
      const VecX<double> q = random_configuration<double>(model, rng);
      compute_joint_jacobians<double>(model, data, q);
      collision::compute_distances<double>(model, data, scene, cd);
      collision::compute_distance_jacobians<double>(model, data, scene, cd);
      std::vector<T> qt(static_cast<std::size_t>(q.size()));
      for (int i = 0; i < q.size(); ++i) qt[static_cast<std::size_t>(i)] = static_cast<T>(q[i]);
      generated::self_distances(qt.data(), distance.data(), normal.data(), witness.data(), jacobian.data());
      const double jscale = std::max(1.0, cd.jacobian.cwiseAbs().maxCoeff());
      for (int k = 0; k < np; ++k) {
        const collision::SsvDistance<double>& r = cd.distances[static_cast<std::size_t>(k)].result;
        w.distance = std::max(w.distance, std::abs(static_cast<double>(distance[k]) - r.distance));
        for (int i = 0; i < 3; ++i)
          w.consistency = std::max(w.consistency, std::abs(static_cast<double>(witness[6 * k + 3 + i]) - static_cast<double>(witness[6 * k + i]) -
                                                           static_cast<double>(distance[k]) * static_cast<double>(normal[3 * k + i])));
        if (r.core_distance <= min_core_distance) continue;
        ++w.compared_directions;
        if (witness_not_unique(data, cd.distances[static_cast<std::size_t>(k)], scene.pairs[static_cast<std::size_t>(k)])) {
          ++w.not_unique;
          continue;
        }
        for (int i = 0; i < 3; ++i) {
          w.witness = std::max(w.witness, std::abs(static_cast<double>(witness[6 * k + i]) - r.point1[i]));
          w.witness = std::max(w.witness, std::abs(static_cast<double>(witness[6 * k + 3 + i]) - r.point2[i]));
        }
        for (int i = 0; i < 3; ++i) w.normal = std::max(w.normal, std::abs(static_cast<double>(normal[3 * k + i]) - r.normal[i]));
        for (int c = 0; c < nv; ++c)
          w.jacobian = std::max(w.jacobian, std::abs(static_cast<double>(jacobian[k * nv + c]) - cd.jacobian(k, c)) / jscale);
      }
    }
    return w;
  }

  const generated::Robot& robot = generated::robot();
  gen::Description description;
  const Model& model;
  collision::CollisionModel scene;
};

TEST_F(GeneratedSelfDistances, PairsAreTheScenesKeptPairs) {
  ASSERT_EQ(robot.num_distance_pairs, static_cast<int>(scene.pairs.size()));
  for (std::size_t k = 0; k < scene.pairs.size(); ++k) {
    EXPECT_EQ(scene.compounds[static_cast<std::size_t>(scene.pairs[k].first)].name, robot.distance_pair_names[k][0]);
    EXPECT_EQ(scene.compounds[static_cast<std::size_t>(scene.pairs[k].second)].name, robot.distance_pair_names[k][1]);
  }
}

TEST_F(GeneratedSelfDistances, DoubleEqualsGeneric) {
  if (robot.num_distance_pairs == 0) GTEST_SKIP() << "the scene keeps no pair";
  const Worst w = compare<double>(200, -1.0);
  EXPECT_LT(w.distance, 1e-12);
  EXPECT_LT(w.witness, 1e-12);
  EXPECT_LT(w.consistency, 1e-12);
  EXPECT_LT(w.normal, 1e-12);
  EXPECT_LT(w.jacobian, 1e-12);
  RecordProperty("distance", std::to_string(w.distance));
  RecordProperty("jacobian", std::to_string(w.jacobian));
  RecordProperty("witness_not_unique", std::to_string(w.not_unique));
}

TEST_F(GeneratedSelfDistances, FloatWithinDerivedBound) {
  if (robot.num_distance_pairs == 0) GTEST_SKIP() << "the scene keeps no pair";
  const Worst w = compare<float>(200, 0.01);
  EXPECT_LT(w.distance, 1e-5);
  EXPECT_LT(w.consistency, 1e-5);
  EXPECT_LT(w.witness, 1e-3);
  EXPECT_GT(w.compared_directions, 0);
  EXPECT_LT(w.normal, 2e-3);
  EXPECT_LT(w.jacobian, 2e-3);
  RecordProperty("distance", std::to_string(w.distance));
  RecordProperty("normal", std::to_string(w.normal));
  RecordProperty("witness", std::to_string(w.witness));
  RecordProperty("jacobian", std::to_string(w.jacobian));
}

/// self_distances_near against self_distances (both generated) at thresholds from overlap to far:
/// a near pair's row is the full function's row bit for bit (the same code on the same placed
/// points); a far pair's distance is a lower bound >= the threshold; rows are compact and ascending.
/// Returns how many near and far pairs were seen.
template <typename T> std::pair<int, int> near_set_against_full(const Model& model, int trials, double* worst_bound_excess) {
  const generated::Robot& robot = generated::robot();
  std::mt19937_64 rng(19);
  const int np = robot.num_distance_pairs, nv = robot.nv;
  std::vector<T> d(np), n(3 * np), w(6 * np), J(np * nv), dn(np), nn(3 * np), wn(6 * np), Jn(np * nv);
  std::vector<int> near(np);
  std::uniform_real_distribution<double> threshold_of(-0.05, 0.4);
  int near_seen = 0, far_seen = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    std::vector<T> qt(static_cast<std::size_t>(q.size()));
    for (int i = 0; i < q.size(); ++i) qt[static_cast<std::size_t>(i)] = static_cast<T>(q[i]);
    generated::self_distances(qt.data(), d.data(), n.data(), w.data(), J.data());
    const T threshold = static_cast<T>(threshold_of(rng));
    int num_near = -1;
    generated::self_distances_near(qt.data(), threshold, dn.data(), near.data(), &num_near, nn.data(), wn.data(), Jn.data());
    EXPECT_GE(num_near, 0);
    int i = 0;
    for (int k = 0; k < np; ++k) {
      if (i < num_near && near[i] == k) {
        EXPECT_EQ(dn[k], d[k]) << "pair " << k;
        EXPECT_LT(d[k], threshold) << "pair " << k;
        for (int c = 0; c < 3; ++c) EXPECT_EQ(nn[3 * i + c], n[3 * k + c]) << "pair " << k;
        for (int c = 0; c < 6; ++c) EXPECT_EQ(wn[6 * i + c], w[6 * k + c]) << "pair " << k;
        for (int c = 0; c < nv; ++c) EXPECT_EQ(Jn[i * nv + c], J[k * nv + c]) << "pair " << k << " column " << c;
        ++i;
        ++near_seen;
      } else {
        EXPECT_GE(dn[k], threshold) << "far pair " << k;
        *worst_bound_excess = std::max(*worst_bound_excess, static_cast<double>(dn[k] - d[k]));
        ++far_seen;
      }
    }
    EXPECT_EQ(i, num_near) << "the near list is not ascending";
  }
  return {near_seen, far_seen};
}

TEST_F(GeneratedSelfDistances, NearSetEqualsFullBelowTheThresholdAndBoundsTheRest) {
  if (robot.num_distance_pairs == 0) GTEST_SKIP() << "the scene keeps no pair";
  double excess = -1e300;
  const auto [near_d, far_d] = near_set_against_full<double>(model, 200, &excess);
  EXPECT_GT(near_d, 0);
  EXPECT_GT(far_d, 0);
  EXPECT_LE(excess, 0.0) << "a far pair's lower bound exceeds its distance";
  double excess_f = -1e300;
  near_set_against_full<float>(model, 50, &excess_f);
  EXPECT_LE(excess_f, 0.0);
  RecordProperty("near", std::to_string(near_d));
  RecordProperty("far", std::to_string(far_d));
}

/// The generated near set picks the pairs the generic compute_near_distances picks, and reports
/// their lower bounds to 1e-12 (bounding spheres: placed the traced way vs Eigen's; a pair within
/// 1e-12 of the threshold may go either way).
TEST_F(GeneratedSelfDistances, NearSetEqualsGeneric) {
  if (robot.num_distance_pairs == 0) GTEST_SKIP() << "the scene keeps no pair";
  std::mt19937_64 rng(23);
  const int np = robot.num_distance_pairs, nv = model.nv();
  std::vector<double> d(np), n(3 * np), w(6 * np), J(np * nv);
  std::vector<int> near(np);
  Data<double> data(model);
  collision::CollisionData<double> cd(model, scene);
  double worst = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const double threshold = 0.002 * (trial % 100);
    compute_joint_jacobians<double>(model, data, q);
    collision::compute_near_distances<double>(model, data, scene, threshold, cd);
    int num_near = 0;
    generated::self_distances_near(q.data(), threshold, d.data(), near.data(), &num_near, n.data(), w.data(), J.data());
    std::vector<bool> generated_near(static_cast<std::size_t>(np), false), generic_near(static_cast<std::size_t>(np), false);
    for (int i = 0; i < num_near; ++i) generated_near[static_cast<std::size_t>(near[i])] = true;
    for (int i = 0; i < cd.num_near; ++i) generic_near[static_cast<std::size_t>(cd.near[static_cast<std::size_t>(i)])] = true;
    for (int k = 0; k < np; ++k) {
      const double generic = cd.distances[static_cast<std::size_t>(k)].result.distance;
      worst = std::max(worst, std::abs(d[k] - generic));
      if (generated_near[static_cast<std::size_t>(k)] != generic_near[static_cast<std::size_t>(k)]) {
        EXPECT_LT(std::abs(d[k] - threshold), 1e-12) << "pair " << k << " near in one, far in the other";
      }
    }
  }
  EXPECT_LT(worst, 1e-12);
  RecordProperty("distance", std::to_string(worst));
}

TEST_F(GeneratedSelfDistances, NoAllocation) {
  std::vector<double> q(robot.nq, 0.1), out(6 * (robot.num_distance_pairs + 1) * robot.nv);
  if (robot.floating_base) q[6] = 1, q[3] = q[4] = q[5] = 0;
  std::vector<int> near(robot.num_distance_pairs + 1);
  int num_near = 0;
  MallocGuard guard;
  generated::self_distances(q.data(), out.data(), out.data(), out.data(), out.data());
  generated::self_distances_near(q.data(), 0.05, out.data(), near.data(), &num_near, out.data(), out.data(), out.data());
  EXPECT_EQ(guard.count(), 0u);
}

}  // namespace
}  // namespace mbgen::test
