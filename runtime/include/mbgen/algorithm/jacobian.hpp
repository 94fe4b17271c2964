#pragma once
// Jacobians: joint columns in the world frame, frame Jacobians and point Jacobians.
#include "mbgen/algorithm/kinematics.hpp"

namespace mbgen {

/// Frame in which a Jacobian's output is expressed.
enum class ReferenceFrame {
  World,               ///< spatial velocity in world axes, taken at the world origin
  Local,               ///< spatial velocity of the frame in its own axes, at its origin
  LocalWorldAligned,   ///< velocity of the frame origin and angular velocity, in world axes
};

/// Joint Jacobian columns S_j expressed in the world frame at the world origin (data.J, 6 x nv),
/// after forward kinematics for q. Returns data.J.
template <typename S> const Mat6X<S>& compute_joint_jacobians(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  forward_kinematics<S>(model, data, q);
  update_frame_placements<S>(model, data);
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    const Joint& joint = model.joint(model.body(i).joint);
    for (int col = 0; col < joint.nv; ++col)
      data.J.col(joint.idx_v + col) = data.X_WB[i].act(joint_subspace_column<S>(joint, col)).vector();
  }
  return data.J;
}

namespace detail {
/// Writes into J (6 x nv) the Jacobian of a point (world position p_W, world orientation R_WF) fixed
/// on body b; columns of joints that do not support b are zero. Needs data.J.
template <typename S, typename Out>
void point_frame_jacobian(const Model& model, const Data<S>& data, BodyIndex b, const Vec3<S>& p_W,
                          const Mat3<S>& R_WF, ReferenceFrame rf, Out&& J) {
  J.setZero();
  for (BodyIndex j = b; j != kWorldBody; j = model.body(j).parent) {
    const Joint& joint = model.joint(model.body(j).joint);
    for (int col = 0; col < joint.nv; ++col) {
      const int c = joint.idx_v + col;
      Motion<S> m = Motion<S>::from_vector(data.J.col(c));
      switch (rf) {
        case ReferenceFrame::World: J.col(c) = m.vector(); break;
        case ReferenceFrame::LocalWorldAligned:
          J.col(c).template head<3>() = m.linear + m.angular.cross(p_W);
          J.col(c).template tail<3>() = m.angular;
          break;
        case ReferenceFrame::Local:
          J.col(c).template head<3>() = R_WF.transpose() * (m.linear + m.angular.cross(p_W));
          J.col(c).template tail<3>() = R_WF.transpose() * m.angular;
          break;
      }
    }
  }
}
}  // namespace detail

/// Jacobian (6 x nv) of frame f, [linear; angular], in the requested reference frame. Needs
/// compute_joint_jacobians(model, data, q) first.
template <typename S, typename Out>
void frame_jacobian(const Model& model, const Data<S>& data, FrameIndex f, ReferenceFrame rf, Out&& J) {
  const SE3<S>& X = data.X_WF[f];
  detail::point_frame_jacobian<S>(model, data, model.frame(f).body, X.translation, X.rotation, rf, J);
}

/// Jacobian (3 x nv) of the velocity of a point fixed on body b at p_B (body coordinates), in
/// world axes (LocalWorldAligned; World means the same for a point) or body axes (Local). Needs compute_joint_jacobians.
template <typename S, typename Out>
void point_jacobian(const Model& model, const Data<S>& data, BodyIndex b, const Vec3<S>& p_B, ReferenceFrame rf,
                    Out&& J) {
  const SE3<S>& X = data.X_WB[b];
  const Vec3<S> p_W = X.act(p_B);
  J.setZero();
  for (BodyIndex j = b; j != kWorldBody; j = model.body(j).parent) {
    const Joint& joint = model.joint(model.body(j).joint);
    for (int col = 0; col < joint.nv; ++col) {
      const int c = joint.idx_v + col;
      Vec3<S> lin = data.J.col(c).template head<3>() + data.J.col(c).template tail<3>().cross(p_W);
      J.col(c) = rf == ReferenceFrame::Local ? Vec3<S>(X.rotation.transpose() * lin) : lin;
    }
  }
}

}  // namespace mbgen
