#pragma once
// Joint position limits as a potential the differential IK descends in the null space of its
// primary tasks, beside the self-collision potential (collision_potential.hpp; the classical
// gradient projection of Liegeois, 1977). For each limited coordinate q_i in [lower, upper],
// with margins d- = q_i - lower and d+ = upper - q_i to its two limits,
//   P(q) = sum_i  1/2 * stiffness * ( max(0, a - d-)^2 + max(0, a - d+)^2 ),
//   dP/dq_i = - stiffness * max(0, a - d-) + stiffness * max(0, a - d+)   (its velocity coordinate),
// a the activation margin. As the collision potential, it is C^1 where it switches on, and keeps
// pushing past a limit (a margin below zero) with a force that grows linearly: the IK takes a
// joint back inside rather than refusing the step. The velocity is the potential's descent
// within what the primary tasks leave free: a limit a task needs is not held (the tasks win), and
// the report says how many limits were active.
//
// Limits are per coordinate of a 1-DoF joint: its position q[q_index] and velocity v[v_index]
// (dq/dt = v for revolute and prismatic joints). With closed loops a limited coordinate may be a
// dependent one (a knee linkage's rod joint): the IK maps the gradient through the loops' velocity
// map, as it does the collision gradient.
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "mbgen/joint_limits.hpp"

namespace mbgen::control {

struct JointLimitOptions {
  std::vector<JointLimit> limits;  ///< empty: no joint limit potential
  double activation = 0.1;         ///< a: rad (m for prismatic joints), margin within which a limit pushes
  double stiffness = 10.0;         ///< of the potential, 1/s: the repulsive velocity is stiffness * (a - margin)
};

/// Throws std::invalid_argument saying what is wrong: a limit outside the coordinates (nq, nv), an
/// empty or non-finite range, a non-positive or non-finite activation or stiffness.
inline void check(const JointLimitOptions& o, int nq, int nv) {
  if (o.limits.empty()) return;
  if (!(o.activation > 0) || !std::isfinite(o.activation))
    throw std::invalid_argument("joint limits: activation must be finite and > 0, got " + std::to_string(o.activation));
  if (!(o.stiffness > 0) || !std::isfinite(o.stiffness))
    throw std::invalid_argument("joint limits: stiffness must be finite and > 0, got " + std::to_string(o.stiffness));
  for (const JointLimit& l : o.limits) {
    const std::string who = "joint limits: '" + l.joint + "'";
    if (l.q_index < 0 || l.q_index >= nq || l.v_index < 0 || l.v_index >= nv)
      throw std::invalid_argument(who + ": coordinate q[" + std::to_string(l.q_index) + "], v[" + std::to_string(l.v_index) +
                                  "] outside the model's nq = " + std::to_string(nq) + ", nv = " + std::to_string(nv));
    if (!(l.lower < l.upper) || !std::isfinite(l.lower) || !std::isfinite(l.upper))
      throw std::invalid_argument(who + ": lower " + std::to_string(l.lower) + " must be below upper " + std::to_string(l.upper) +
                                  ", both finite (leave an unlimited joint out)");
  }
}

namespace detail {
/// How far x has entered the activation zone of each limit: a - (x - lower) and
/// a - (upper - x); positive inside the zone (or past the limit).
template <typename S> std::pair<S, S> limit_gaps(S x, const JointLimit& l, S a) {
  return {a - (x - S(l.lower)), a - (S(l.upper) - x)};
}
}  // namespace detail

/// P(q).
template <typename S> S joint_limit_potential(const S* q, const JointLimitOptions& o) {
  const S a(o.activation), k(o.stiffness);
  S p = S(0);
  for (const JointLimit& l : o.limits) {
    const auto [below, above] = detail::limit_gaps<S>(q[l.q_index], l, a);
    if (below > S(0)) p += S(0.5) * k * below * below;
    if (above > S(0)) p += S(0.5) * k * above * above;
  }
  return p;
}

/// Adds dP/dq to gradient (nv, velocity coordinates); returns the number of limits within their
/// activation margin.
template <typename S, typename Out> int add_joint_limit_gradient(const S* q, const JointLimitOptions& o, Out&& gradient) {
  const S a(o.activation), k(o.stiffness);
  int active = 0;
  for (const JointLimit& l : o.limits) {
    const auto [below, above] = detail::limit_gaps<S>(q[l.q_index], l, a);
    if (below > S(0)) gradient[l.v_index] -= k * below, ++active;
    if (above > S(0)) gradient[l.v_index] += k * above, ++active;
  }
  return active;
}

}  // namespace mbgen::control
