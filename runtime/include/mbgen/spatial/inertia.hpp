#pragma once
// Rigid-body inertia (mass, centre of mass, rotational inertia about the centre of mass) and the
// 6x6 spatial-inertia algebra that composite (CRBA) and articulated (ABA) inertias need.
#include "mbgen/spatial/se3.hpp"

namespace mbgen {

/// Inertia of one rigid body in its own frame B: mass m, centre of mass c_B, rotational inertia
/// I_c about the centre of mass in B's orientation.
template <typename S> struct Inertia {
  S mass = S(0);
  Vec3<S> com = Vec3<S>::Zero();
  Mat3<S> inertia_com = Mat3<S>::Zero();

  /// Momentum of the body moving with spatial velocity v (both in B, at B's origin).
  Force<S> operator*(const Motion<S>& v) const {
    Force<S> h;
    h.linear = mass * (v.linear - com.cross(v.angular));
    h.angular = inertia_com * v.angular + com.cross(h.linear);
    return h;
  }

  /// 6x6 matrix acting on [linear; angular] motion vectors at B's origin.
  Mat6<S> matrix() const {
    Mat6<S> m;
    Mat3<S> cx = skew<S>(com);
    m.template topLeftCorner<3, 3>() = mass * Mat3<S>::Identity();
    m.template topRightCorner<3, 3>() = -mass * cx;
    m.template bottomLeftCorner<3, 3>() = mass * cx;
    m.template bottomRightCorner<3, 3>() = inertia_com - mass * cx * cx;
    return m;
  }

  /// Rotational inertia about B's origin.
  Mat3<S> inertia_origin() const {
    Mat3<S> cx = skew<S>(com);
    return inertia_com - mass * cx * cx;
  }

  /// The same body seen from frame A, given the pose X_AB.
  Inertia transformed(const SE3<S>& X_AB) const {
    return {mass, X_AB.act(com), X_AB.rotation * inertia_com * X_AB.rotation.transpose()};
  }

  /// Sum of two bodies expressed in the same frame (parallel-axis theorem). Massless sums keep
  /// the rotational inertias (a massless flywheel still has inertia).
  Inertia operator+(const Inertia& o) const {
    S m = mass + o.mass;
    if (!(m > S(0))) return {S(0), Vec3<S>::Zero(), inertia_com + o.inertia_com};
    Vec3<S> c = (mass * com + o.mass * o.com) / m;
    Vec3<S> d1 = com - c, d2 = o.com - c;
    Mat3<S> s1 = skew<S>(d1), s2 = skew<S>(d2);
    return {m, c, inertia_com + o.inertia_com - mass * s1 * s1 - o.mass * s2 * s2};
  }

  template <typename T> Inertia<T> cast() const {
    return {T(mass), com.template cast<T>(), inertia_com.template cast<T>()};
  }
};

/// R A R^T for a symmetric 3x3 A. Only the upper triangle is computed and then mirrored, so the
/// result is exactly symmetric and a symbolic scalar records each pair of entries once.
template <typename S> Mat3<S> rotate_symmetric(const Mat3<S>& R, const Mat3<S>& A) {
  const Mat3<S> RA = R * A;
  Mat3<S> out;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      out(i, j) = RA.row(i).dot(R.row(j));
      out(j, i) = out(i, j);
    }
  return out;
}

/// The inertia of a body, or of several bodies together, as its mass moments about a frame's
/// origin: mass m, first moment h = m c, rotational inertia I_O about the origin. Unlike Inertia
/// (centre of mass form), moments of bodies in one frame simply add (no division by the total
/// mass), and the momentum of a motion [v; w] is [m v - h x w; I_O w + h x v]: 10 numbers and
/// about 40 operations where the 6x6 matrix takes 36 and 66.
template <typename S> struct InertiaMoments {
  S mass = S(0);
  Vec3<S> first_moment = Vec3<S>::Zero();
  Mat3<S> rotational = Mat3<S>::Zero();  ///< about the origin, symmetric

  /// The moments of body inertia I (given in frame B) about the origin of frame A, X_AB its pose.
  static InertiaMoments of(const Inertia<double>& I, const SE3<S>& X_AB) {
    InertiaMoments out;
    out.mass = S(I.mass);
    const Vec3<S> c = X_AB.act(I.com.cast<S>());
    out.first_moment = out.mass * c;
    // R I_c R^T - m [c]x^2 = R I_c R^T + m (|c|^2 1 - c c^T), upper triangle mirrored.
    out.rotational = rotate_symmetric<S>(X_AB.rotation, I.inertia_com.cast<S>());
    const Vec3<S>& h = out.first_moment;
    out.rotational(0, 0) += h.y() * c.y() + h.z() * c.z();
    out.rotational(1, 1) += h.x() * c.x() + h.z() * c.z();
    out.rotational(2, 2) += h.x() * c.x() + h.y() * c.y();
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j) {
        out.rotational(i, j) -= h[i] * c[j];
        out.rotational(j, i) = out.rotational(i, j);
      }
    return out;
  }

  /// The moments of body inertia I about the origin of its own frame (computed in double).
  static InertiaMoments of_body(const Inertia<double>& I) {
    const InertiaMoments<double> d = InertiaMoments<double>::of(I, SE3<double>());
    InertiaMoments out;
    out.mass = S(d.mass);
    out.first_moment = d.first_moment.template cast<S>();
    out.rotational = d.rotational.template cast<S>();
    return out;
  }

  /// The same moments in axes rotated by R (same origin): m, R h, R I_O R^T.
  InertiaMoments rotated(const Mat3<S>& R) const {
    return {mass, R * first_moment, rotate_symmetric<S>(R, rotational)};
  }

  /// The same moments about a point at -p, i.e. in a frame whose origin sees this one's at p
  /// (same axes): h' = h + m p and, from sum m_i [p + r_i]x^T [p + r_i]x,
  /// I' = I_O + (p . (h + h')) 1 - p h'^T - h p^T (symmetric; the upper triangle is mirrored).
  InertiaMoments translated(const Vec3<S>& p) const {
    InertiaMoments out;
    out.mass = mass;
    out.first_moment = first_moment + mass * p;
    const Vec3<S>& h = first_moment;
    const Vec3<S>& g = out.first_moment;
    const S trace_term = p.dot(h + g);
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) {
        S entry = rotational(i, j) - p[i] * g[j] - h[i] * p[j];
        if (i == j) entry += trace_term;
        out.rotational(i, j) = entry;
        out.rotational(j, i) = entry;
      }
    return out;
  }

  /// The moments given about B's origin, taken about A's, X_AB the pose of B in A.
  InertiaMoments transformed(const SE3<S>& X_AB) const { return rotated(X_AB.rotation).translated(X_AB.translation); }

  InertiaMoments& operator+=(const InertiaMoments& o) {
    mass += o.mass;
    first_moment += o.first_moment;
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) {
        rotational(i, j) += o.rotational(i, j);
        rotational(j, i) = rotational(i, j);
      }
    return *this;
  }

  /// The 6x6 spatial inertia acting on [linear; angular] motions at the origin:
  /// [m 1, -[h]x; [h]x, I_O], the matrix of operator* below.
  Mat6<S> matrix() const {
    Mat6<S> out;
    const Mat3<S> hx = skew<S>(first_moment);
    out.template topLeftCorner<3, 3>() = mass * Mat3<S>::Identity();
    out.template topRightCorner<3, 3>() = -hx;
    out.template bottomLeftCorner<3, 3>() = hx;
    out.template bottomRightCorner<3, 3>() = rotational;
    return out;
  }

  /// Momentum (about the origin) of the bodies moving with spatial velocity m = [v; w].
  Force<S> operator*(const Motion<S>& m) const {
    Vec3<S> angular;
    for (int i = 0; i < 3; ++i) angular[i] = rotational.row(i).dot(m.angular);
    return {mass * m.linear - first_moment.cross(m.angular), angular + first_moment.cross(m.linear)};
  }
};

/// A spatial inertia (composite or articulated; symmetric 6x6 on [linear; angular] motions)
/// re-expressed in axes rotated by R (frame with the same origin): diag(R) I diag(R)^T.
template <typename S> Mat6<S> rotate_spatial_inertia(const Mat3<S>& R, const Mat6<S>& I) {
  Mat6<S> out;
  out.template topLeftCorner<3, 3>() = rotate_symmetric<S>(R, I.template topLeftCorner<3, 3>());
  out.template bottomRightCorner<3, 3>() = rotate_symmetric<S>(R, I.template bottomRightCorner<3, 3>());
  const Mat3<S> B = R * I.template topRightCorner<3, 3>() * R.transpose();
  out.template topRightCorner<3, 3>() = B;
  out.template bottomLeftCorner<3, 3>() = B.transpose();
  return out;
}

/// A spatial inertia taken about a point p instead of the origin (same axes): X^* I X^-1 for the
/// pure translation X = (I, p). Symmetric blocks are computed once and mirrored.
template <typename S> Mat6<S> translate_spatial_inertia(const Vec3<S>& p, const Mat6<S>& I) {
  const Mat3<S> A = I.template topLeftCorner<3, 3>();
  const Mat3<S> B = I.template topRightCorner<3, 3>();
  const Mat3<S> C = I.template bottomRightCorner<3, 3>();
  const Mat3<S> px = skew<S>(p);
  const Mat3<S> lower_left = px * A + B.transpose();
  const Mat3<S> pxB = px * B;
  Mat6<S> out;
  out.template topLeftCorner<3, 3>() = A;
  out.template topRightCorner<3, 3>() = lower_left.transpose();  // = B - A px, as A is symmetric
  out.template bottomLeftCorner<3, 3>() = lower_left;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      out(3 + i, 3 + j) = pxB(i, j) + C(i, j) - lower_left.row(i).dot(px.col(j));
      out(3 + j, 3 + i) = out(3 + i, 3 + j);
    }
  return out;
}

/// Spatial inertia given in B, expressed in A: X_AB^* I_B X_AB^-1 (rotate, then move the origin).
template <typename S> Mat6<S> transform_spatial_inertia(const SE3<S>& X_AB, const Mat6<S>& I_B) {
  return translate_spatial_inertia<S>(X_AB.translation, rotate_spatial_inertia<S>(X_AB.rotation, I_B));
}

}  // namespace mbgen
