#pragma once
// Centroidal momentum matrix (Orin and Goswami): h_G = A_G(q) v, the linear momentum and the
// angular momentum about the centre of mass, both in world axes.
#include "mbgen/algorithm/kinematics.hpp"

namespace mbgen {

namespace detail {
/// A_G from the body poses of data (X_J and X_WB: forward_kinematics first): see
/// centroidal_momentum_matrix. Separate so that a caller that has the poses already (the
/// generic backend, after compute_joint_jacobians) does not compute them twice.
template <typename S> const Mat6X<S>& centroidal_momentum_matrix_from_poses(const Model& model, Data<S>& data) {
  for (int k = 1; k < model.num_bodies(); ++k) data.composite[BodyIndex(k)] = InertiaMoments<S>::of_body(model.body(BodyIndex(k)).inertia);
  for (int k = model.num_bodies() - 1; k >= 1; --k) {
    const BodyIndex i(k);
    const BodyIndex parent = model.body(i).parent;
    if (parent != kWorldBody) data.composite[parent] += moments_child_to_parent<S>(model.joint(model.body(i).joint), data.X_J[i], data.composite[i]);
  }
  // Mass and centre of mass from the composites of the bodies on the world (their subtrees).
  data.mass = S(0);
  Vec3<S> first_moment = Vec3<S>::Zero();
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    if (model.body(i).parent != kWorldBody) continue;
    const InertiaMoments<S>& Y = data.composite[i];
    data.mass += Y.mass;
    first_moment += data.X_WB[i].rotation * Y.first_moment + Y.mass * data.X_WB[i].translation;
  }
  data.com = first_moment / data.mass;
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    const Joint& joint = model.joint(model.body(i).joint);
    const SE3<S>& X = data.X_WB[i];
    const Vec3<S> arm = X.translation - data.com;
    for (int col = 0; col < joint.nv; ++col) {
      const int c = joint.idx_v + col;
      // Momentum of the composite moving with the joint column, about the body origin in body
      // axes, then in world axes about the centre of mass.
      const Force<S> h = data.composite[i] * joint_subspace_column<S>(joint, col);
      const Vec3<S> linear = X.rotation * h.linear;
      data.Ag.col(c).template head<3>() = linear;
      data.Ag.col(c).template tail<3>() = X.rotation * h.angular + arm.cross(linear);
    }
  }
  return data.Ag;
}
}  // namespace detail

/// A_G (6 x nv) in data.Ag, also returned; sets data.com, data.mass and the body poses. O(n), as
/// CRBA's composites: each body's mass moments (InertiaMoments: 10 numbers, they add without
/// division) in its own frame, moved to the parent through the joint (a rotation about the joint
/// axis and the constant tree transform) leaves to root; column c of A_G is the momentum of the
/// composite supported by joint c moving with that joint's column, taken to world axes about the
/// centre of mass. Summing the composites in world axes instead (the previous form) rotated every
/// body's inertia by its full world rotation: on Lola, 6,700 operations against ~4,000.
template <typename S> const Mat6X<S>& centroidal_momentum_matrix(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  forward_kinematics<S>(model, data, q);
  return detail::centroidal_momentum_matrix_from_poses<S>(model, data);
}

/// Centroidal momentum h_G = A_G v in data.hg (also fills data.Ag), returned.
template <typename S>
const Vec6<S>& centroidal_momentum(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  centroidal_momentum_matrix<S>(model, data, q);
  data.hg = data.Ag * v;
  return data.hg;
}

}  // namespace mbgen
