#pragma once
// Rigid transform. X_AB (rotation R_AB, translation p_AB) is the pose of frame B in frame A:
// a point with coordinates r_B in B has coordinates r_A = R_AB r_B + p_AB in A.
#include "mbgen/spatial/motion.hpp"

namespace mbgen {

template <typename S> struct SE3 {
  Mat3<S> rotation = Mat3<S>::Identity();
  Vec3<S> translation = Vec3<S>::Zero();

  static SE3 Identity() { return SE3{}; }

  /// Composition: X_AC = X_AB * X_BC.
  SE3 operator*(const SE3& o) const { return {rotation * o.rotation, rotation * o.translation + translation}; }
  SE3 inverse() const {
    Mat3<S> rt = rotation.transpose();
    return {rt, -(rt * translation)};
  }
  Vec3<S> act(const Vec3<S>& point) const { return rotation * point + translation; }
  Vec3<S> act_inv(const Vec3<S>& point) const { return rotation.transpose() * (point - translation); }

  /// Motion given in B (at B's origin) expressed in A (at A's origin).
  Motion<S> act(const Motion<S>& m) const {
    Vec3<S> w = rotation * m.angular;
    return {rotation * m.linear + translation.cross(w), w};
  }
  /// Motion given in A expressed in B.
  Motion<S> act_inv(const Motion<S>& m) const {
    return {rotation.transpose() * (m.linear - translation.cross(m.angular)), rotation.transpose() * m.angular};
  }
  /// Force given in B expressed in A.
  Force<S> act(const Force<S>& f) const {
    Vec3<S> lin = rotation * f.linear;
    return {lin, rotation * f.angular + translation.cross(lin)};
  }
  /// Force given in A expressed in B.
  Force<S> act_inv(const Force<S>& f) const {
    return {rotation.transpose() * f.linear, rotation.transpose() * (f.angular - translation.cross(f.linear))};
  }

  /// 6x6 motion transform (acts on [linear; angular] vectors).
  Mat6<S> action_matrix() const {
    Mat6<S> x;
    x.template topLeftCorner<3, 3>() = rotation;
    x.template topRightCorner<3, 3>() = skew<S>(translation) * rotation;
    x.template bottomLeftCorner<3, 3>().setZero();
    x.template bottomRightCorner<3, 3>() = rotation;
    return x;
  }

  template <typename T> SE3<T> cast() const {
    return {rotation.template cast<T>(), translation.template cast<T>()};
  }
};

}  // namespace mbgen
