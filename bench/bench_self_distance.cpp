// Whole-robot self-distances with their Jacobians: `self_distance/<robot>/generic` runs, per call,
// forward kinematics with the world joint Jacobians, the distance of every pair the scene keeps
// (compounds of SSVs, bounding spheres first) and the distance Jacobian rows;
// `self_distance/<robot>/generated` the generated self_distances, which computes the same.
// Robots: the Lola biped (its extras' SSVs and scene: margin, excludes, prune_samples) and
// panda_collision (URDF spheres and cylinders). Both sides use the same pair list: the scene built
// with gen::collision_scene_options(description), as the generator builds it (checked at startup).
#include "bench_self_distance.hpp"

#include <memory>

#include <stdexcept>

#include "lola.hpp"
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

}  // namespace

void add_self_distance_benchmarks() {
  add_scene_robot("lola", std::string(MBGEN_SOURCE_DIR) + "/robots/lola/lola.urdf", std::string(MBGEN_SOURCE_DIR) + "/robots/lola/lola.yaml",
                  gen::BaseType::Floating, {&lola::self_distances, lola::num_distance_pairs});
  add_scene_robot("panda_collision", std::string(MBGEN_SHARED_ROBOTS) + "/panda/panda_collision.urdf", "", gen::BaseType::Fixed,
                  {&panda_collision::self_distances, panda_collision::num_distance_pairs});
}

}  // namespace mbgen::bench
