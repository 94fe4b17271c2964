#pragma once
// Distances between compounds of SSV shapes placed by body poses, and the distance Jacobians of a
// scene's pairs. Generic (interpreted) runtime, templated on the scalar.
//
// Compound vs compound: bounding spheres first. A shape pair whose spheres are farther apart
// than the best distance found so far cannot be closest and is skipped; the answer is the same
// as trying every shape pair (tests/test_compound_distance.cpp checks it).
#include <algorithm>
#include <cmath>

#include "mbgen/algorithm/jacobian.hpp"
#include "mbgen/collision/closest_shapes.hpp"
#include "mbgen/collision/collision_model.hpp"
#include "mbgen/collision/ssv_distance.hpp"

namespace mbgen::collision {

namespace detail {
template <typename S> Vec3<S> place(const SE3<S>& X, const Vec3<double>& p) { return X.act(p.template cast<S>()); }

/// The distance of shapes a (volume 1) and b (volume 2) placed by X_Wa and X_Wb.
template <typename S> SsvDistance<S> shape_distance(const Shape& a, const SE3<S>& X_Wa, const Shape& b, const SE3<S>& X_Wb) {
  const S ra(a.radius), rb(b.radius);
  auto p = [](const Shape& s, const SE3<S>& X, int k) { return place<S>(X, s.points[static_cast<std::size_t>(k)]); };
  using K = Shape::Kind;
  const PointSsv<S> pa{p(a, X_Wa, 0), ra}, pb{p(b, X_Wb, 0), rb};
  const LineSsv<S> la{p(a, X_Wa, 0), p(a, X_Wa, 1), ra}, lb{p(b, X_Wb, 0), p(b, X_Wb, 1), rb};
  switch (a.kind) {
    case K::Point:
      switch (b.kind) {
        case K::Point: return ssv_distance(pa, pb);
        case K::Line: return ssv_distance(pa, lb);
        case K::Triangle: return ssv_distance(pa, TriangleSsv<S>{p(b, X_Wb, 0), p(b, X_Wb, 1), p(b, X_Wb, 2), rb});
      }
      break;
    case K::Line:
      switch (b.kind) {
        case K::Point: return reversed(ssv_distance(pb, la));
        case K::Line: return ssv_distance(la, lb);
        case K::Triangle: return ssv_distance(la, TriangleSsv<S>{p(b, X_Wb, 0), p(b, X_Wb, 1), p(b, X_Wb, 2), rb});
      }
      break;
    case K::Triangle: {
      const TriangleSsv<S> ta{p(a, X_Wa, 0), p(a, X_Wa, 1), p(a, X_Wa, 2), ra};
      switch (b.kind) {
        case K::Point: return reversed(ssv_distance(pb, ta));
        case K::Line: return reversed(ssv_distance(lb, ta));
        case K::Triangle: return ssv_distance(ta, TriangleSsv<S>{p(b, X_Wb, 0), p(b, X_Wb, 1), p(b, X_Wb, 2), rb});
      }
      break;
    }
  }
  return ssv_distance(pa, pb);  // unreachable: every kind is handled above
}
}  // namespace detail

/// The closest shapes of two compounds and their distance (closest_shapes.hpp).
template <typename S> using CompoundDistance = ClosestShapes<S>;

/// Distance from compound a (placed by X_Wa) to compound b (placed by X_Wb); normal from a to b.
/// Both compounds must have at least one shape. The generated self_distances unrolls this loop.
/// With a limit (compute_near_distances' threshold), shape pairs whose bounding spheres are at
/// least that far apart are skipped (ClosestShapes): the result is exact when within_limit(). A
/// single shape pair is always computed: its compounds' spheres are the test that counts (the
/// generated code places no sphere of its own for it).
template <typename S>
CompoundDistance<S> compound_distance(const Compound& a, const SE3<S>& X_Wa, const Compound& b, const SE3<S>& X_Wb,
                                      bool limited = false, S limit = S(0)) {
  CompoundDistance<S> best(limited, limit);
  if (a.shapes.size() == 1 && b.shapes.size() == 1) {
    best.take(detail::shape_distance<S>(a.shapes[0], X_Wa, b.shapes[0], X_Wb), 0, 0);
    return best;
  }
  for (std::size_t i = 0; i < a.shapes.size(); ++i) {
    const Vec3<S> ca = detail::place<S>(X_Wa, a.shapes[i].bound_center);
    for (std::size_t j = 0; j < b.shapes.size(); ++j) {
      const Vec3<S> cb = detail::place<S>(X_Wb, b.shapes[j].bound_center);
      if (!best.worth(ca, S(a.shapes[i].bound_radius), cb, S(b.shapes[j].bound_radius))) continue;
      best.take(detail::shape_distance<S>(a.shapes[i], X_Wa, b.shapes[j], X_Wb), static_cast<int>(i), static_cast<int>(j));
    }
  }
  return best;
}

/// Work memory and results of a scene's distances: one entry per pair of the CollisionModel.
template <typename S> struct CollisionData {
  explicit CollisionData(const Model& model, const CollisionModel& cm)
      : distances(cm.pairs.size()),
        jacobian(MatX<S>::Zero(static_cast<int>(cm.pairs.size()), model.nv())),
        near(cm.pairs.size(), 0) {}
  /// Per pair, normal from `first` to `second`. For a far pair (compute_near_distances) only
  /// `result.distance` counts: a lower bound of its distance (its closest shapes, shape_first -1
  /// when its bounding spheres were far enough to skip them).
  std::vector<CompoundDistance<S>> distances;
  MatX<S> jacobian;  ///< pairs x nv: row k is d distance_k / d q (velocity coordinates); zero for a far pair
  /// The pairs computed exactly, ascending: near[0 .. num_near) (compute_distances: every pair).
  std::vector<int> near;
  int num_near = 0;
};

/// Distances of every pair of the scene at the body poses of data (run forward_kinematics first).
template <typename S>
void compute_distances(const Model& model, const Data<S>& data, const CollisionModel& cm, CollisionData<S>& cd) {
  (void)model;
  for (std::size_t k = 0; k < cm.pairs.size(); ++k) {
    const Compound& a = cm.compounds[static_cast<std::size_t>(cm.pairs[k].first)];
    const Compound& b = cm.compounds[static_cast<std::size_t>(cm.pairs[k].second)];
    cd.distances[k] = compound_distance<S>(a, data.X_WB[a.body], b, data.X_WB[b.body]);
    cd.near[k] = static_cast<int>(k);
  }
  cd.num_near = static_cast<int>(cm.pairs.size());
}

/// A lower bound of the distance of compounds a and b placed by X_Wa and X_Wb from their bounding
/// spheres (sphere_lower_bound: never above the computed distance; negative when the spheres
/// overlap). The generated self_distances_near computes the same expression.
template <typename S>
S bounding_distance(const Compound& a, const SE3<S>& X_Wa, const Compound& b, const SE3<S>& X_Wb) {
  const Vec3<S> ca = detail::place<S>(X_Wa, a.bound_center), cb = detail::place<S>(X_Wb, b.bound_center);
  return sphere_lower_bound<S>(ca, S(a.bound_radius), cb, S(b.bound_radius));
}

/// The near set: the pairs closer than `threshold`, with the results of compute_distances (the
/// same values); the others are far, with a lower bound >= threshold of their distance in
/// result.distance. The bounding spheres decide first: a pair whose spheres are at least
/// `threshold` apart is far at once (its bound is the spheres' distance, and it has no closest
/// shapes: shape_first -1); the others are computed shape pair by shape pair with `threshold` as
/// ClosestShapes' limit (a shape pair whose own spheres are that far apart is skipped), and those
/// with no shape pair within it are far, with the least of their computed distances and skipped
/// shape pairs' bounds. compute_distance_jacobians then fills the near pairs' rows only: on
/// Lola standing, 71 of 178 pairs have their spheres within 5 cm and 24 are within it. A pair
/// whose distance is NaN is near, as compute_distances would report it. Pass the avoidance's
/// activation distance: a far pair then cannot be active. Allocation-free.
template <typename S>
void compute_near_distances(const Model& model, const Data<S>& data, const CollisionModel& cm, S threshold, CollisionData<S>& cd) {
  (void)model;
  cd.num_near = 0;
  for (std::size_t k = 0; k < cm.pairs.size(); ++k) {
    const Compound& a = cm.compounds[static_cast<std::size_t>(cm.pairs[k].first)];
    const Compound& b = cm.compounds[static_cast<std::size_t>(cm.pairs[k].second)];
    const SE3<S>& X_Wa = data.X_WB[a.body];
    const SE3<S>& X_Wb = data.X_WB[b.body];
    const S bound = bounding_distance<S>(a, X_Wa, b, X_Wb);
    if (bound >= threshold) {
      cd.distances[k] = CompoundDistance<S>{};
      cd.distances[k].result.distance = bound;
      continue;
    }
    cd.distances[k] = compound_distance<S>(a, X_Wa, b, X_Wb, true, threshold);
    if (!cd.distances[k].within_limit()) {  // far: every shape pair at least threshold apart
      cd.distances[k].result.distance = cd.distances[k].lower_bound();
      continue;
    }
    cd.near[static_cast<std::size_t>(cd.num_near++)] = static_cast<int>(k);
  }
}

/// Distance Jacobians of the computed pairs (cd.near): row k = n^T (J_p2 - J_p1), the point
/// Jacobians of the witness points p1 (on `first`) and p2 (on `second`) as material points of
/// their bodies, n the pair's normal; zero rows for far pairs. Needs compute_joint_jacobians
/// (data.J) at the same q and compute_distances or compute_near_distances.
/// O(depth) per pair: only the joints supporting either body contribute, and the ones
/// supporting both give n . (w x (p2 - p1)).
template <typename S>
void compute_distance_jacobians(const Model& model, const Data<S>& data, const CollisionModel& cm, CollisionData<S>& cd) {
  std::size_t next = 0;  // the next entry of the near list
  for (std::size_t k = 0; k < cm.pairs.size(); ++k) {
    auto row = cd.jacobian.row(static_cast<int>(k));
    row.setZero();
    if (next == static_cast<std::size_t>(cd.num_near) || cd.near[next] != static_cast<int>(k)) continue;  // far
    ++next;
    const SsvDistance<S>& d = cd.distances[k].result;
    const Vec3<S> n = d.normal;
    auto add = [&](BodyIndex body, const Vec3<S>& p, const S& sign) {
      // n . (v_c + w_c x p) = n . v_c + w_c . (p x n)
      const Vec3<S> pxn = p.cross(n);
      for (BodyIndex b = body; b != kWorldBody; b = model.body(b).parent) {
        const Joint& joint = model.joint(model.body(b).joint);
        for (int col = 0; col < joint.nv; ++col) {
          const int c = joint.idx_v + col;
          row[c] += sign * (n.dot(data.J.col(c).template head<3>()) + pxn.dot(data.J.col(c).template tail<3>()));
        }
      }
    };
    add(cm.compounds[static_cast<std::size_t>(cm.pairs[k].second)].body, d.point2, S(1));
    add(cm.compounds[static_cast<std::size_t>(cm.pairs[k].first)].body, d.point1, S(-1));
  }
}

}  // namespace mbgen::collision
