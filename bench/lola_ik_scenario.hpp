#pragma once
// Lola's differential-IK scenario, shared by tests/test_differential_ik.cpp and the ik_step/lola
// benchmarks (bench_control.cpp): the full controller step the thesis runs, with the feet (pose),
// the centre of mass and the torso orientation as primary tasks, self-collision avoidance over
// the scene's pairs and angular-momentum tracking in the null space, on a bent-knee pose with
// the loops closed. The collision scene is the one the generator emits (its seeded pruning), so
// the generic and the generated controllers see the same pairs in the same order.
#include <string>
#include <vector>

#include "collision/collision_scene.hpp"
#include "mbgen/algorithm/closure_positions.hpp"
#include "mbgen/control/differential_ik.hpp"
#include "model/load_description.hpp"

namespace mbgen::scenario {

inline gen::Description lola_description(const std::string& source_dir) {
  gen::LoadOptions options;
  options.base = gen::BaseType::Floating;
  options.pick_up_robot_yaml = false;
  options.extras_file = source_dir + "/robots/lola/lola.yaml";
  return gen::load_description(source_dir + "/robots/lola/lola.urdf", options);
}

inline std::vector<control::TaskSpec> lola_tasks(double gain = 10.0) {
  return {{"left_foot", control::TaskKind::FramePose, "foot_l", gain},
          {"right_foot", control::TaskKind::FramePose, "foot_r", gain},
          {"com", control::TaskKind::CenterOfMass, "", gain},
          {"torso", control::TaskKind::FrameOrientation, "torso", gain}};
}

/// The generator's collision scene of d (the pairs and order of the generated self_distances).
inline collision::CollisionModel generated_collision_scene(const gen::Description& d) {
  return gen::build_collision_scene(d, gen::collision_scene_options(d)).model;
}

/// Bent knees (knee actuators at `knee` of their travel, loops closed): the straight legs of the
/// assembled pose are singular for the feet tasks (sigma_min 1.5e-3).
inline VecX<double> lola_bent_pose(const gen::Description& d, double knee = 0.3) {
  const Model& model = d.model;
  VecX<double> q = d.assembly.q;
  for (const char* name : {"knee_act_l", "knee_act_r"}) {
    const Joint& joint = model.joint(*model.find_joint(name));
    q[joint.idx_q] = joint.lower + knee * (joint.upper - joint.lower);
  }
  Data<double> data(model);
  if (closure_positions<double>(model, data, q).status != ClosureStatus::Converged)
    throw std::runtime_error("lola_bent_pose: the loops do not close at the bent pose");
  return q;
}

/// The controller's options: collision avoidance (activation 8 cm) and angular momentum tracking.
inline control::DifferentialIkOptions lola_ik_options() {
  control::DifferentialIkOptions options;
  options.collision_avoidance = true;
  options.collision = {0.08, 100.0};
  options.angular_momentum.enabled = true;
  return options;
}

}  // namespace mbgen::scenario
