#pragma once
// O(n) forward dynamics of a closed-loop system: each sub-system's maps G and g at the state
// (subsystem_maps.hpp), then the articulated-body algorithm with every sub-system as one
// aggregate body (subsystem_aba.hpp). The result matches the O(n^3) reference
// (constrained_dynamics.hpp) to round-off on consistent states.
#include <type_traits>

#include "mbgen/algorithm/aba.hpp"
#include "mbgen/algorithm/subsystem_maps.hpp"

namespace mbgen {

/// Joint accelerations of every tree joint (data.ddq, nv) at a consistent state (q closed,
/// v = G vy) under joint forces tau (nv; forces on dependent joints act through G^T). The
/// independent coordinates' accelerations are data.ddq's entries at them (and
/// data.subsystem[s].ydd per sub-system). Status: Singular where a linkage is at (or within
/// options.singular_tolerance of) a dead point, where the accelerations are not defined and must
/// not be used.
template <typename S>
LoopSolveStatus forward_dynamics_loops(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                                       const ConstVecRef<S>& tau, const LoopSolveOptions& options = {}) {
  aba<S>(model, data, q, v, tau);  // computes the sub-systems' maps first
  const S ratio = subsystem_pivot_ratio<S>(model, data);
  return ratio > S(options.singular_tolerance) ? LoopSolveStatus::Converged : LoopSolveStatus::Singular;
}

/// The same with the velocity given in independent coordinates: vy (ny) for the coordinates
/// `independent` (every v index not dependent in a sub-system, ascending: LoopWorkspace's
/// order); the full velocity G vy is built in data.v_full. The form the generator traces.
template <typename S>
void forward_dynamics_loops_independent(const Model& model, Data<S>& data, const std::vector<int>& independent,
                                        const ConstVecRef<S>& q, const ConstVecRef<S>& vy, const ConstVecRef<S>& tau) {
  subsystem_velocity_maps<S>(model, data, q);
  for (std::size_t i = 0; i < independent.size(); ++i) data.v_full[independent[i]] = vy[static_cast<int>(i)];
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    const SubSystemWork<S>& w = data.subsystem[k];
    for (std::size_t j = 0; j < sub.coordinates.size(); ++j) {
      if (w.coordinate_role[j] >= 0) continue;  // independent: already set
      S rate = S(0);
      for (std::size_t c = 0; c < sub.independent.size(); ++c)
        rate += w.G(static_cast<int>(j), static_cast<int>(c)) * data.v_full[sub.independent[c]];
      data.v_full[sub.coordinates[j]] = rate;
    }
  }
  subsystem_acceleration_biases<S>(model, data, q, data.v_full);
  detail::aba_recursion<S>(model, data, q, data.v_full, tau);
}

}  // namespace mbgen
