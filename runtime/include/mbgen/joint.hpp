#pragma once
// Joint kinematics: transform, motion subspace S and its transpose, for each joint type.
// Each function costs only what its joint type needs, so that a symbolic scalar records no
// multiplication by a structural zero.
#include <cmath>

#include "mbgen/model.hpp"

namespace mbgen {

/// Rotation matrix of the unit quaternion (x, y, z, w), Hamilton convention.
template <typename S> Mat3<S> quaternion_to_rotation(const S& x, const S& y, const S& z, const S& w) {
  S xx = x * x, yy = y * y, zz = z * z, xy = x * y, xz = x * z, yz = y * z, wx = w * x, wy = w * y, wz = w * z;
  Mat3<S> R;
  R << S(1) - S(2) * (yy + zz), S(2) * (xy - wz), S(2) * (xz + wy),  //
      S(2) * (xy + wz), S(1) - S(2) * (xx + zz), S(2) * (yz - wx),   //
      S(2) * (xz - wy), S(2) * (yz + wx), S(1) - S(2) * (xx + yy);
  return R;
}

/// Rotation by angle (given as its sine and cosine) about a constant unit axis (Rodrigues).
/// About a coordinate axis (+-x, +-y, +-z, the usual case) the entries are written directly:
/// Rodrigues' c + (1 - c) on the axis is 1 only up to round-off, and a symbolic scalar would
/// carry it (and every product with it) into generated code.
template <typename S> Mat3<S> axis_rotation(const Vec3<double>& axis, const S& s, const S& c) {
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    if ((axis[k] == 1.0 || axis[k] == -1.0) && axis[k1] == 0.0 && axis[k2] == 0.0) {
      const S s_signed = axis[k] > 0 ? s : -s;
      Mat3<S> R = Mat3<S>::Zero();
      R(k, k) = S(1);
      R(k1, k1) = c;
      R(k2, k2) = c;
      R(k2, k1) = s_signed;
      R(k1, k2) = -s_signed;
      return R;
    }
  }
  Vec3<S> a = axis.cast<S>();
  S t = S(1) - c;
  Mat3<S> R;
  R << c + t * a.x() * a.x(), t * a.x() * a.y() - s * a.z(), t * a.x() * a.z() + s * a.y(),  //
      t * a.x() * a.y() + s * a.z(), c + t * a.y() * a.y(), t * a.y() * a.z() - s * a.x(),   //
      t * a.x() * a.z() - s * a.y(), t * a.y() * a.z() + s * a.x(), c + t * a.z() * a.z();
  return R;
}

/// Pose of the child body in the joint frame J for joint coordinates q_j (the joint's slice of q).
template <typename S> SE3<S> joint_motion_transform(const Joint& joint, const S* q_j) {
  using std::cos;
  using std::sin;
  SE3<S> X;
  switch (joint.type) {
    case JointType::Revolute: X.rotation = axis_rotation<S>(joint.axis, sin(q_j[0]), cos(q_j[0])); break;
    case JointType::Prismatic: X.translation = joint.axis.cast<S>() * q_j[0]; break;
    case JointType::Floating:
      X.translation << q_j[0], q_j[1], q_j[2];
      X.rotation = quaternion_to_rotation<S>(q_j[3], q_j[4], q_j[5], q_j[6]);
      break;
  }
  return X;
}

/// S * v_j: spatial velocity of the child relative to the parent, in the child frame.
template <typename S> Motion<S> joint_velocity(const Joint& joint, const S* v_j) {
  Motion<S> m;
  switch (joint.type) {
    case JointType::Revolute: m.angular = joint.axis.cast<S>() * v_j[0]; break;
    case JointType::Prismatic: m.linear = joint.axis.cast<S>() * v_j[0]; break;
    case JointType::Floating:
      m.linear << v_j[0], v_j[1], v_j[2];
      m.angular << v_j[3], v_j[4], v_j[5];
      break;
  }
  return m;
}

/// S^T f, written into out[0 .. nv).
template <typename S> void joint_project(const Joint& joint, const Force<S>& f, S* out) {
  switch (joint.type) {
    case JointType::Revolute: out[0] = joint.axis.cast<S>().dot(f.angular); break;
    case JointType::Prismatic: out[0] = joint.axis.cast<S>().dot(f.linear); break;
    case JointType::Floating:
      for (int k = 0; k < 3; ++k) {
        out[k] = f.linear[k];
        out[3 + k] = f.angular[k];
      }
      break;
  }
}

/// The index (0-5, [linear; angular]) of the one entry of a 1-DoF joint's motion subspace S when
/// its axis is a coordinate axis (either sign), -1 otherwise (and for a floating joint).
inline int joint_subspace_coordinate(const Joint& joint) {
  if (joint.type == JointType::Floating) return -1;
  int found = -1;
  for (int k = 0; k < 3; ++k) {
    if (joint.axis[k] == 0) continue;
    if (found >= 0 || (joint.axis[k] != 1 && joint.axis[k] != -1)) return -1;
    found = k;
  }
  if (found < 0) return -1;
  return joint.type == JointType::Revolute ? 3 + found : found;
}

/// Column k of the motion subspace S (in the child frame).
template <typename S> Motion<S> joint_subspace_column(const Joint& joint, int k) {
  Vec6<S> e = Vec6<S>::Zero();
  switch (joint.type) {
    case JointType::Revolute: e.template tail<3>() = joint.axis.cast<S>(); break;
    case JointType::Prismatic: e.template head<3>() = joint.axis.cast<S>(); break;
    case JointType::Floating: e[k] = S(1); break;
  }
  return Motion<S>::from_vector(e);
}

}  // namespace mbgen

// Moving quantities between a body and its parent in two stages, the joint transform X_J(q)
// and the constant tree transform X_PJ. Two stages cost the double path a little, but they let
// a symbolic scalar see the structure of each: X_J of a revolute joint has no translation and
// rotates about a constant axis, and an axis-aligned X_PJ folds to sign changes and swaps.
namespace mbgen {

/// Motion of the parent (in P) expressed in the child body frame.
template <typename S> Motion<S> motion_parent_to_child(const Joint& joint, const SE3<S>& X_J, const Motion<S>& m_P) {
  const Motion<S> m_J = joint.X_PJ_is_identity ? m_P : joint.X_PJ.cast<S>().act_inv(m_P);
  switch (joint.type) {
    case JointType::Revolute:
      return {X_J.rotation.transpose() * m_J.linear, X_J.rotation.transpose() * m_J.angular};
    case JointType::Prismatic: return {m_J.linear - X_J.translation.cross(m_J.angular), m_J.angular};
    case JointType::Floating: break;
  }
  return X_J.act_inv(m_J);
}

/// Force on the child (in the child frame) expressed in the parent frame P.
template <typename S> Force<S> force_child_to_parent(const Joint& joint, const SE3<S>& X_J, const Force<S>& f_C) {
  Force<S> f_J;
  switch (joint.type) {
    case JointType::Revolute: f_J = {X_J.rotation * f_C.linear, X_J.rotation * f_C.angular}; break;
    case JointType::Prismatic: f_J = {f_C.linear, f_C.angular + X_J.translation.cross(f_C.linear)}; break;
    case JointType::Floating: f_J = X_J.act(f_C); break;
  }
  return joint.X_PJ_is_identity ? f_J : joint.X_PJ.cast<S>().act(f_J);
}

/// Spatial inertia (6x6) of the child, in the child frame, expressed in the parent frame P.
template <typename S> Mat6<S> inertia_child_to_parent(const Joint& joint, const SE3<S>& X_J, const Mat6<S>& I_C) {
  Mat6<S> I_J;
  switch (joint.type) {
    case JointType::Revolute: I_J = rotate_spatial_inertia<S>(X_J.rotation, I_C); break;
    case JointType::Prismatic: I_J = translate_spatial_inertia<S>(X_J.translation, I_C); break;
    case JointType::Floating: I_J = transform_spatial_inertia<S>(X_J, I_C); break;
  }
  if (joint.X_PJ_is_identity) return I_J;
  return transform_spatial_inertia<S>(joint.X_PJ.cast<S>(), I_J);
}

/// Mass moments of the child (about its origin, child axes) taken about the parent's origin in
/// the parent's axes: the composite inertia of CRBA in its 10-number form (inertia.hpp).
template <typename S>
InertiaMoments<S> moments_child_to_parent(const Joint& joint, const SE3<S>& X_J, const InertiaMoments<S>& I_C) {
  InertiaMoments<S> I_J;
  switch (joint.type) {
    case JointType::Revolute: I_J = I_C.rotated(X_J.rotation); break;
    case JointType::Prismatic: I_J = I_C.translated(X_J.translation); break;
    case JointType::Floating: I_J = I_C.transformed(X_J); break;
  }
  if (joint.X_PJ_is_identity) return I_J;
  return I_J.transformed(joint.X_PJ.cast<S>());
}

}  // namespace mbgen
