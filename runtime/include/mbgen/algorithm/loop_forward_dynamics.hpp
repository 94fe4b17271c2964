#pragma once
// O(n) forward dynamics of a closed-loop system: the loop maps (loop_maps.hpp) give each
// sub-system its G and g at the state, then the articulated-body algorithm treats every
// sub-system as one aggregate body (subsystem_aba.hpp). The result matches the O(n^3) reference
// (constrained_dynamics.hpp) to round-off on consistent states.
#include "mbgen/algorithm/aba.hpp"
#include "mbgen/algorithm/loop_maps.hpp"

namespace mbgen {

/// Copies the loop maps' G and g (global, nv x ny and nv) into each sub-system's work memory
/// (its coordinates x its independent coordinates).
template <typename S> void load_subsystem_maps(const Model& model, Data<S>& data, const LoopWorkspace<S>& ws) {
  for (std::size_t s = 0; s < model.subsystems.size(); ++s) {
    const SubSystem& sub = model.subsystems[s];
    SubSystemWork<S>& w = data.subsystem[s];
    for (std::size_t j = 0; j < sub.coordinates.size(); ++j) {
      const int row = sub.coordinates[j];
      for (std::size_t c = 0; c < sub.independent.size(); ++c)
        w.G(static_cast<int>(j), static_cast<int>(c)) = ws.G(row, ws.column_of[static_cast<std::size_t>(sub.independent[c])]);
      w.g[static_cast<int>(j)] = ws.g[row];
    }
  }
}

/// Joint accelerations of every tree joint (data.ddq, nv; also returned through it) at a
/// consistent state (q closed, v = G vy) under joint forces tau (nv; forces on dependent joints
/// act through G^T). The independent coordinates' accelerations are the entries of data.ddq at
/// ws.independent. Returns the velocity map's status: Singular at a dead point of a linkage,
/// where the accelerations are not defined (and not to be used).
template <typename S>
LoopSolveStatus forward_dynamics_loops(const Model& model, Data<S>& data, LoopWorkspace<S>& ws, const ConstVecRef<S>& q,
                                       const ConstVecRef<S>& v, const ConstVecRef<S>& tau, const LoopSolveOptions& options = {}) {
  const LoopSolveStatus status = loop_velocity_map<S>(model, data, ws, q, options);
  loop_acceleration_bias<S>(model, data, ws, q, v);
  load_subsystem_maps<S>(model, data, ws);
  aba<S>(model, data, q, v, tau);
  return status;
}

}  // namespace mbgen
