#pragma once
// Closest points between cores made of points and segments: point-segment and segment-segment.
// Every branch decision is a comparison of S values in a small helper (clamp01, take_closer), so
// that the arithmetic stays plain templated math (DESIGN.md "One implementation of the math").
// No NaN or inf for finite inputs whose squared coordinates do not overflow.
#include <limits>

#include "mbgen/spatial/types.hpp"

namespace mbgen::collision {

/// A closest pair: c1 on core 1, c2 on core 2, and dist2 = |c2 - c1|^2.
template <typename S> struct ClosestPoints {
  Vec3<S> c1, c2;
  S dist2;
};

template <typename S> ClosestPoints<S> make_closest(const Vec3<S>& c1, const Vec3<S>& c2) {
  return {c1, c2, (c2 - c1).squaredNorm()};
}

/// The closer of two candidate pairs (the first one on a tie).
template <typename S> const ClosestPoints<S>& take_closer(const ClosestPoints<S>& x, const ClosestPoints<S>& y) {
  return y.dist2 < x.dist2 ? y : x;
}

template <typename S> S clamp01(S t) { return t < S(0) ? S(0) : (t > S(1) ? S(1) : t); }

/// Parameter t in [0, 1] of the point of segment a-b closest to p.
/// Rule (zero-length segment): when |b - a|^2 is 0 the segment is the point a (t = 0). A
/// positive but tiny |b - a|^2 may make the quotient overflow to +-inf, which the clamp maps to
/// 0 or 1; 0/0 cannot occur.
template <typename S> S closest_parameter_on_segment(const Vec3<S>& p, const Vec3<S>& a, const Vec3<S>& b) {
  const Vec3<S> d = b - a;
  const S dd = d.squaredNorm();
  return dd > S(0) ? clamp01((p - a).dot(d) / dd) : S(0);
}

/// Closest points of a point p (core 1) and the segment a-b (core 2).
template <typename S> ClosestPoints<S> closest_point_segment(const Vec3<S>& p, const Vec3<S>& a, const Vec3<S>& b) {
  const S t = closest_parameter_on_segment(p, a, b);
  return make_closest<S>(p, a + t * (b - a));
}

/// Closest points of the segments p0-p1 (core 1) and q0-q1 (core 2).
///
/// The squared distance |p0 + s d1 - q0 - t d2|^2 is convex on [0,1]^2. Its minimum is either
/// the stationary point of the infinite lines, when that lies inside the square, or on one of
/// the square's four sides, i.e. an endpoint against the other segment: the minimum of four
/// point-segment distances, each computed stably. Rules:
///  - Line-line stationary point: s = (n . (d2 x r)) / |n|^2 with n = d1 x d2, r = p0 - q0 (the
///    Lagrange identity turns Ericson's (b f - c e) / (a e - b^2) into cross products, which do
///    not cancel catastrophically for small angles); t is then the projection of the point at s
///    onto the second line, so the pair is consistent even when s is inaccurate.
///  - Parallel and nearly parallel: the stationary point is used only when
///    |d1 x d2|^2 > eps^2 |d1|^2 |d2|^2, i.e. sin(angle) > eps (machine epsilon of S). This is
///    scale free (it compares the cross product with the lengths of the segments themselves),
///    and below it the computed cross product is rounding noise (each component carries an
///    error ~eps |d1| |d2|). The four endpoint candidates are exact for parallel segments and
///    within |d1| sin(angle) <= eps |d1| of the minimum below the threshold.
///  - Zero-length segments: n = 0, so the endpoint candidates run, and they reduce to
///    point-segment or point-point (closest_parameter_on_segment's rule).
template <typename S>
ClosestPoints<S> closest_segment_segment(const Vec3<S>& p0, const Vec3<S>& p1, const Vec3<S>& q0, const Vec3<S>& q1) {
  const Vec3<S> d1 = p1 - p0, d2 = q1 - q0;
  const S a = d1.squaredNorm(), e = d2.squaredNorm();
  const Vec3<S> n = d1.cross(d2);
  const S nn = n.squaredNorm();
  const S eps = std::numeric_limits<S>::epsilon();
  if (nn > eps * eps * a * e) {
    const S s = n.dot(d2.cross(p0 - q0)) / nn;
    if (s >= S(0) && s <= S(1)) {
      const Vec3<S> c1 = p0 + s * d1;
      const S t = (c1 - q0).dot(d2) / e;
      if (t >= S(0) && t <= S(1)) return make_closest<S>(c1, q0 + t * d2);
    }
  }
  // The minimum is on a side of the parameter square.
  ClosestPoints<S> best = closest_point_segment(p0, q0, q1);
  best = take_closer(best, closest_point_segment(p1, q0, q1));
  const ClosestPoints<S> r0 = closest_point_segment(q0, p0, p1);
  const ClosestPoints<S> r1 = closest_point_segment(q1, p0, p1);
  best = take_closer(best, ClosestPoints<S>{r0.c2, r0.c1, r0.dist2});
  return take_closer(best, ClosestPoints<S>{r1.c2, r1.c1, r1.dist2});
}

}  // namespace mbgen::collision
