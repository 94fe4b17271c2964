// Whole-robot self-distances with their Jacobians: `self_distance/<robot>/generic` runs, per call,
// forward kinematics with the world joint Jacobians, the distance of every pair the scene keeps
// (compounds of SSVs, bounding spheres first) and the distance Jacobian rows;
// `self_distance/<robot>/generated` the generated self_distances, which computes the same.
// Robots: the Lola biped (its extras' SSVs and scene: margin, excludes, prune_samples) and
// panda_collision (URDF spheres and cylinders). Both sides use the same pair list: the scene built
// with gen::collision_scene_options(description), as the generator builds it (checked at startup).
//
// The near set on Lola standing: `self_distance_standing/lola/<implementation>` over 64 poses
// around the bent-knee standing pose (joints moved by up to 0.05 rad, loops re-closed):
// `generic` and `generated` compute every pair, `generic_near` and `generated_near` the near set
// at 5 cm (compute_near_distances, the generated self_distances_near: SSV calls for the pairs whose
// bounding spheres are within 5 cm, witnesses and Jacobian rows for the pairs within 5 cm). The
// mean sizes of both sets over the poses are printed at registration. Two thresholds bracket what
// any near set could cost on these poses: `generated_near_floor` (threshold -inf: every pair is
// decided by its bounding spheres, no SSV call, no row: the placement, the Jacobian columns and
// the sphere tests every call pays) and `generated_near_all` (threshold +inf: every pair near,
// with its row). A near set that spent nothing on its far pairs would take the floor plus the
// near pairs' share of (all - floor) (docs/ssv.md: the bound this puts on the full/near ratio).
#include "bench_self_distance.hpp"

#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <utility>

#include "lola.hpp"
#include "lola_ik_scenario.hpp"
#include "mbgen/collision/compound_distance.hpp"
#include "collision/collision_scene.hpp"
#include "model/load_description.hpp"
#include "panda_collision.hpp"

namespace mbgen::bench {

namespace {

struct SceneRobot {
  Robot robot;
  collision::CollisionModel scene;
};

/// The double entry point of a generated robot's self_distances and its pair count.
struct GeneratedSelfDistances {
  void (*self_distances)(const double*, double*, double*, double*, double*);
  int num_pairs;
};

void add_scene_robot(const std::string& name, const std::string& urdf, const std::string& extras, gen::BaseType base,
                     GeneratedSelfDistances generated) {
  static std::vector<std::unique_ptr<SceneRobot>> robots;  // live as long as the benchmarks
  auto r = std::make_unique<SceneRobot>();
  gen::LoadOptions options;
  options.base = base;
  options.pick_up_robot_yaml = false;
  if (!extras.empty()) options.extras_file = extras;
  const gen::Description d = gen::load_description(urdf, options);
  r->scene = gen::build_collision_scene(d, gen::collision_scene_options(d)).model;
  if (static_cast<int>(r->scene.pairs.size()) != generated.num_pairs)
    throw std::runtime_error(name + ": the generated self_distances has another pair list than the generic scene");
  r->robot.name = name;
  r->robot.urdf = urdf;
  r->robot.model = d.model;
  r->robot.pool = make_pool(r->robot.model);
  const Model* model = &r->robot.model;
  const collision::CollisionModel* scene = &r->scene;
  struct Work {
    Work(const Model& m, const collision::CollisionModel& s) : data(m), cd(m, s) {}
    Data<double> data;
    collision::CollisionData<double> cd;
  };
  add_benchmark("self_distance", r->robot, "generic", [model, scene, w = std::make_shared<Work>(*model, *scene)](const Sample& s) {
    compute_joint_jacobians<double>(*model, w->data, s.q);
    collision::compute_distances<double>(*model, w->data, *scene, w->cd);
    collision::compute_distance_jacobians<double>(*model, w->data, *scene, w->cd);
    return w->cd.jacobian.data();
  });
  const int np = generated.num_pairs, nv = model->nv();
  add_benchmark("self_distance", r->robot, "generated",
                [generated, np, out = std::make_shared<std::vector<double>>(static_cast<std::size_t>(np * (10 + nv)))](const Sample& s) {
                  double* distance = out->data();
                  generated.self_distances(s.q.data(), distance, distance + np, distance + 4 * np, distance + 10 * np);
                  return distance;
                });
  robots.push_back(std::move(r));
}

constexpr double kNearThreshold = 0.05;  // m: the "within 5 cm"

/// 64 poses around Lola's bent-knee standing pose: every joint off the base moved by up to 0.05 rad,
/// the loops re-closed (a pose that does not close is the standing pose itself).
std::shared_ptr<const std::vector<Sample>> standing_pool(const gen::Description& d) {
  const Model& model = d.model;
  const VecX<double> standing = scenario::lola_bent_pose(d);
  Data<double> data(model);
  std::mt19937_64 rng(61);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  auto pool = std::make_shared<std::vector<Sample>>();
  for (std::size_t k = 0; k < kPoolSize; ++k) {
    Sample s;
    s.q = standing;
    for (int j = 1; j < model.num_joints(); ++j)
      if (model.joint(JointIndex(j)).type == JointType::Revolute) s.q[model.joint(JointIndex(j)).idx_q] += u(rng);
    if (closure_positions<double>(model, data, s.q).status != ClosureStatus::Converged) s.q = standing;
    pool->push_back(std::move(s));
  }
  return pool;
}

void add_standing_lola() {
  static gen::Description d = scenario::lola_description(MBGEN_SOURCE_DIR);
  static collision::CollisionModel scene = scenario::generated_collision_scene(d);
  const auto pool = standing_pool(d);
  const Model* model = &d.model;
  const collision::CollisionModel* cm = &scene;
  struct Work {
    Work(const Model& m, const collision::CollisionModel& s) : data(m), cd(m, s) {}
    Data<double> data;
    collision::CollisionData<double> cd;
  };
  for (const bool near : {false, true}) {
    add_benchmark<Sample>("self_distance_standing", "lola", near ? "generic_near" : "generic", pool,
                          [model, cm, near, w = std::make_shared<Work>(*model, *cm)](const Sample& s) {
                            compute_joint_jacobians<double>(*model, w->data, s.q);
                            if (near) {
                              collision::compute_near_distances<double>(*model, w->data, *cm, kNearThreshold, w->cd);
                            } else {
                              collision::compute_distances<double>(*model, w->data, *cm, w->cd);
                            }
                            collision::compute_distance_jacobians<double>(*model, w->data, *cm, w->cd);
                            return w->cd.jacobian.data();
                          });
  }
  const int np = lola::num_distance_pairs, nv = lola::nv;
  struct Out {
    std::vector<double> values;
    std::vector<int> near;
  };
  auto out = std::make_shared<Out>(Out{std::vector<double>(static_cast<std::size_t>(np * (10 + nv))), std::vector<int>(np)});
  add_benchmark<Sample>("self_distance_standing", "lola", "generated", pool, [np, out](const Sample& s) {
    double* distance = out->values.data();
    lola::self_distances(s.q.data(), distance, distance + np, distance + 4 * np, distance + 10 * np);
    return distance;
  });
  const double infinity = std::numeric_limits<double>::infinity();
  for (const auto& [name, threshold] : {std::pair<const char*, double>{"generated_near", kNearThreshold},
                                        {"generated_near_floor", -infinity},
                                        {"generated_near_all", infinity}})
    add_benchmark<Sample>("self_distance_standing", "lola", name, pool, [np, out, threshold = threshold](const Sample& s) {
      double* distance = out->values.data();
      int num_near = 0;
      lola::self_distances_near(s.q.data(), threshold, distance, out->near.data(), &num_near, distance + np, distance + 4 * np,
                                distance + 10 * np);
      return distance;
    });
  // The mean near-set sizes over the pool, printed once at registration (a property of the poses).
  double near_total = 0, spheres_total = 0;
  Data<double> data(*model);
  for (const Sample& s : *pool) {
    int num_near = 0;
    double* distance = out->values.data();
    lola::self_distances_near(s.q.data(), kNearThreshold, distance, out->near.data(), &num_near, distance + np, distance + 4 * np,
                              distance + 10 * np);
    near_total += num_near;
    forward_kinematics<double>(*model, data, s.q);
    for (const collision::CollisionPair& p : cm->pairs) {
      const collision::Compound& a = cm->compounds[static_cast<std::size_t>(p.first)];
      const collision::Compound& b = cm->compounds[static_cast<std::size_t>(p.second)];
      if (collision::bounding_distance<double>(a, data.X_WB[a.body], b, data.X_WB[b.body]) < kNearThreshold) spheres_total += 1;
    }
  }
  const double poses = static_cast<double>(kPoolSize);
  std::printf("self_distance_standing/lola: of %d pairs, %.1f have their bounding spheres and %.1f themselves within %.0f cm (mean over %zu "
              "poses)\n",
              np, spheres_total / poses, near_total / poses, 100 * kNearThreshold, kPoolSize);
}

}  // namespace

void add_self_distance_benchmarks() {
  add_standing_lola();
  add_scene_robot("lola", std::string(MBGEN_SOURCE_DIR) + "/robots/lola/lola.urdf", std::string(MBGEN_SOURCE_DIR) + "/robots/lola/lola.yaml",
                  gen::BaseType::Floating, {&lola::self_distances, lola::num_distance_pairs});
  add_scene_robot("panda_collision", std::string(MBGEN_SHARED_ROBOTS) + "/panda/panda_collision.urdf", "", gen::BaseType::Fixed,
                  {&panda_collision::self_distances, panda_collision::num_distance_pairs});
}

}  // namespace mbgen::bench
