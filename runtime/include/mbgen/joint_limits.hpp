#pragma once
// Which joints of a model have a position range, and what it is: a fact of the model (URDF
// <limit>, MJCF range), read by the generator (the generated header's limited_* lists), the
// differential IK (control/joint_limit_potential.hpp) and the simulator's end stops
// (sim/joint_stops.hpp, whose law's parameters are here: JointStopParameters).
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

/// One joint's own stop settings (`scene: joint_limits: joints:` and `free:`, docs/extras.md).
struct JointStopSetting {
  std::string joint;
  bool free = false;     ///< no stop on this joint
  double stiffness = 0;  ///< k, N m/rad^exponent (N/m^exponent); <= 0: the default (frequency)
  double damping = -1;   ///< d, s/rad (s/m); < 0: JointStopParameters::damping
};

/// The simulator's end stops (sim/joint_stops.hpp): every range of joint_position_limits becomes a
/// compliant unilateral stop in the ground's Hunt-Crossley form, torque k delta^e + c delta_dot >= 0
/// pushing back into the range, delta the distance past the end, c = k d delta^e up to critical
/// damping, c <= 2 zeta sqrt(k m) (m the inertia the stop feels, zeta = max_damping_ratio). Why compliant:
/// it fits the explicit and linearly implicit integrators the simulator has (a hard stop would
/// need impulses and a complementarity solve), and it is the law of the ground, so one set of
/// numbers describes both. Why the default stiffness comes from a frequency: a stop's stiffness
/// has to match the inertia it stops, which ranges over four orders of magnitude within one robot
/// (a hip carries the leg, a foot's rod only itself); k = m (2 pi f)^2, m the inertia the stop
/// feels (1 / (t' M_y^-1 t), t the joint's row of the velocity map: through the loops for a
/// dependent joint), makes every stop ring at f when it is hit, whatever it holds. Why the cap on
/// the damping: Hunt-Crossley's damping rate k d delta^e / m is d times the acceleration the load
/// gives the stop's inertia, whatever k is; a light link under the whole robot's weight (Cassie's
/// tarsus when it falls) makes it stiff beyond what an explicit step takes (10^4 /s, RK4 at 0.5
/// ms diverges). Critical damping, 2 sqrt(k/m) /s, bounds it, and a stop damped critically does
/// not bounce anyway.
struct JointStopParameters {
  bool enabled = true;     ///< `scene: joint_limits: false` turns every stop off
  double frequency = 100;  ///< f, Hz: each default stiffness, k = m (2 pi f)^2 at the start pose
  double damping = 3;      ///< d, s/rad (s/m): Hunt-Crossley damping of every stop
  double exponent = 1;     ///< e >= 1: 1 is a linear spring at the end stop
  double max_damping_ratio = 1;  ///< zeta: the damping c = k d delta^e at most 2 zeta sqrt(k m); <= 0: no cap
  std::vector<JointStopSetting> joints;  ///< per-joint exceptions, by joint name
  /// The setting for `joint`, or nullptr.
  const JointStopSetting* setting(const std::string& joint) const {
    for (const JointStopSetting& s : joints)
      if (s.joint == joint) return &s;
    return nullptr;
  }
};

}  // namespace mbgen
