#pragma once
// Self-collision potential over a scene's kept pairs (thesis ch. 5; DESIGN.md "Controller side"):
//   P(q) = sum_k  1/2 * stiffness * (d_a - d_k(q))^2   for d_k < d_a, 0 otherwise,
//   dP/dq = - sum_k stiffness * (d_a - d_k) * dd_k/dq   (velocity coordinates, nv).
// d_a is the activation distance. The quadratic is C^1 at d_a: the potential and its gradient
// switch on from zero, so a controller that descends it does not jerk when a pair comes within
// d_a; it is defined for negative d (overlap) too, where it keeps pushing apart with a force that
// grows linearly with the penetration of the activation zone. The gradient is what the
// differential IK projects into the null space of the primary tasks (its negative, scaled by the
// inverse velocity weights, is the steepest-descent velocity of P).
//
// Needs compute_distances and compute_distance_jacobians (collision/compound_distance.hpp) at q.
#include <stdexcept>
#include <string>

#include "mbgen/collision/compound_distance.hpp"

namespace mbgen::control {

struct CollisionPotentialOptions {
  double activation_distance = 0.05;  ///< d_a, m: pairs closer than this are pushed apart
  double stiffness = 100.0;           ///< of the potential, 1/(m s): the repulsive velocity is stiffness * (d_a - d) * J_d^T
};

inline void check(const CollisionPotentialOptions& o) {
  if (!(o.activation_distance > 0) || !std::isfinite(o.activation_distance))
    throw std::invalid_argument("collision avoidance: activation_distance must be finite and > 0, got " + std::to_string(o.activation_distance));
  if (!(o.stiffness > 0) || !std::isfinite(o.stiffness))
    throw std::invalid_argument("collision avoidance: stiffness must be finite and > 0, got " + std::to_string(o.stiffness));
}

/// P(q) from the pair distances in cd.
template <typename S> S collision_potential(const collision::CollisionData<S>& cd, const CollisionPotentialOptions& o) {
  const S da(o.activation_distance), k(o.stiffness);
  S p = S(0);
  for (const auto& pair : cd.distances) {
    const S gap = da - pair.result.distance;
    if (gap > S(0)) p += S(0.5) * k * gap * gap;
  }
  return p;
}

namespace detail {
/// dP/dq from pair i's distance distance_of(i) and the Jacobian's row i, i < pairs.
template <typename S, typename DistanceOf, typename Jacobian, typename Out>
int potential_gradient(int pairs, const DistanceOf& distance_of, const Jacobian& jacobian, const CollisionPotentialOptions& o,
                       Out&& gradient) {
  const S da(o.activation_distance), k(o.stiffness);
  gradient.setZero();
  int active = 0;
  for (int i = 0; i < pairs; ++i) {
    const S gap = da - distance_of(i);
    if (!(gap > S(0))) continue;
    gradient -= (k * gap) * jacobian.row(i).transpose();
    ++active;
  }
  return active;
}
}  // namespace detail

/// dP/dq (nv) from `pairs` distances and the distance Jacobian's rows (pairs x nv, any Eigen
/// expression: the generated self_distances' row-major array mapped); returns the number of
/// active pairs.
template <typename S, typename Jacobian, typename Out>
int collision_potential_gradient(int pairs, const S* distance, const Jacobian& jacobian, const CollisionPotentialOptions& o,
                                 Out&& gradient) {
  return detail::potential_gradient<S>(pairs, [&](int i) { return distance[i]; }, jacobian, o, gradient);
}

/// dP/dq (nv) from a near set (self_distances_near's layout): the pairs near[0 .. num_near), their
/// distances distance[near[i]] and compact Jacobian rows i (num_near x nv). The far pairs, at least
/// the threshold apart, contribute nothing when the threshold is at least the activation distance.
/// Returns the number of active pairs.
template <typename S, typename Jacobian, typename Out>
int collision_potential_gradient(int num_near, const int* near, const S* distance, const Jacobian& jacobian,
                                 const CollisionPotentialOptions& o, Out&& gradient) {
  return detail::potential_gradient<S>(num_near, [&](int i) { return distance[near[i]]; }, jacobian, o, gradient);
}

/// dP/dq (nv) from the distances and distance Jacobians in cd; returns the number of active pairs.
template <typename S, typename Out>
int collision_potential_gradient(const collision::CollisionData<S>& cd, const CollisionPotentialOptions& o, Out&& gradient) {
  return detail::potential_gradient<S>(
      static_cast<int>(cd.distances.size()), [&](int i) { return cd.distances[static_cast<std::size_t>(i)].result.distance; },
      cd.jacobian, o, gradient);
}

}  // namespace mbgen::control
