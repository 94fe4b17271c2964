// Whole-robot self-distances with their Jacobians: `self_distance/<robot>/generic` runs, per call,
// forward kinematics with the world joint Jacobians, the distance of every pair the scene keeps
// (compounds of SSVs, bounding spheres first) and the distance Jacobian rows. Robots: the Lola
// biped (its extras' SSVs and scene: margin, excludes; pairs pruned with 2000 samples) and
// panda_collision (URDF spheres and cylinders, every non-adjacent pair kept).
#include "bench_self_distance.hpp"

#include <memory>

#include "mbgen/collision/compound_distance.hpp"
#include "mbgen/gen/collision_scene.hpp"

namespace mbgen::bench {

namespace {

struct SceneRobot {
  Robot robot;
  collision::CollisionModel scene;
};

void add_scene_robot(const std::string& name, const std::string& urdf, const std::string& extras, gen::BaseType base,
                     int prune_samples) {
  static std::vector<std::unique_ptr<SceneRobot>> robots;  // live as long as the benchmarks
  auto r = std::make_unique<SceneRobot>();
  gen::LoadOptions options;
  options.base = base;
  options.pick_up_robot_yaml = false;
  if (!extras.empty()) options.extras_file = extras;
  const gen::Description d = gen::load_description(urdf, options);
  gen::CollisionSceneOptions scene_options = gen::collision_scene_options(d);
  scene_options.samples = prune_samples;
  r->scene = gen::build_collision_scene(d, scene_options).model;
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
  robots.push_back(std::move(r));
}

}  // namespace

void add_self_distance_benchmarks() {
  add_scene_robot("lola", std::string(MBGEN_SOURCE_DIR) + "/robots/lola/lola.urdf", std::string(MBGEN_SOURCE_DIR) + "/robots/lola/lola.yaml",
                  gen::BaseType::Floating, 2000);
  add_scene_robot("panda_collision", std::string(MBGEN_SHARED_ROBOTS) + "/panda/panda_collision.urdf", "", gen::BaseType::Fixed, 0);
}

}  // namespace mbgen::bench
