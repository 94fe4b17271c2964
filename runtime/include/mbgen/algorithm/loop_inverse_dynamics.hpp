#pragma once
// Inverse dynamics and mass matrix of a closed-loop system in its independent coordinates y
// (ModelStructure::independent_v): with qd = T yd and qdd = T ydd + g_full (T: identity off the loops, each
// sub-system's G on its coordinates; g_full: each sub-system's g),
//   tau_y = T^T RNEA(q, qd, T ydd + g_full),   M_y = T^T M T.
// tau_y are the generalized forces on y that produce ydd: what the actuators of the independent
// joints must apply when the dependent joints are passive. Both need the sub-system maps at the
// state (subsystem_velocity_maps, subsystem_acceleration_biases). O(n) for tau_y, O(n^2) for M_y.
#include "mbgen/algorithm/crba.hpp"
#include "mbgen/algorithm/rnea.hpp"
#include "mbgen/algorithm/subsystem_maps.hpp"

namespace mbgen {

namespace detail {
/// out_y = T^T f_full.
template <typename S> void project_independent(const Model& model, const Data<S>& data, const VecX<S>& f_full, VecX<S>& out_y) {
  for (std::size_t i = 0; i < model.structure().independent_v.size(); ++i) out_y[static_cast<int>(i)] = f_full[model.structure().independent_v[i]];
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    const SubSystemWork<S>& w = data.subsystem[k];
    for (std::size_t c = 0; c < sub.independent.size(); ++c) {
      S x = S(0);
      for (std::size_t j = 0; j < sub.coordinates.size(); ++j) x += w.G(static_cast<int>(j), static_cast<int>(c)) * f_full[sub.coordinates[j]];
      out_y[model.structure().column_of_v[static_cast<std::size_t>(sub.independent[c])]] = x;
    }
  }
}
}  // namespace detail

namespace detail {
/// tau_y = T^T RNEA(q, v, T ydd + g) into data.tau_y, the sub-system maps G already at q.
template <typename S, typename V>
const VecX<S>& inverse_dynamics_at_maps(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const V& v, const ConstVecRef<S>& ydd) {
  subsystem_acceleration_biases<S>(model, data, q, v);
  expand_independent<S>(model, data, ydd, true, data.v_full);  // v_full holds qdd here
  const VecX<S>& tau = rnea<S>(model, data, q, v, data.v_full);
  project_independent<S>(model, data, tau, data.tau_y);
  return data.tau_y;
}
}  // namespace detail

/// tau_y (ny) in data.tau_y, also returned: the forces on the independent coordinates giving
/// accelerations ydd (ny) at the consistent state (q, v) (v: all nv velocities). Computes the
/// sub-system maps itself.
template <typename S>
const VecX<S>& inverse_dynamics_loops(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                                      const ConstVecRef<S>& ydd) {
  subsystem_velocity_maps<S>(model, data, q);
  return detail::inverse_dynamics_at_maps<S>(model, data, q, v, ydd);
}

/// The same from the independent velocities vy (ny): v = T vy first (in data.scratch_nv).
template <typename S>
const VecX<S>& inverse_dynamics_independent(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& vy,
                                            const ConstVecRef<S>& ydd) {
  subsystem_velocity_maps<S>(model, data, q);
  detail::expand_independent<S>(model, data, vy, false, data.scratch_nv);
  return detail::inverse_dynamics_at_maps<S>(model, data, q, data.scratch_nv, ydd);
}

/// M_y = T^T M T (ny x ny) in data.M_y, also returned, at a closed configuration q.
template <typename S> const MatX<S>& mass_matrix_loops(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  subsystem_velocity_maps<S>(model, data, q);
  const MatX<S>& M = crba<S>(model, data, q);
  for (int c = 0; c < data.M_y.cols(); ++c) {  // column c: T^T M (T e_c)
    data.scratch_y.setZero();
    data.scratch_y[c] = S(1);
    detail::expand_independent<S>(model, data, data.scratch_y, false, data.v_full);
    data.scratch_nv.noalias() = M * data.v_full;
    detail::project_independent<S>(model, data, data.scratch_nv, data.tau_y);
    data.M_y.col(c) = data.tau_y;
  }
  return data.M_y;
}

}  // namespace mbgen
