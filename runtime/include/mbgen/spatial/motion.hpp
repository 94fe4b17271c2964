#pragma once
// Spatial motion and force vectors. Ordering everywhere in mbgen: [linear; angular]
// (as in Pinocchio). A Motion expressed in frame B and taken at B's origin is written v_B.
#include "mbgen/spatial/types.hpp"

namespace mbgen {

template <typename S> struct Force;

/// Spatial velocity or acceleration: linear part (velocity of the frame origin) and angular part.
template <typename S> struct Motion {
  Vec3<S> linear = Vec3<S>::Zero();
  Vec3<S> angular = Vec3<S>::Zero();

  static Motion Zero() { return Motion{}; }
  Vec6<S> vector() const {
    Vec6<S> x;
    x << linear, angular;
    return x;
  }
  static Motion from_vector(const Vec6<S>& x) { return Motion{x.template head<3>(), x.template tail<3>()}; }

  Motion operator+(const Motion& o) const { return {linear + o.linear, angular + o.angular}; }
  Motion operator-(const Motion& o) const { return {linear - o.linear, angular - o.angular}; }
  Motion operator-() const { return {-linear, -angular}; }
  Motion operator*(const S& s) const { return {linear * s, angular * s}; }
  Motion& operator+=(const Motion& o) {
    linear += o.linear;
    angular += o.angular;
    return *this;
  }

  /// Motion cross product (this ×  m), the derivative of m seen from a frame moving with this.
  Motion cross(const Motion& m) const {
    return {angular.cross(m.linear) + linear.cross(m.angular), angular.cross(m.angular)};
  }
  /// Force cross product (this ×* f).
  Force<S> cross(const Force<S>& f) const;

  S dot(const Force<S>& f) const;
};

/// Spatial force: linear part (force) and angular part (moment about the frame origin).
template <typename S> struct Force {
  Vec3<S> linear = Vec3<S>::Zero();
  Vec3<S> angular = Vec3<S>::Zero();

  static Force Zero() { return Force{}; }
  Vec6<S> vector() const {
    Vec6<S> x;
    x << linear, angular;
    return x;
  }
  static Force from_vector(const Vec6<S>& x) { return Force{x.template head<3>(), x.template tail<3>()}; }

  Force operator+(const Force& o) const { return {linear + o.linear, angular + o.angular}; }
  Force operator-(const Force& o) const { return {linear - o.linear, angular - o.angular}; }
  Force operator-() const { return {-linear, -angular}; }
  Force operator*(const S& s) const { return {linear * s, angular * s}; }
  Force& operator+=(const Force& o) {
    linear += o.linear;
    angular += o.angular;
    return *this;
  }
  Force& operator-=(const Force& o) {
    linear -= o.linear;
    angular -= o.angular;
    return *this;
  }
};

template <typename S> Force<S> Motion<S>::cross(const Force<S>& f) const {
  return {angular.cross(f.linear), angular.cross(f.angular) + linear.cross(f.linear)};
}

template <typename S> S Motion<S>::dot(const Force<S>& f) const {
  return linear.dot(f.linear) + angular.dot(f.angular);
}

}  // namespace mbgen
