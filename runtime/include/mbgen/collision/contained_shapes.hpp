#pragma once
// Shapes of a compound that lie inside another shape of the same compound, and their removal.
//
// Why: descriptions model a capsule the way ROS tools cannot, as a cylinder with a sphere of its
// radius at each end (franka's panda, Lola's drive rods and housings). Each URDF cylinder becomes
// a line SSV (collision_ssv.cpp), which is already that capsule, so the two spheres add nothing
// to the volume but two more SSV calls per shape of every other compound: Lola's 178 pairs hold
// 711 shape pairs with them, 247 without. A compound's volume is the union of its shapes, so a
// shape inside another one changes no distance: the distance to the union is the least over its
// shapes, and the container's is never larger than the one inside it.
//
// Containment is exact for these volumes: every SSV is convex, and a shape is the convex hull of
// the spheres of radius r around its core's vertices (1, 2 or 3), so it lies inside a convex
// volume exactly when those spheres do, i.e. when each vertex v has
//   dist(v, container's core) + r <= container's radius.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "mbgen/collision/closest_segment.hpp"
#include "mbgen/collision/closest_triangle.hpp"
#include "mbgen/collision/collision_model.hpp"

namespace mbgen::collision {

/// How far a shape may reach outside its container and still be dropped, in metres. Not zero:
/// the sphere at a capsule's end is exactly the capsule's cap, and the description's rotations
/// (a URDF's rpy of 3.14159265359 for pi) move the cap's centre off the segment's end by ~1e-13 m.
/// A dropped shape changes the compound's distances by at most this much.
inline constexpr double kContainmentTolerance = 1e-9;

/// Distance from point p to the core of `s` (both in the same frame).
inline double distance_to_core(const Shape& s, const Vec3<double>& p) {
  const SsvVec3<double> x(p), a(s.points[0]), b(s.points[1]), c(s.points[2]);
  switch (s.kind) {
    case Shape::Kind::Point: return (x - a).norm();
    case Shape::Kind::Line: return std::sqrt(closest_point_segment(x, a, b).dist2);
    case Shape::Kind::Triangle: return std::sqrt(closest_point_triangle(x, a, b, c).dist2);
  }
  return (x - a).norm();  // unreachable: every kind is handled above
}

/// How far `inner` reaches outside `outer` (same frame): the largest over inner's core vertices v
/// of dist(v, outer's core) + inner.radius - outer.radius. At most 0: inner lies inside outer.
inline double protrusion(const Shape& outer, const Shape& inner) {
  double worst = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < vertex_count(inner); ++k)
    worst = std::max(worst, distance_to_core(outer, inner.points[static_cast<std::size_t>(k)]) + inner.radius - outer.radius);
  return worst;
}

/// A shape removed by drop_contained_shapes: its index and its container's, in the compound's
/// shapes as they were given.
struct ContainedShape {
  int shape = -1, container = -1;
  double protrusion = 0.0;  ///< protrusion(container, shape): <= the tolerance
};

/// Removes from `c` every shape that reaches at most `tolerance` outside another of its shapes,
/// and updates its bounding sphere. Shapes are taken in order, each against the shapes not yet
/// removed, so of two equal shapes the later one stays. Returns the removed shapes, in order.
inline std::vector<ContainedShape> drop_contained_shapes(Compound& c, double tolerance = kContainmentTolerance) {
  const int n = static_cast<int>(c.shapes.size());
  std::vector<char> removed(static_cast<std::size_t>(n), 0);
  std::vector<ContainedShape> out;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (j == i || removed[static_cast<std::size_t>(j)]) continue;
      const double reach = protrusion(c.shapes[static_cast<std::size_t>(j)], c.shapes[static_cast<std::size_t>(i)]);
      if (reach <= tolerance) {
        removed[static_cast<std::size_t>(i)] = 1;
        out.push_back({i, j, reach});
        break;
      }
    }
  if (out.empty()) return out;
  std::vector<Shape> kept;
  for (int i = 0; i < n; ++i)
    if (!removed[static_cast<std::size_t>(i)]) kept.push_back(std::move(c.shapes[static_cast<std::size_t>(i)]));
  c.shapes = std::move(kept);
  update_bound(c);
  return out;
}

}  // namespace mbgen::collision
