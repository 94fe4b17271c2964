#pragma once
// Recursive Newton-Euler inverse dynamics: tau = M(q) a + C(q, v) v + g(q).
#include "mbgen/algorithm/kinematics.hpp"
#include "mbgen/algorithm/rotor.hpp"

namespace mbgen {

/// Joint forces that produce accelerations a (nv) at state (q, v). Result in data.tau (nv), which
/// is also returned. Gravity enters as an upward acceleration of the world.
template <typename S>
const VecX<S>& rnea(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                    const ConstVecRef<S>& a) {
  data.a[kWorldBody] = Motion<S>{-model.gravity.cast<S>(), Vec3<S>::Zero()};
  data.v[kWorldBody] = Motion<S>::Zero();
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    const Body& body = model.body(i);
    const Joint& joint = model.joint(body.joint);
    data.X_J[i] = joint_motion_transform<S>(joint, q.data() + joint.idx_q);
    Motion<S> vj = joint_velocity<S>(joint, v.data() + joint.idx_v);
    data.v[i] = motion_parent_to_child<S>(joint, data.X_J[i], data.v[body.parent]) + vj;
    data.a[i] = motion_parent_to_child<S>(joint, data.X_J[i], data.a[body.parent]) +
                joint_velocity<S>(joint, a.data() + joint.idx_v) + data.v[i].cross(vj);
    const Inertia<S> I = body.inertia.cast<S>();
    data.f[i] = I * data.a[i] + data.v[i].cross(I * data.v[i]);
    // A rotor body rides on the parent: its force joins the parent's (rotor.hpp).
    if (joint.has_rotor_body() && body.parent != kWorldBody)
      data.f[body.parent] += rotor_force<S>(joint, data.v[body.parent], data.a[body.parent], v[joint.idx_v], a[joint.idx_v]);
  }
  for (int k = model.num_bodies() - 1; k >= 1; --k) {
    const BodyIndex i(k);
    const Body& body = model.body(i);
    const Joint& joint = model.joint(body.joint);
    joint_project<S>(joint, data.f[i], data.tau.data() + joint.idx_v);
    if (joint.armature != 0 || joint.has_rotor_body())
      data.tau[joint.idx_v] += rotor_joint_force<S>(joint, data.a[body.parent], a[joint.idx_v]);
    if (body.parent != kWorldBody) data.f[body.parent] += force_child_to_parent<S>(joint, data.X_J[i], data.f[i]);
  }
  return data.tau;
}

/// Bias forces C(q, v) v + g(q) (RNEA with zero acceleration). Result in data.tau.
template <typename S>
const VecX<S>& nonlinear_effects(const Model& model, Data<S>& data, const ConstVecRef<S>& q,
                                 const ConstVecRef<S>& v) {
  data.ddq.setZero();
  return rnea<S>(model, data, q, v, data.ddq);
}

}  // namespace mbgen
