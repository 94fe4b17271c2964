#pragma once
// Fixed-size Eigen aliases used throughout the runtime, templated on the scalar so that the same
// algorithms run on double, float, and (in the generator) a symbolic scalar that records them.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace mbgen {

template <typename S> using Vec3 = Eigen::Matrix<S, 3, 1>;
template <typename S> using Mat3 = Eigen::Matrix<S, 3, 3>;
template <typename S> using Vec6 = Eigen::Matrix<S, 6, 1>;
template <typename S> using Mat6 = Eigen::Matrix<S, 6, 6>;
template <typename S> using VecX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
template <typename S> using MatX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <typename S> using Mat6X = Eigen::Matrix<S, 6, Eigen::Dynamic>;
template <typename S> using Mat3X = Eigen::Matrix<S, 3, Eigen::Dynamic>;

/// Skew-symmetric matrix: skew(a) * b == a.cross(b).
template <typename S> Mat3<S> skew(const Vec3<S>& a) {
  Mat3<S> m;
  m << S(0), -a.z(), a.y(),  //
      a.z(), S(0), -a.x(),   //
      -a.y(), a.x(), S(0);
  return m;
}

/// Casts a fixed-size Eigen object of doubles to scalar S (constants of the model enter every
/// algorithm through here, so a symbolic scalar sees them as constants it can fold).
template <typename S, typename Derived> auto cast(const Eigen::MatrixBase<Derived>& m) {
  return m.template cast<S>().eval();
}

}  // namespace mbgen
