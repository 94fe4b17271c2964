#pragma once
// Kinetic and potential energy.
#include "mbgen/algorithm/kinematics.hpp"
#include "mbgen/algorithm/rotor.hpp"

namespace mbgen {

/// Kinetic energy 1/2 v^T M v, computed body by body (drives included, rotor.hpp).
template <typename S> S kinetic_energy(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  forward_kinematics<S>(model, data, q, v);
  S e = S(0);
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    e += data.v[i].dot(model.body(i).inertia.cast<S>() * data.v[i]) / S(2);
    const Joint& joint = model.joint(model.body(i).joint);
    if (joint.armature != 0 || joint.has_rotor_body())
      e += rotor_kinetic_energy<S>(joint, data.v[model.body(i).parent], v[joint.idx_v]);
  }
  return e;
}

/// Potential energy of gravity, -sum m_i g . c_i (zero at the world origin).
template <typename S> S potential_energy(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  forward_kinematics<S>(model, data, q);
  S e = S(0);
  const Vec3<S> g = model.gravity.cast<S>();
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    const Inertia<double>& I = model.body(i).inertia;
    e -= S(I.mass) * g.dot(data.X_WB[i].act(I.com.cast<S>()));
  }
  return e;
}

}  // namespace mbgen
