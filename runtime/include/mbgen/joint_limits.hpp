#pragma once
// Which joints of a model have a position range, and what it is: a fact of the model (URDF
// <limit>, MJCF range), read by the generator (the generated header's limited_* lists), the
// differential IK (control/joint_limit_potential.hpp).
#include <string>
#include <vector>

#include "mbgen/model.hpp"

namespace mbgen {

/// The range of one 1-DoF joint's coordinate: lower < upper, both finite.
struct JointLimit {
  std::string joint;   ///< for messages
  int q_index = 0;     ///< position coordinate
  int v_index = 0;     ///< velocity coordinate (the gradient's row)
  double lower = 0, upper = 0;
};

/// The limits of the model's bounded 1-DoF joints (revolute with <limit lower upper>, prismatic):
/// what the URDF or MJCF says, ready for JointLimitOptions::limits. Continuous joints, the floating
/// base and fixed joints have none, nor has a joint whose range is empty (URDF's `lower="0"
/// upper="0"`, which urdfdom also reads for a <limit> that gives only effort and velocity).
inline std::vector<JointLimit> joint_position_limits(const Model& model) {
  std::vector<JointLimit> limits;
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    if (!joint.bounded || joint.nq != 1 || joint.nv != 1 || !(joint.lower < joint.upper)) continue;
    limits.push_back({joint.name, joint.idx_q, joint.idx_v, joint.lower, joint.upper});
  }
  return limits;
}

/// The limits a generated header lists (NAME::num_limited_joints, limited_joint_names,
/// limited_q_index, limited_v_index, limited_lower, limited_upper): the same ranges as
/// joint_position_limits(model) of the description the code was generated from, for a controller
/// on the generated backend, which has no Model.
inline std::vector<JointLimit> joint_position_limits(int count, const char* const* names, const int* q_index, const int* v_index,
                                                     const double* lower, const double* upper) {
  std::vector<JointLimit> limits;
  for (int i = 0; i < count; ++i) limits.push_back({names[i], q_index[i], v_index[i], lower[i], upper[i]});
  return limits;
}

}  // namespace mbgen
