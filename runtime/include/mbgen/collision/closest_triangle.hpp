#pragma once
// Closest points between a triangle core and a point, a segment or another triangle, and the
// segment-through-triangle (piercing) test. Same rules as closest_segment.hpp: plain templated
// math, branch decisions as comparisons of S in small helpers, no NaN or inf for finite input.
#include <cmath>
#include <limits>

#include "mbgen/collision/closest_segment.hpp"

namespace mbgen::collision {

/// A triangle's normal n (not normalised) and whether the plane it defines is trustworthy.
template <typename S> struct TrianglePlane {
  SsvVec3<S> n;
  S nn;        ///< |n|^2
  bool valid;  ///< false for degenerate triangles (needles, collinear or coincident corners)
};

/// n = (b - a) x (c - a), with two rules:
///  - Degenerate triangle: valid only when |n|^2 > eps^2 |b - a|^2 |c - a|^2, i.e. the sine of
///    the angle at a exceeds eps (machine epsilon of S); below it n is rounding noise. Invalid
///    planes make every routine below fall back to the three edges (a needle behaves as its
///    longest edge, three equal corners as a point), which is within the triangle's height
///    (< eps * longest edge) of the exact answer.
///  - Thin but valid triangle: the rounding error of the cross product (~eps |b-a| |c-a| per
///    component) tilts n about the in-plane axis across the longest edge by ~eps / sin(angle),
///    and a point far along that edge would see its plane distance off by that tilt times the
///    edge length. The component of n along the longest edge, which is exactly zero in exact
///    arithmetic, is therefore projected out; the remaining tilt about the longest edge only
///    acts on offsets across the triangle, which are at most its height.
template <typename S> TrianglePlane<S> triangle_plane(const SsvVec3<S>& a, const SsvVec3<S>& b, const SsvVec3<S>& c) {
  const SsvVec3<S> e0 = b - a, e1 = c - a, e2 = c - b;
  const S l0 = e0.squaredNorm(), l1 = e1.squaredNorm(), l2 = e2.squaredNorm();
  SsvVec3<S> n = e0.cross(e1);
  const SsvVec3<S>& longest = (l0 >= l1 && l0 >= l2) ? e0 : (l1 >= l2 ? e1 : e2);
  const S ll = l0 >= l1 && l0 >= l2 ? l0 : (l1 >= l2 ? l1 : l2);
  const S eps = std::numeric_limits<S>::epsilon();
  const S nn0 = n.squaredNorm();
  const bool valid = nn0 > eps * eps * l0 * l1 && ll > S(0);
  if (valid) n -= (n.dot(longest) / ll) * longest;
  return {n, n.squaredNorm(), valid};
}

/// Whether x, taken to lie in the plane of the triangle, is inside it or on its boundary
/// (signed areas of the three sub-triangles against n; x's offset along n does not matter).
template <typename S>
bool inside_triangle(const SsvVec3<S>& x, const SsvVec3<S>& a, const SsvVec3<S>& b, const SsvVec3<S>& c, const SsvVec3<S>& n) {
  return (b - a).cross(x - a).dot(n) >= S(0) && (c - b).cross(x - b).dot(n) >= S(0) &&
         (a - c).cross(x - c).dot(n) >= S(0);
}

/// Closest points of the point p (core 1) and the triangle a, b, c (core 2), whose plane is
/// `plane` (triangle_plane(a, b, c)). Inside the prism over the triangle: p's projection onto
/// the plane; elsewhere, or for a degenerate triangle, the closest of the three edges.
template <typename S>
ClosestPoints<S> closest_point_triangle(const SsvVec3<S>& p, const SsvVec3<S>& a, const SsvVec3<S>& b, const SsvVec3<S>& c,
                                        const TrianglePlane<S>& plane) {
  if (plane.valid && inside_triangle(p, a, b, c, plane.n))
    return make_closest<S>(p, p - ((p - a).dot(plane.n) / plane.nn) * plane.n);
  ClosestPoints<S> best = closest_point_segment(p, a, b);
  best = take_closer(best, closest_point_segment(p, b, c));
  return take_closer(best, closest_point_segment(p, c, a));
}

template <typename S>
ClosestPoints<S> closest_point_triangle(const SsvVec3<S>& p, const SsvVec3<S>& a, const SsvVec3<S>& b, const SsvVec3<S>& c) {
  return closest_point_triangle(p, a, b, c, triangle_plane(a, b, c));
}

/// Where the segment p0-p1 pierces a triangle: the point x, and the unit normal from the
/// segment's volume to the triangle's volume defined for this case (core distance 0).
template <typename S> struct Piercing {
  bool pierced;
  SsvVec3<S> x;
  SsvVec3<S> normal;
};

/// Piercing test. The segment pierces when its endpoints' signed distances to the plane
/// s0 = (p0 - a).n, s1 = (p1 - a).n do not have the same strict sign, not both zero (a segment
/// in the plane is left to the edge and corner candidates, which find its zero distance), and
/// the crossing point x = p0 + s0 / (s0 - s1) (p1 - p0) is inside the triangle. Degenerate
/// triangles are never pierced (their edges find the contact).
/// Normal rule (core distance 0, so there is no direction between the cores): +-n/|n|, the
/// sign chosen so that moving the segment by -normal along the triangle normal is the shorter
/// way out: -sign of the deeper endpoint's signed distance (the endpoint with the larger |s|,
/// s1 on a tie). It is the same direction a volume pushed apart along the triangle normal takes,
/// so it points from the segment's volume to the triangle's.
template <typename S>
Piercing<S> pierce_segment_triangle(const SsvVec3<S>& p0, const SsvVec3<S>& p1, const SsvVec3<S>& a, const SsvVec3<S>& b,
                                    const SsvVec3<S>& c, const TrianglePlane<S>& plane) {
  Piercing<S> out{false, p0, SsvVec3<S>::UnitZ()};
  if (!plane.valid) return out;
  const S s0 = (p0 - a).dot(plane.n), s1 = (p1 - a).dot(plane.n);
  if ((s0 > S(0) && s1 > S(0)) || (s0 < S(0) && s1 < S(0)) || s0 == s1) return out;
  const SsvVec3<S> x = p0 + (s0 / (s0 - s1)) * (p1 - p0);
  if (!inside_triangle(x, a, b, c, plane.n)) return out;
  using std::abs;
  using std::sqrt;
  const S deep = abs(s1) >= abs(s0) ? s1 : s0;
  const SsvVec3<S> w = plane.n / plane.n.cwiseAbs().maxCoeff();  // rescaled: |n|^2 may be denormal
  const SsvVec3<S> unit = w / sqrt(w.squaredNorm());
  return {true, x, deep > S(0) ? SsvVec3<S>(-unit) : unit};
}

/// Closest points of the segment p0-p1 (core 1) and the triangle a, b, c (core 2); `pierce`
/// tells whether the segment goes through the triangle (then c1 == c2 == the crossing point).
/// Without piercing, the closest pair of two convex polytopes involves a vertex or two edges:
/// a segment endpoint against the triangle, or the segment against one of the triangle's edges.
template <typename S> struct SegmentTriangleClosest {
  ClosestPoints<S> points;
  Piercing<S> pierce;
};

template <typename S>
SegmentTriangleClosest<S> closest_segment_triangle(const SsvVec3<S>& p0, const SsvVec3<S>& p1, const SsvVec3<S>& a,
                                                   const SsvVec3<S>& b, const SsvVec3<S>& c,
                                                   const TrianglePlane<S>& plane) {
  const Piercing<S> pierce = pierce_segment_triangle(p0, p1, a, b, c, plane);
  if (pierce.pierced) return {ClosestPoints<S>{pierce.x, pierce.x, S(0)}, pierce};
  ClosestPoints<S> best = closest_point_triangle(p0, a, b, c, plane);
  best = take_closer(best, closest_point_triangle(p1, a, b, c, plane));
  best = take_closer(best, closest_segment_segment(p0, p1, a, b));
  best = take_closer(best, closest_segment_segment(p0, p1, b, c));
  best = take_closer(best, closest_segment_segment(p0, p1, c, a));
  return {best, pierce};
}

/// Closest points of the triangles a0 b0 c0 (core 1) and a1 b1 c1 (core 2). If an edge of one
/// pierces the other, the cores intersect (core distance 0, normal by pierce_segment_triangle's
/// rule with the roles of the volumes kept: an edge of triangle 2 piercing triangle 1 gives the
/// negated normal). Otherwise the closest pair is a corner against the other triangle or two
/// edges: 3 + 3 point-triangle and 9 segment-segment candidates. Coplanar overlapping triangles
/// are found by those candidates (an edge crossing or a corner inside, at distance 0).
template <typename S>
SegmentTriangleClosest<S> closest_triangle_triangle(const SsvVec3<S>& a0, const SsvVec3<S>& b0, const SsvVec3<S>& c0,
                                                    const SsvVec3<S>& a1, const SsvVec3<S>& b1, const SsvVec3<S>& c1) {
  const TrianglePlane<S> plane0 = triangle_plane(a0, b0, c0), plane1 = triangle_plane(a1, b1, c1);
  const SsvVec3<S>* t0[3] = {&a0, &b0, &c0};
  const SsvVec3<S>* t1[3] = {&a1, &b1, &c1};
  for (int i = 0; i < 3; ++i) {
    const Piercing<S> p = pierce_segment_triangle(*t0[i], *t0[(i + 1) % 3], a1, b1, c1, plane1);
    if (p.pierced) return {ClosestPoints<S>{p.x, p.x, S(0)}, p};
  }
  for (int i = 0; i < 3; ++i) {
    Piercing<S> p = pierce_segment_triangle(*t1[i], *t1[(i + 1) % 3], a0, b0, c0, plane0);
    if (p.pierced) {
      p.normal = -p.normal;
      return {ClosestPoints<S>{p.x, p.x, S(0)}, p};
    }
  }
  ClosestPoints<S> best = closest_point_triangle(a0, a1, b1, c1, plane1);
  best = take_closer(best, closest_point_triangle(b0, a1, b1, c1, plane1));
  best = take_closer(best, closest_point_triangle(c0, a1, b1, c1, plane1));
  for (int i = 0; i < 3; ++i) {
    const ClosestPoints<S> r = closest_point_triangle(*t1[i], a0, b0, c0, plane0);
    best = take_closer(best, ClosestPoints<S>{r.c2, r.c1, r.dist2});
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      best = take_closer(best, closest_segment_segment(*t0[i], *t0[(i + 1) % 3], *t1[j], *t1[(j + 1) % 3]));
  return {best, Piercing<S>{false, best.c1, SsvVec3<S>::UnitZ()}};
}

}  // namespace mbgen::collision
