#pragma once
// The TALOS differential-IK scenario shared by tests/test_differential_ik.cpp and the
// ik_step/talos benchmark (bench_control.cpp): a regular bent-knee pose, the feet + CoM + torso
// task stack, and targets a little away from the pose. One copy, so the benchmark times what
// the tests check.
#include <random>
#include <string>
#include <vector>

#include "mbgen/algorithm/center_of_mass.hpp"
#include "mbgen/algorithm/configuration.hpp"
#include "mbgen/algorithm/kinematics.hpp"
#include "mbgen/control/differential_ik.hpp"

namespace mbgen::scenario {

/// Bent knees (-0.4, 0.8, -0.4 rad) and random small joint angles (+-0.2 rad, seeded): a regular
/// pose for the feet tasks.
inline VecX<double> talos_pose(const Model& model, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  VecX<double> q = neutral_configuration<double>(model);
  for (int j = 2; j < model.num_joints(); ++j) q[model.joint(JointIndex(j)).idx_q] = u(rng);
  for (const char* side : {"left", "right"}) {
    q[model.joint(*model.find_joint(std::string("leg_") + side + "_3_joint")).idx_q] = -0.4;
    q[model.joint(*model.find_joint(std::string("leg_") + side + "_4_joint")).idx_q] = 0.8;
    q[model.joint(*model.find_joint(std::string("leg_") + side + "_5_joint")).idx_q] = -0.4;
  }
  return q;
}

/// Both feet (pose), the centre of mass and the torso orientation, all with the same gain [1/s].
inline std::vector<control::TaskSpec> talos_tasks(double gain = 10.0) {
  return {{"left_foot", control::TaskKind::FramePose, "left_sole_link", gain},
          {"right_foot", control::TaskKind::FramePose, "right_sole_link", gain},
          {"com", control::TaskKind::CenterOfMass, "", gain},
          {"torso", control::TaskKind::FrameOrientation, "torso_2_link", gain}};
}

/// Targets near the pose q (5 cm, 0.1 rad away, seeded) with feed-forward velocities.
inline void set_targets_near(control::DifferentialIk<double>& ik, const Model& model, const VecX<double>& q, unsigned seed) {
  std::mt19937_64 rng(seed);
  Data<double> data(model);
  center_of_mass<double>(model, data, q);
  update_frame_placements<double>(model, data);
  for (int i = 0; i < ik.num_tasks(); ++i) {
    const control::Task& t = ik.task(i);
    control::TaskTarget<double>& target = ik.target(i);
    const Vec3<double> offset = random_vector<double>(3, rng, 0.05);
    if (t.spec.kind == control::TaskKind::CenterOfMass) {
      target.position = data.com + offset;
    } else {
      target.position = data.X_WF[t.frame].translation + offset;
      target.rotation = Eigen::AngleAxisd(0.1, Vec3<double>(random_vector<double>(3, rng)).normalized()).toRotationMatrix() *
                        data.X_WF[t.frame].rotation;
    }
    target.velocity = random_vector<double>(6, rng, 0.2);
  }
}

}  // namespace mbgen::scenario
