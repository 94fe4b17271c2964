#pragma once
// Forward kinematics: body poses (parent and world), body velocities and accelerations.
#include <Eigen/Core>

#include "mbgen/data.hpp"
#include "mbgen/joint.hpp"

namespace mbgen {

template <typename S> using ConstVecRef = Eigen::Ref<const VecX<S>>;

namespace detail {
/// Body i's pose in its parent, X_PB = X_PJ X_J, with X_J kept: the centroidal composites move
/// through it.
template <typename S> void place_in_parent(const Model& model, Data<S>& data, const S* q, BodyIndex i) {
  const Joint& joint = model.joint(model.body(i).joint);
  data.X_J[i] = joint_motion_transform<S>(joint, q + joint.idx_q);
  data.X_PB[i] = joint.X_PJ.template cast<S>() * data.X_J[i];
}

/// Shared pass: poses always, velocities if v, accelerations if a (no gravity in a).
template <typename S> void kinematics_pass(const Model& model, Data<S>& data, const S* q, const S* v, const S* a) {
  data.X_WB[kWorldBody] = SE3<S>::Identity();
  data.v[kWorldBody] = Motion<S>::Zero();
  data.a[kWorldBody] = Motion<S>::Zero();
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    const Body& body = model.body(i);
    const Joint& joint = model.joint(body.joint);
    place_in_parent<S>(model, data, q, i);
    data.X_WB[i] = data.X_WB[body.parent] * data.X_PB[i];
    if (v) {
      Motion<S> vj = joint_velocity<S>(joint, v + joint.idx_v);
      data.v[i] = data.X_PB[i].act_inv(data.v[body.parent]) + vj;
      if (a) {
        data.a[i] = data.X_PB[i].act_inv(data.a[body.parent]) + joint_velocity<S>(joint, a + joint.idx_v) +
                    data.v[i].cross(vj);
      }
    }
  }
}
}  // namespace detail

/// Body poses X_J, X_PB, X_WB for configuration q (size nq).
template <typename S> void forward_kinematics(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  detail::kinematics_pass<S>(model, data, q.data(), nullptr, nullptr);
}

/// Poses and body velocities data.v (body frame) for q (nq) and v (nv).
template <typename S>
void forward_kinematics(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  detail::kinematics_pass<S>(model, data, q.data(), v.data(), nullptr);
}

/// Poses, velocities and spatial accelerations data.a (body frame, without gravity).
template <typename S>
void forward_kinematics(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                        const ConstVecRef<S>& a) {
  detail::kinematics_pass<S>(model, data, q.data(), v.data(), a.data());
}

/// World poses of all frames, data.X_WF, from data.X_WB (run forward_kinematics first).
template <typename S> void update_frame_placements(const Model& model, Data<S>& data) {
  for (int k = 0; k < model.num_frames(); ++k) {
    const FrameIndex f(k);
    const Frame& frame = model.frame(f);
    data.X_WF[f] = data.X_WB[frame.body] * frame.X_BF.cast<S>();
  }
}

/// Spatial velocity of body b, or of frame f, in the world frame at the world origin.
template <typename S> Motion<S> body_velocity_world(const Data<S>& data, BodyIndex b) {
  return data.X_WB[b].act(data.v[b]);
}

}  // namespace mbgen
