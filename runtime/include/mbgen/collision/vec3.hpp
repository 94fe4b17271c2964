#pragma once
// The SSV primitives' own 3-vector: three scalars, nothing else.
//
// Why not Eigen's Vec3 (spatial/types.hpp): generated self-distance code calls these primitives,
// and generated code compiles with only its output directory and runtime/include on the include
// path, for a Cortex-M7 too (tests/firmware/check_firmware.sh). This header needs the standard
// library's <cmath> and <type_traits> only.
//
// The members are named as Eigen's (x(), dot, cross, squaredNorm, cwiseAbs, maxCoeff, UnitZ...)
// so the primitives read as before, and two implicit bridges let Eigen code (the generic
// compound layer, tests, benchmarks) pass and take these vectors without copies by hand:
//   - from any Eigen 3-vector expression of the same scalar (detected by its RowsAtCompileTime,
//     ColsAtCompileTime and Scalar members, so Eigen need not be included here);
//   - to any Eigen fixed 3x1 matrix type of the same scalar (constructed from x, y, z).
// Arithmetic operators are hidden friends: found by argument-dependent lookup on an SsvVec3
// operand, and the other operand may then convert (SsvVec3 + Eigen vector is an SsvVec3).
#include <cmath>
#include <type_traits>

namespace mbgen::collision {

template <typename S> struct SsvVec3 {
  S v[3];

  SsvVec3() = default;
  constexpr SsvVec3(S x, S y, S z) : v{x, y, z} {}
  template <typename E, std::enable_if_t<E::RowsAtCompileTime == 3 && E::ColsAtCompileTime == 1 &&
                                             std::is_same_v<typename E::Scalar, S>, int> = 0>
  SsvVec3(const E& e) : v{e.x(), e.y(), e.z()} {}  // NOLINT: implicit on purpose (see above)
  template <typename M, std::enable_if_t<M::RowsAtCompileTime == 3 && M::ColsAtCompileTime == 1 &&
                                             std::is_same_v<typename M::Scalar, S>, int> = 0>
  operator M() const {  // NOLINT: implicit on purpose (see above)
    return M(v[0], v[1], v[2]);
  }

  static constexpr SsvVec3 Zero() { return {S(0), S(0), S(0)}; }
  static constexpr SsvVec3 UnitZ() { return {S(0), S(0), S(1)}; }

  S x() const { return v[0]; }
  S y() const { return v[1]; }
  S z() const { return v[2]; }
  S& operator[](int i) { return v[i]; }
  S operator[](int i) const { return v[i]; }

  S dot(const SsvVec3& b) const { return v[0] * b.v[0] + v[1] * b.v[1] + v[2] * b.v[2]; }
  SsvVec3 cross(const SsvVec3& b) const {
    return {v[1] * b.v[2] - v[2] * b.v[1], v[2] * b.v[0] - v[0] * b.v[2], v[0] * b.v[1] - v[1] * b.v[0]};
  }
  S squaredNorm() const { return dot(*this); }
  S norm() const {
    using std::sqrt;
    return sqrt(squaredNorm());
  }
  SsvVec3 normalized() const { return *this / norm(); }
  SsvVec3 cwiseAbs() const {
    using std::abs;
    return {abs(v[0]), abs(v[1]), abs(v[2])};
  }
  SsvVec3 cwiseMax(const SsvVec3& b) const {
    return {v[0] > b.v[0] ? v[0] : b.v[0], v[1] > b.v[1] ? v[1] : b.v[1], v[2] > b.v[2] ? v[2] : b.v[2]};
  }
  S maxCoeff() const {
    const S m = v[0] > v[1] ? v[0] : v[1];
    return m > v[2] ? m : v[2];
  }
  bool allFinite() const {
    using std::isfinite;
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
  }
  template <typename T> SsvVec3<T> cast() const { return {T(v[0]), T(v[1]), T(v[2])}; }

  SsvVec3& operator+=(const SsvVec3& b) { return *this = *this + b; }
  SsvVec3& operator-=(const SsvVec3& b) { return *this = *this - b; }

  friend SsvVec3 operator+(const SsvVec3& a, const SsvVec3& b) { return {a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2]}; }
  friend SsvVec3 operator-(const SsvVec3& a, const SsvVec3& b) { return {a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2]}; }
  friend SsvVec3 operator-(const SsvVec3& a) { return {-a.v[0], -a.v[1], -a.v[2]}; }
  friend SsvVec3 operator*(S s, const SsvVec3& a) { return {s * a.v[0], s * a.v[1], s * a.v[2]}; }
  friend SsvVec3 operator*(const SsvVec3& a, S s) { return {a.v[0] * s, a.v[1] * s, a.v[2] * s}; }
  friend bool operator==(const SsvVec3& a, const SsvVec3& b) { return a.v[0] == b.v[0] && a.v[1] == b.v[1] && a.v[2] == b.v[2]; }
  friend bool operator!=(const SsvVec3& a, const SsvVec3& b) { return !(a == b); }
  friend SsvVec3 operator/(const SsvVec3& a, S s) { return {a.v[0] / s, a.v[1] / s, a.v[2] / s}; }
};

}  // namespace mbgen::collision
