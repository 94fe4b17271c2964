#pragma once
// Closest points between cores made of points and segments: point-segment and segment-segment.
// Every branch decision is a comparison of S values in a small helper (clamp01, take_closer), so
// that the arithmetic stays plain templated math (DESIGN.md "One implementation of the math").
// No NaN or inf for finite inputs whose fourth powers do not overflow (squared areas such as
// |d1 x d2|^2 are formed): coordinates below 1e75 in double, 1e9 in float.
#include <limits>

#include "mbgen/collision/vec3.hpp"

// Speed: GCC does not inline closest_segment_segment into the capsule-capsule distance by its size
// heuristics, and the 56-byte ClosestPoints then goes through memory: forcing it saves ~10 % of an
// LL call (bench ssv_ll). Other compilers: plain inline.
#if defined(__GNUC__)
#define MBGEN_SSV_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define MBGEN_SSV_ALWAYS_INLINE inline
#endif

namespace mbgen::collision {

/// A closest pair: c1 on core 1, c2 on core 2, and dist2 = |c2 - c1|^2.
template <typename S> struct ClosestPoints {
  SsvVec3<S> c1, c2;
  S dist2;
};

template <typename S> ClosestPoints<S> make_closest(const SsvVec3<S>& c1, const SsvVec3<S>& c2) {
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
template <typename S> S closest_parameter_on_segment(const SsvVec3<S>& p, const SsvVec3<S>& a, const SsvVec3<S>& b) {
  const SsvVec3<S> d = b - a;
  const S dd = d.squaredNorm();
  return dd > S(0) ? clamp01((p - a).dot(d) / dd) : S(0);
}

/// 1 / dd for a squared length dd that is a normal number (then finite: dd >= min), else 0.
template <typename S> S reciprocal(S dd) { return dd >= std::numeric_limits<S>::min() ? S(1) / dd : S(0); }

/// dot / dd, a projection parameter before clamping, given inv = reciprocal(dd): dot * inv for
/// normal dd, dot / dd for denormal dd (whose reciprocal would overflow), 0 for dd = 0 (the
/// zero-length rule of closest_parameter_on_segment).
template <typename S> S projection(S dot, S dd, S inv) {
  return dd >= std::numeric_limits<S>::min() ? dot * inv : (dd > S(0) ? dot / dd : S(0));
}

/// Closest points of a point p (core 1) and the segment a-b (core 2).
template <typename S> ClosestPoints<S> closest_point_segment(const SsvVec3<S>& p, const SsvVec3<S>& a, const SsvVec3<S>& b) {
  const S t = closest_parameter_on_segment(p, a, b);
  return make_closest<S>(p, a + t * (b - a));
}

/// Closest points of the segments p0-p1 (core 1) and q0-q1 (core 2), parameters s, t in [0, 1].
///
/// Ericson's clamping scheme (Real-Time Collision Detection 5.1.9) on the convex squared
/// distance |p0 + s d1 - q0 - t d2|^2: s from the infinite lines, clamped; t of the point at s,
/// and if t leaves [0, 1] it is clamped and s recomputed for it. Robustness rules:
///  - Line-line parameter: s = (n . (d2 x r)) / |n|^2 with n = d1 x d2, r = p0 - q0. The
///    Lagrange identity turns Ericson's (b f - c e) / (a e - b^2) into cross products: a e - b^2
///    cancels catastrophically for small angles (its error is ~eps a e, so sin^2 of the angle is
///    known only to ~eps absolute), |d1 x d2|^2 keeps a relative error ~eps / sin(angle).
///  - Parallel and nearly parallel: s comes from the lines only when
///    |d1 x d2|^2 > eps^2 |d1|^2 |d2|^2, i.e. sin(angle) > eps (machine epsilon of S). The test is
///    scale free (the cross product against the segments' own lengths, not a fixed 1e-6), and
///    below it the computed cross product is rounding noise. Then s = 0 and the clamping steps
///    find a closest pair, which is exact for parallel segments (any pair in the overlap is
///    closest) and within |d1| sin(angle) <= eps |d1| of the minimum below the threshold.
///    Above the threshold, s's error slides the pair along the valley of the near-parallel
///    pair, whose slope is sin(angle): the distance error stays ~eps |d1|.
///  - Zero-length segments: |d1|^2 = 0 or |d2|^2 = 0 gives n = 0, so s = 0. A zero-length
///    second segment takes the clamping branch (t = 0, s = the point q0 projected onto the
///    first), a zero-length first one stays at s = 0 (t = p0 projected onto the second), so
///    point-segment and point-point come out of the same steps (closest_parameter_on_segment's
///    rule).
///  - Projections on scalars: with b = d1 . d2, c = d1 . r, f = d2 . r formed once, t of the
///    point at s is (b s + f) / e and s of the point at t is (b t - c) / a (the projections of
///    p0 + s d1 onto line 2 and of q0 + t d2 onto line 1, expanded). Their rounding is
///    ~eps (|r| + |d1|) |d2| in the numerator, i.e. the point moves along its segment by
///    ~eps (|r| + |d1|): the same order as forming the point first and projecting it (whose
///    rounding also carries eps times the absolute coordinates). Only the returned points are
///    formed, once.
///
/// Speed (bench ssv_ll, ~3-4 of an LL call's ~25 ns): the scalar projections replace two
/// point-then-dot-product steps (a point, a difference and a dot product, ~21 cycles of latency
/// each) by a multiply-add (~9), and the two reciprocals run in parallel with the cross
/// products (reciprocal(): same zero-length rule, exact division kept for denormals). Measured
/// and rejected: branch-free clamps (SSE max/min) and an unconditional recompute of s (no branch
/// at all) were 10-40 % slower, on the bench's 64-pair pool and on a 4096-pair pool alike: the
/// predicted branches let the processor start the next step before the clamped value is known,
/// the selects put every step on the dependency chain.
template <typename S>
MBGEN_SSV_ALWAYS_INLINE ClosestPoints<S> closest_segment_segment_inline(const SsvVec3<S>& p0, const SsvVec3<S>& p1,
                                                                       const SsvVec3<S>& q0, const SsvVec3<S>& q1) {
  const SsvVec3<S> d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const S a = d1.squaredNorm(), e = d2.squaredNorm();
  const S b = d1.dot(d2), c = d1.dot(r), f = d2.dot(r);
  // Multiplied instead of divided by in the projections below (off the dependency chain).
  const S inv_a = reciprocal(a), inv_e = reciprocal(e);
  const SsvVec3<S> n = d1.cross(d2);
  const S nn = n.squaredNorm();
  const S eps = std::numeric_limits<S>::epsilon();
  S s = nn > eps * eps * a * e ? clamp01(n.dot(d2.cross(r)) / nn) : S(0);
  S t = projection(b * s + f, e, inv_e);
  if (!(e > S(0)) || t < S(0) || t > S(1)) {
    t = clamp01(t);
    s = clamp01(projection(b * t - c, a, inv_a));
  }
  return make_closest<S>(p0 + s * d1, q0 + t * d2);
}

/// The same, left to the compiler's inlining judgement (the triangle routines call it up to nine
/// times); capsule-capsule calls the forced-inline form above.
template <typename S>
ClosestPoints<S> closest_segment_segment(const SsvVec3<S>& p0, const SsvVec3<S>& p1, const SsvVec3<S>& q0, const SsvVec3<S>& q1) {
  return closest_segment_segment_inline(p0, p1, q0, q1);
}

}  // namespace mbgen::collision
