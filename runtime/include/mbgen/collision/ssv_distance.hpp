#pragma once
// Distances between swept-sphere volumes: the six pair kinds PP, PL, PT, LL, LT, TT.
//
//   SsvDistance<S> ssv_distance(const PointSsv<S>&, const PointSsv<S>&);       // PP
//   SsvDistance<S> ssv_distance(const PointSsv<S>&, const LineSsv<S>&);        // PL
//   SsvDistance<S> ssv_distance(const PointSsv<S>&, const TriangleSsv<S>&);    // PT
//   SsvDistance<S> ssv_distance(const LineSsv<S>&, const LineSsv<S>&);         // LL
//   SsvDistance<S> ssv_distance(const LineSsv<S>&, const TriangleSsv<S>&);     // LT
//   SsvDistance<S> ssv_distance(const TriangleSsv<S>&, const TriangleSsv<S>&); // TT
//
// Result conventions in ssv.hpp (SsvDistance): distance = core distance - r1 - r2, witness
// points on the surfaces, unit normal from volume 1 to volume 2. Core closest points come from
// closest_segment.hpp and closest_triangle.hpp, whose comments state the robustness rules.
//
// Normal when the cores touch (core distance at rounding level, see finish()): the direction
// between the cores is noise or undefined, so each pair kind uses a fixed rule instead:
//   PP  +z (0, 0, 1).
//   PL  a unit vector perpendicular to the segment (perpendicular()), +z if it has zero length.
//   PT  the triangle's unit normal (b - a) x (c - a); a degenerate triangle (sine of the angle
//       at a at most eps): perpendicular to b - a (to c - a when a == b); all corners equal: +z.
//   LL  (p1 - p0) x (q1 - q0) normalised (crossing segments); parallel: perpendicular to the
//       first segment (or the second if the first has zero length); both points: +z.
//   LT  segment piercing the triangle: the triangle normal oriented by
//       pierce_segment_triangle's rule (the shorter way out); touching otherwise (e.g. a segment
//       lying in the triangle): the PT rule for the triangle.
//   TT  an edge piercing the other triangle: as LT (negated when the edge is triangle 2's);
//       otherwise the PT rule applied to triangle 2.
// These normals are always unit and finite; unlike the normal between apart cores they do not
// in general flip when the arguments are swapped (LL's cross product does).
#include <cmath>
#include <limits>

#include "mbgen/collision/closest_segment.hpp"
#include "mbgen/collision/closest_triangle.hpp"
#include "mbgen/collision/ssv.hpp"

namespace mbgen::collision {

namespace detail {

template <typename S> S max_abs(const SsvVec3<S>& v) {
  using std::abs;
  const S x = abs(v.x()), y = abs(v.y()), z = abs(v.z());
  return x >= y ? (x >= z ? x : z) : (y >= z ? y : z);
}

/// v / |v| for v != 0, rescaled first so that |v|^2 neither underflows nor overflows.
template <typename S> SsvVec3<S> normalized(const SsvVec3<S>& v) {
  using std::sqrt;
  const SsvVec3<S> w = v / max_abs(v);
  return w / sqrt(w.squaredNorm());
}

/// A unit vector perpendicular to u (u != 0): u x e_k for the axis k of u's smallest component.
template <typename S> SsvVec3<S> perpendicular(const SsvVec3<S>& u) {
  using std::abs;
  const SsvVec3<S> w = u / max_abs(u);
  const S x = abs(w.x()), y = abs(w.y()), z = abs(w.z());
  if (x <= y && x <= z) return normalized(SsvVec3<S>(S(0), w.z(), -w.y()));
  if (y <= z) return normalized(SsvVec3<S>(-w.z(), S(0), w.x()));
  return normalized(SsvVec3<S>(w.y(), -w.x(), S(0)));
}

/// The fallback normal of two directions u, v (either may be zero): u x v normalised when the
/// two are not parallel (sine of their angle above eps), else perpendicular to u, else to v,
/// else +z.
template <typename S> SsvVec3<S> fallback_normal(const SsvVec3<S>& u, const SsvVec3<S>& v) {
  const S mu = max_abs(u), mv = max_abs(v);
  if (mu > S(0) && mv > S(0)) {
    const SsvVec3<S> uu = u / mu, vv = v / mv;
    const SsvVec3<S> w = uu.cross(vv);
    const S eps = std::numeric_limits<S>::epsilon();
    if (w.squaredNorm() > eps * eps * uu.squaredNorm() * vv.squaredNorm()) return normalized(w);
  }
  if (mu > S(0)) return perpendicular(u);
  if (mv > S(0)) return perpendicular(v);
  return SsvVec3<S>::UnitZ();
}

/// The result from the closest core points. The cores count as touching when
/// |c2 - c1| <= 16 eps * scale (scale: the largest coordinate magnitude of the inputs, i.e. the
/// rounding noise of the closest points) or when |c2 - c1|^2 is below min / eps (so that the
/// direction is never computed from denormals); then `fallback()` gives the normal.
template <typename S, typename Fallback>
SsvDistance<S> finish(const ClosestPoints<S>& c, S r1, S r2, S scale, Fallback fallback) {
  using std::sqrt;
  const S eps = std::numeric_limits<S>::epsilon();
  const S noise = S(16) * eps * scale;
  const S tiny = std::numeric_limits<S>::min() / eps;
  const S threshold = noise * noise > tiny ? noise * noise : tiny;
  SsvDistance<S> out;
  out.core1 = c.c1;
  out.core2 = c.c2;
  const SsvVec3<S> diff = c.c2 - c.c1;
  out.core_distance = sqrt(c.dist2);
  // 1 / |diff| as |diff| * (1 / |diff|^2): the square root and the division both start from
  // dist2 and run in parallel instead of one after the other (dist2 > threshold >= min / eps, so
  // 1 / dist2 is finite; ~1.5 ulp instead of 1).
  out.normal = c.dist2 > threshold ? SsvVec3<S>(diff * (out.core_distance * (S(1) / c.dist2))) : fallback();
  out.distance = out.core_distance - r1 - r2;
  out.point1 = c.c1 + r1 * out.normal;
  out.point2 = c.c2 - r2 * out.normal;
  return out;
}

/// The largest coordinate magnitude of the points (element-wise max, then one reduction).
template <typename S> SsvVec3<S> abs_max(const SsvVec3<S>& p) { return p.cwiseAbs(); }
template <typename S, typename... More> SsvVec3<S> abs_max(const SsvVec3<S>& p, const More&... more) {
  return p.cwiseAbs().cwiseMax(abs_max(more...));
}
template <typename S, typename... More> S scale_of(const SsvVec3<S>& p, const More&... more) {
  return abs_max(p, more...).maxCoeff();
}

/// The PT fallback: the triangle normal, or perpendicular to an edge, or +z.
template <typename S> SsvVec3<S> triangle_fallback(const SsvVec3<S>& a, const SsvVec3<S>& b, const SsvVec3<S>& c) {
  return fallback_normal<S>(b - a, c - a);
}

}  // namespace detail

template <typename S> SsvDistance<S> ssv_distance(const PointSsv<S>& x, const PointSsv<S>& y) {
  return detail::finish(make_closest<S>(x.center, y.center), x.radius, y.radius,
                        detail::scale_of(x.center, y.center), [] { return SsvVec3<S>(SsvVec3<S>::UnitZ()); });
}

template <typename S> SsvDistance<S> ssv_distance(const PointSsv<S>& x, const LineSsv<S>& y) {
  return detail::finish(closest_point_segment(x.center, y.p0, y.p1), x.radius, y.radius,
                        detail::scale_of(x.center, y.p0, y.p1),
                        [&] { return detail::fallback_normal<S>(y.p1 - y.p0, SsvVec3<S>::Zero()); });
}

template <typename S> SsvDistance<S> ssv_distance(const PointSsv<S>& x, const TriangleSsv<S>& y) {
  return detail::finish(closest_point_triangle(x.center, y.a, y.b, y.c), x.radius, y.radius,
                        detail::scale_of(x.center, y.a, y.b, y.c),
                        [&] { return detail::triangle_fallback(y.a, y.b, y.c); });
}

template <typename S> SsvDistance<S> ssv_distance(const LineSsv<S>& x, const LineSsv<S>& y) {
  return detail::finish(closest_segment_segment_inline(x.p0, x.p1, y.p0, y.p1), x.radius, y.radius,
                        detail::scale_of(x.p0, x.p1, y.p0, y.p1),
                        [&] { return detail::fallback_normal<S>(x.p1 - x.p0, y.p1 - y.p0); });
}

template <typename S> SsvDistance<S> ssv_distance(const LineSsv<S>& x, const TriangleSsv<S>& y) {
  const SegmentTriangleClosest<S> c = closest_segment_triangle(x.p0, x.p1, y.a, y.b, y.c, triangle_plane(y.a, y.b, y.c));
  return detail::finish(c.points, x.radius, y.radius, detail::scale_of(x.p0, x.p1, y.a, y.b, y.c), [&] {
    return c.pierce.pierced ? c.pierce.normal : detail::triangle_fallback(y.a, y.b, y.c);
  });
}

template <typename S> SsvDistance<S> ssv_distance(const TriangleSsv<S>& x, const TriangleSsv<S>& y) {
  const SegmentTriangleClosest<S> c = closest_triangle_triangle(x.a, x.b, x.c, y.a, y.b, y.c);
  return detail::finish(c.points, x.radius, y.radius, detail::scale_of(x.a, x.b, x.c, y.a, y.b, y.c), [&] {
    return c.pierce.pierced ? c.pierce.normal : detail::triangle_fallback(y.a, y.b, y.c);
  });
}

}  // namespace mbgen::collision
