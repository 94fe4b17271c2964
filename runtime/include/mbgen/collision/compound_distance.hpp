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
template <typename S>
CompoundDistance<S> compound_distance(const Compound& a, const SE3<S>& X_Wa, const Compound& b, const SE3<S>& X_Wb) {
  CompoundDistance<S> best;
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
      : distances(cm.pairs.size()), jacobian(MatX<S>::Zero(static_cast<int>(cm.pairs.size()), model.nv())) {}
  std::vector<CompoundDistance<S>> distances;  ///< per pair, normal from `first` to `second`
  MatX<S> jacobian;                            ///< pairs x nv: row k is d distance_k / d q (velocity coordinates)
};

/// Distances of every pair of the scene at the body poses of data (run forward_kinematics first).
template <typename S>
void compute_distances(const Model& model, const Data<S>& data, const CollisionModel& cm, CollisionData<S>& cd) {
  (void)model;
  for (std::size_t k = 0; k < cm.pairs.size(); ++k) {
    const Compound& a = cm.compounds[static_cast<std::size_t>(cm.pairs[k].first)];
    const Compound& b = cm.compounds[static_cast<std::size_t>(cm.pairs[k].second)];
    cd.distances[k] = compound_distance<S>(a, data.X_WB[a.body], b, data.X_WB[b.body]);
  }
}

/// Distance Jacobians of every pair: row k = n^T (J_p2 - J_p1), the point Jacobians of the
/// witness points p1 (on `first`) and p2 (on `second`) as material points of their bodies, n the
/// pair's normal. Needs compute_joint_jacobians (data.J) at the same q and compute_distances.
/// O(depth) per pair: only the joints supporting either body contribute, and the ones
/// supporting both give n . (w x (p2 - p1)).
template <typename S>
void compute_distance_jacobians(const Model& model, const Data<S>& data, const CollisionModel& cm, CollisionData<S>& cd) {
  for (std::size_t k = 0; k < cm.pairs.size(); ++k) {
    const SsvDistance<S>& d = cd.distances[k].result;
    auto row = cd.jacobian.row(static_cast<int>(k));
    row.setZero();
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
