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
template <typename S> S sphere_lower_bound(const SsvVec3<S>& ca, S ra, const SsvVec3<S>& cb, S rb) {
  using std::abs;
  S scale = ra + rb;
  for (int i = 0; i < 3; ++i) scale += (abs(ca[i]) > abs(cb[i]) ? abs(ca[i]) : abs(cb[i]));
  return (cb - ca).norm() - ra - rb - S(32) * std::numeric_limits<S>::epsilon() * scale;
}

/// Running best over the shape pairs (i, j) of compound a (volume 1) and compound b (volume 2).
template <typename S> struct ClosestShapes {
  SsvDistance<S> result;
  int shape_first = -1, shape_second = -1;  ///< the closest shapes so far (-1: none yet)
  int shape_pairs_computed = 0;              ///< shape pairs whose bounding spheres could not rule them out

  /// Whether shapes with bounding spheres (ca, ra) and (cb, rb), placed in the world, could beat
  /// the best so far (always true for the first pair).
  bool worth(const SsvVec3<S>& ca, S ra, const SsvVec3<S>& cb, S rb) const {
    return shape_first < 0 || (cb - ca).norm() - ra - rb < result.distance;
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
