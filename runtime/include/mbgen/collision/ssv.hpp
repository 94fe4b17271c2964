#pragma once
// Swept-sphere volumes (SSVs): a core (point, segment or triangle) swept by a sphere of radius r.
// Header-only, templated on the scalar S (float, double), no heap, no exceptions, no virtuals:
// generated code includes these headers and calls the pair distances of ssv_distance.hpp.
// Conventions (docs/ssv.md): all points in one frame (the caller's, usually the world frame).
#include "mbgen/collision/vec3.hpp"

namespace mbgen::collision {

/// Point-SSV (a sphere): centre and radius.
template <typename S> struct PointSsv {
  SsvVec3<S> center;
  S radius;
};

/// Line-SSV (a capsule): the segment p0-p1 swept by a sphere of radius `radius`. p0 == p1 is
/// allowed (a sphere).
template <typename S> struct LineSsv {
  SsvVec3<S> p0, p1;
  S radius;
};

/// Triangle-SSV: the triangle a, b, c swept by a sphere of radius `radius`. Degenerate
/// triangles (collinear or coincident corners) are allowed: they behave as their longest edge
/// or as a point.
template <typename S> struct TriangleSsv {
  SsvVec3<S> a, b, c;
  S radius;
};

/// Distance between two SSVs, volume 1 and volume 2 (the arguments in order).
///
///   distance  = core_distance - r1 - r2: positive when apart, negative when the volumes overlap
///               (a negative value is not a penetration depth once the cores themselves touch).
///   core1/2   closest points of the cores; |core2 - core1| == core_distance.
///   normal    unit vector from volume 1 to volume 2: (core2 - core1) / core_distance when the
///             cores are apart by more than rounding noise, else a documented fallback
///             (ssv_distance.hpp). Swapping the arguments negates it (when the cores are apart).
///   point1/2  witness points on the surfaces: point1 = core1 + r1 normal,
///             point2 = core2 - r2 normal, so point2 - point1 == distance * normal.
template <typename S> struct SsvDistance {
  S distance;
  S core_distance;
  SsvVec3<S> normal;
  SsvVec3<S> point1, point2;
  SsvVec3<S> core1, core2;
};

}  // namespace mbgen::collision
