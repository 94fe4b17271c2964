#pragma once
// O(n) forward dynamics of a closed-loop system: each sub-system's maps G and g at the state
// (subsystem_maps.hpp), then the articulated-body algorithm with every sub-system as one
// aggregate body (subsystem_aba.hpp). The result matches the O(n^3) reference
// (constrained_dynamics.hpp) to round-off on consistent states.
#include <type_traits>

#include "mbgen/algorithm/aba.hpp"
#include "mbgen/algorithm/closure_positions.hpp"
#include "mbgen/algorithm/subsystem_maps.hpp"

namespace mbgen {

/// Joint accelerations of every tree joint (data.ddq, nv) at a consistent state (q closed,
/// v = G vy) under joint forces tau (nv; forces on dependent joints act through G^T). The
/// independent coordinates' accelerations are data.ddq's entries at them (and
/// data.subsystem[s].ydd per sub-system). Status: Singular where a linkage is at (or within
/// options.singular_tolerance of) a dead point, where the accelerations are not defined and must
/// not be used.
template <typename S>
ClosureStatus forward_dynamics_loops(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                                       const ConstVecRef<S>& tau, const ClosureOptions& options = {}) {
  aba<S>(model, data, q, v, tau);  // computes the sub-systems' maps first
  const S ratio = subsystem_pivot_ratio<S>(model, data);
  return ratio > S(options.singular_tolerance) ? ClosureStatus::Converged : ClosureStatus::Singular;
}

namespace detail {
/// The sub-systems' maps G and g at (q, vy) and the full velocity T vy in data.v_full: what the
/// recursion with sub-systems needs before its passes.
template <typename S> void loop_maps(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& vy) {
  subsystem_velocity_maps<S>(model, data, q);
  expand_independent<S>(model, data, vy, false, data.v_full);
  subsystem_acceleration_biases<S>(model, data, q, data.v_full);
}
}  // namespace detail

/// The same with the velocity given in independent coordinates: vy (ny) for the coordinates
/// ModelStructure::independent_v (every v index not dependent in a sub-system, ascending); the full
/// velocity T vy is built in data.v_full. The form the generator traces.
template <typename S>
void forward_dynamics_loops_independent(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& vy, const ConstVecRef<S>& tau) {
  detail::loop_maps<S>(model, data, q, vy);
  detail::aba_recursion<S>(model, data, q, data.v_full, tau);
}

}  // namespace mbgen
