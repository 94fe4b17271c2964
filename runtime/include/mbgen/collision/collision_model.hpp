#pragma once
// The collision side of a robot (DESIGN.md, "Swept-sphere volumes"): one compound of SSV shapes
// per body, fixed in the body frame, and the pairs of compounds a scene checks. Constant, like
// Model; CollisionData<S> (collision_data.hpp) is its work memory. Built by the generator
// library from the description (gen::build_collision_model) or by hand.
#include <array>
#include <string>
#include <vector>

#include "mbgen/index.hpp"
#include "mbgen/spatial/types.hpp"

namespace mbgen::collision {

/// One SSV of a compound: a point, segment or triangle core (1, 2 or 3 of `points`, in the body
/// frame) swept by a sphere of `radius`.
struct Shape {
  enum class Kind { Point, Line, Triangle };
  Kind kind = Kind::Point;
  std::array<Vec3<double>, 3> points{Vec3<double>::Zero(), Vec3<double>::Zero(), Vec3<double>::Zero()};
  double radius = 0.0;
  /// A sphere around the whole volume (body frame): the cores' bounding sphere plus the radius.
  Vec3<double> bound_center = Vec3<double>::Zero();
  double bound_radius = 0.0;
  std::string source;  ///< where it was given (extras file:line or the URDF collision it models)
};

/// The shapes fixed in one body (the links merged into it included), with a bounding sphere.
struct Compound {
  std::string name;  ///< the body's name
  BodyIndex body;
  std::vector<Shape> shapes;
  Vec3<double> bound_center = Vec3<double>::Zero();
  double bound_radius = 0.0;
};

/// Two compounds whose distance the scene needs (indices into CollisionModel::compounds).
struct CollisionPair {
  int first = -1, second = -1;
};

struct CollisionModel {
  std::vector<Compound> compounds;
  std::vector<CollisionPair> pairs;
};

/// The number of core vertices of a shape (of `points` in use): 1, 2 or 3.
inline int vertex_count(const Shape& s) { return s.kind == Shape::Kind::Point ? 1 : (s.kind == Shape::Kind::Line ? 2 : 3); }

/// Sets a shape's bounding sphere from its core: the centre of the core's points' bounding box
/// and the largest distance from it to a point, plus the radius.
inline void update_bound(Shape& s) {
  const int n = vertex_count(s);
  Vec3<double> lo = s.points[0], hi = s.points[0];
  for (int k = 1; k < n; ++k) {
    lo = lo.cwiseMin(s.points[static_cast<std::size_t>(k)]);
    hi = hi.cwiseMax(s.points[static_cast<std::size_t>(k)]);
  }
  s.bound_center = 0.5 * (lo + hi);
  double r = 0.0;
  for (int k = 0; k < n; ++k) r = std::max(r, (s.points[static_cast<std::size_t>(k)] - s.bound_center).norm());
  s.bound_radius = r + s.radius;
}

/// Sets a compound's bounding sphere around its shapes' spheres (centre: the middle of their
/// bounding box).
inline void update_bound(Compound& c) {
  if (c.shapes.empty()) return;
  Vec3<double> lo = c.shapes[0].bound_center - Vec3<double>::Constant(c.shapes[0].bound_radius);
  Vec3<double> hi = c.shapes[0].bound_center + Vec3<double>::Constant(c.shapes[0].bound_radius);
  for (const Shape& s : c.shapes) {
    lo = lo.cwiseMin(s.bound_center - Vec3<double>::Constant(s.bound_radius));
    hi = hi.cwiseMax(s.bound_center + Vec3<double>::Constant(s.bound_radius));
  }
  c.bound_center = 0.5 * (lo + hi);
  c.bound_radius = 0.0;
  for (const Shape& s : c.shapes) c.bound_radius = std::max(c.bound_radius, (s.bound_center - c.bound_center).norm() + s.bound_radius);
}

}  // namespace mbgen::collision
