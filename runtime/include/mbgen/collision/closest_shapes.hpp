#pragma once
// The closest pair among the shape pairs of two compounds, with the bounding-sphere skip: a shape
// pair whose bounding spheres are at least the best distance so far apart cannot be closer and
// is not computed. Shared by the generic compound_distance (compound_distance.hpp) and the
// generated self_distances, which unrolls the shape pairs and calls `worth` and `take` in the
// same order: one implementation of the skip, so both pick the same closest shapes.
// POD only (no Eigen, no heap): generated and firmware code include it.
#include <cmath>
#include <limits>

#include "mbgen/collision/ssv.hpp"

namespace mbgen::collision {

/// to = from, member by member. Why not `to = from`: a whole-struct copy (68 bytes in float) is
/// lowered by GCC to a memcpy call on bare-metal targets, which firmware objects must not need
/// (tests/firmware/check_firmware.sh); 12-byte members are copied inline.
template <typename S> void assign(SsvDistance<S>& to, const SsvDistance<S>& from) {
  to.distance = from.distance;
  to.core_distance = from.core_distance;
  to.normal = from.normal;
  to.point1 = from.point1;
  to.point2 = from.point2;
  to.core1 = from.core1;
  to.core2 = from.core2;
}

/// The result of ssv_distance(y, x) turned into that of x vs y: witnesses and cores swapped,
/// normal negated. For shape pairs given in the order the primitives do not provide (a line or
/// triangle against a point, a triangle against a line).
template <typename S> SsvDistance<S> reversed(const SsvDistance<S>& r) {
  SsvDistance<S> out;
  out.distance = r.distance;
  out.core_distance = r.core_distance;
  out.normal = -r.normal;
  out.point1 = r.point2;
  out.point2 = r.point1;
  out.core1 = r.core2;
  out.core2 = r.core1;
  return out;
}

/// A lower bound of the distance of two volumes inside the spheres (ca, ra) and (cb, rb), placed in
/// the world, that never exceeds their computed distance: the spheres' distance less 32 eps times
/// the coordinates' scale, the rounding of this expression and of the SSV primitives' (16 u x
/// scale, docs/ssv.md). Without the allowance a sphere that is the volume itself (a point SSV)
/// gave a bound 1e-17 above the distance, and the near set lost a pair at the threshold.
template <typename S> S sphere_allowance(const SsvVec3<S>& ca, S ra, const SsvVec3<S>& cb, S rb) {
  using std::abs;
  S scale = ra + rb;
  for (int i = 0; i < 3; ++i) scale += (abs(ca[i]) > abs(cb[i]) ? abs(ca[i]) : abs(cb[i]));
  return S(32) * std::numeric_limits<S>::epsilon() * scale;
}
template <typename S> S sphere_lower_bound(const SsvVec3<S>& ca, S ra, const SsvVec3<S>& cb, S rb) {
  return (cb - ca).norm() - ra - rb - sphere_allowance<S>(ca, ra, cb, rb);
}

/// Running best over the shape pairs (i, j) of compound a (volume 1) and compound b (volume 2).
///
/// With a limit (the near set's threshold), a shape pair whose bounding spheres are at least the
/// limit apart (sphere_lower_bound) is not computed at all: it cannot make the compounds near,
/// and the pair's distance is wanted exactly only when it is below the limit. Then either some
/// computed shape pair lies below the limit (within_limit(): the result is the exact closest
/// pair, as without the limit, since every skipped shape pair is farther), or the compounds are
/// farther than the limit and lower_bound() is what is known: the least of the computed
/// distances and the skipped pairs' bounds. On Lola standing at 5 cm this spares about a third of
/// the near set's SSV calls (docs/ssv.md).
template <typename S> struct ClosestShapes {
  SsvDistance<S> result;
  int shape_first = -1, shape_second = -1;  ///< the closest shapes so far (-1: none yet)
  int shape_pairs_computed = 0;              ///< shape pairs whose bounding spheres could not rule them out
  bool limited = false;                      ///< whether `limit` applies
  S limit = S(0);                            ///< shape pairs bounded at least this far apart are skipped
  S skipped_bound = std::numeric_limits<S>::infinity();  ///< the least bound of the pairs skipped for the limit

  // result.distance starts at infinity (no pair yet): g++ cannot see that a result is read only
  // once a pair was taken, and warns where the near set's branches hide it.
  ClosestShapes() { result.distance = std::numeric_limits<S>::infinity(); }
  /// With limited, skip the shape pairs whose bounding spheres are at least `limit` apart.
  ClosestShapes(bool limited_, S limit_) : limited(limited_), limit(limit_) { result.distance = std::numeric_limits<S>::infinity(); }

  /// Whether shapes with bounding spheres (ca, ra) and (cb, rb), placed in the world, could beat
  /// the best so far (always true for the first pair computed) and, with a limit, could lie
  /// within it.
  bool worth(const SsvVec3<S>& ca, S ra, const SsvVec3<S>& cb, S rb) {
    const S gap = (cb - ca).norm() - ra - rb;
    if (limited) {
      const S bound = gap - sphere_allowance<S>(ca, ra, cb, rb);  // sphere_lower_bound, one square root
      if (bound >= limit) {
        if (bound < skipped_bound) skipped_bound = bound;
        return false;
      }
    }
    return shape_first < 0 || gap < result.distance;
  }
  /// Whether a computed shape pair lies within the limit (always, without one, once a pair is
  /// computed). A NaN distance counts as within: it is reported, not hidden.
  bool within_limit() const { return shape_first >= 0 && !(limited && result.distance >= limit); }
  /// A lower bound of the compounds' distance (their distance when within_limit()).
  S lower_bound() const {
    if (shape_first < 0) return skipped_bound;
    return result.distance < skipped_bound ? result.distance : skipped_bound;
  }
  /// Keeps d if it is the first or strictly closer (the earlier pair on a tie).
  void take(const SsvDistance<S>& d, int i, int j) {
    ++shape_pairs_computed;
    if (shape_first < 0 || d.distance < result.distance) {
      assign(result, d);
      shape_first = i;
      shape_second = j;
    }
  }
};

}  // namespace mbgen::collision
