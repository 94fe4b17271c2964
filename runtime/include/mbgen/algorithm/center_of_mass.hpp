#pragma once
// Centre of mass: position, velocity and Jacobian.
#include "mbgen/algorithm/jacobian.hpp"

namespace mbgen {

/// Total mass, centre of mass (data.com) and, if v is given, its velocity (data.vcom), world.
template <typename S>
const Vec3<S>& center_of_mass(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  forward_kinematics<S>(model, data, q, v);
  data.mass = S(0);
  data.com.setZero();
  data.vcom.setZero();
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    const Inertia<double>& I = model.body(i).inertia;
    const S m = S(I.mass);
    const Vec3<S> c_B = I.com.cast<S>();
    data.mass += m;
    data.com += m * data.X_WB[i].act(c_B);
    const Motion<S>& vb = data.v[i];
    data.vcom += m * (data.X_WB[i].rotation * (vb.linear + vb.angular.cross(c_B)));
  }
  data.com /= data.mass;
  data.vcom /= data.mass;
  return data.com;
}

/// Centre-of-mass position only.
template <typename S> const Vec3<S>& center_of_mass(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  forward_kinematics<S>(model, data, q);
  data.mass = S(0);
  data.com.setZero();
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    const Inertia<double>& I = model.body(i).inertia;
    data.mass += S(I.mass);
    data.com += S(I.mass) * data.X_WB[i].act(I.com.cast<S>());
  }
  data.com /= data.mass;
  return data.com;
}

/// Centre-of-mass Jacobian (3 x nv, world) in data.Jcom; also sets data.com and data.J.
template <typename S> const Mat3X<S>& jacobian_center_of_mass(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  compute_joint_jacobians<S>(model, data, q);
  data.Jcom.setZero();
  data.mass = S(0);
  data.com.setZero();
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    const Inertia<double>& I = model.body(i).inertia;
    const S m = S(I.mass);
    const Vec3<S> c_W = data.X_WB[i].act(I.com.cast<S>());
    data.mass += m;
    data.com += m * c_W;
    for (BodyIndex j = i; j != kWorldBody; j = model.body(j).parent) {
      const Joint& joint = model.joint(model.body(j).joint);
      for (int col = 0; col < joint.nv; ++col) {
        const int c = joint.idx_v + col;
        data.Jcom.col(c) += m * (data.J.col(c).template head<3>() + data.J.col(c).template tail<3>().cross(c_W));
      }
    }
  }
  data.com /= data.mass;
  data.Jcom /= data.mass;
  return data.Jcom;
}

}  // namespace mbgen
