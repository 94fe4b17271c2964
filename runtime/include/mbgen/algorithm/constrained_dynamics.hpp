#pragma once
// Reference forward dynamics of a closed-loop system, O(n^3), two independent ways (DESIGN.md:
// what the O(n) sub-system recursion must match to round-off on consistent states):
//   full coordinates with Lagrange multipliers (KKT):
//     [M  Phi_k^T] [qdd]   [tau - C - g                    ]
//     [Phi_k   0 ] [ mu] = [gamma_k - 2 alpha Phidot_k - beta^2 Phi_k],   lambda = -mu
//   independent coordinates: G^T M G ydd = G^T (tau - C - g - M g_acc), qdd = G ydd + g_acc.
// Phi_k are the kept rows of the sub-systems (redundant rows dropped, so the KKT matrix is
// regular); lambda are the closure forces along them (M qdd = tau - C - g + Phi_k^T lambda).
// Baumgarte stabilisation (alpha, beta > 0) pulls a drifting state back to Phi = 0; with
// alpha = beta = 0 the constraint holds at the acceleration level only and Phi drifts.
// Fixed base or floating base alike; allocation-free after the workspace is made.
#include <Eigen/Cholesky>
#include <algorithm>
#include <Eigen/LU>

#include "mbgen/algorithm/crba.hpp"
#include "mbgen/algorithm/closure_positions.hpp"
#include "mbgen/algorithm/rnea.hpp"

namespace mbgen {

struct BaumgarteGains {
  double alpha = 0;  ///< velocity gain, 1/s
  double beta = 0;   ///< position gain, 1/s
};

/// Work memory of the reference forward dynamics.
template <typename S> struct ConstrainedDynamicsWorkspace {
  explicit ConstrainedDynamicsWorkspace(const Model& model);
  std::vector<int> rows;   ///< kept constraint rows of all sub-systems, ascending (r = size)
  MatX<S> K;               ///< KKT matrix (nv + r)^2
  VecX<S> rhs, solution;   ///< nv + r
  Eigen::PartialPivLU<MatX<S>> kkt_lu;
  VecX<S> qdd;             ///< nv: the result
  VecX<S> lambda;          ///< r: closure forces along the kept rows (KKT only)
  VecX<S> bias;            ///< nv: C v + g
  // Independent coordinates.
  MatX<S> MG, Mr;          ///< M G (nv x ny), G^T M G (ny x ny)
  VecX<S> force, rhs_y, ydd;
  Eigen::LLT<MatX<S>> Mr_llt;
  MatX<S> G;               ///< nv x ny velocity map T (subsystem_maps.hpp: velocity_map)
  VecX<S> g;               ///< nv acceleration bias (acceleration_bias)
};

namespace detail {
/// The kept constraint rows of all sub-systems, ascending.
inline std::vector<int> kept_closure_rows(const Model& model) {
  std::vector<int> rows;
  for (const SubSystem& s : model.subsystems) rows.insert(rows.end(), s.rows.begin(), s.rows.end());
  std::sort(rows.begin(), rows.end());
  return rows;
}
}  // namespace detail

// The factorisations are sized in place, and the Cholesky factor is computed once, of the
// identity: Eigen's LLT(Index) leaves its status (an enum) and norm unset, and the workspace's
// implicit copy and move read every member, so a workspace moved before its first solve read an
// indeterminate enum (UndefinedBehaviorSanitizer: "not a valid value for type
// 'ComputationInfo'"; issue 61). PartialPivLU(Index) sets all of its own.
template <typename S>
ConstrainedDynamicsWorkspace<S>::ConstrainedDynamicsWorkspace(const Model& model)
    : rows(detail::kept_closure_rows(model)),
      kkt_lu(model.nv() + static_cast<int>(rows.size())),
      Mr_llt(static_cast<Eigen::Index>(model.structure().num_independent())) {
  const int n = model.nv(), r = static_cast<int>(rows.size()), y = static_cast<int>(Mr_llt.rows());
  K = MatX<S>::Zero(n + r, n + r);
  rhs = VecX<S>::Zero(n + r);
  solution = VecX<S>::Zero(n + r);
  qdd = VecX<S>::Zero(n);
  lambda = VecX<S>::Zero(r);
  bias = VecX<S>::Zero(n);
  MG = MatX<S>::Zero(n, y);
  Mr = MatX<S>::Zero(y, y);
  force = VecX<S>::Zero(n);
  rhs_y = VecX<S>::Zero(y);
  ydd = VecX<S>::Zero(y);
  G = MatX<S>::Zero(n, y);
  g = VecX<S>::Zero(n);
  Mr_llt.compute(MatX<S>::Identity(y, y));
}

/// Full-coordinate forward dynamics with Lagrange multipliers at (q, v) with joint forces tau:
/// ws.qdd (nv), also returned, and ws.lambda. Optional Baumgarte gains.
template <typename S>
const VecX<S>& forward_dynamics_kkt(const Model& model, Data<S>& data, ConstrainedDynamicsWorkspace<S>& ws,
                                    const ConstVecRef<S>& q, const ConstVecRef<S>& v, const ConstVecRef<S>& tau,
                                    const BaumgarteGains& gains = {}) {
  const int n = model.nv(), r = static_cast<int>(ws.rows.size());
  ws.K.topLeftCorner(n, n) = crba<S>(model, data, q);
  ws.bias = nonlinear_effects<S>(model, data, q, v);
  ws.rhs.head(n) = tau - ws.bias;
  closure_jacobian<S>(model, data, q);
  for (int i = 0; i < r; ++i)
    for (int c = 0; c < n; ++c) ws.K(n + i, c) = ws.K(c, n + i) = data.Phi_q(ws.rows[i], c);
  closure_bias<S>(model, data, q, v);
  for (int i = 0; i < r; ++i) ws.rhs[n + i] = data.gamma[ws.rows[i]];
  if (gains.alpha != 0 || gains.beta != 0) {
    closure_residual<S>(model, data, q);
    for (int i = 0; i < r; ++i) {
      const S phi_dot = data.Phi_q.row(ws.rows[i]).dot(v);
      ws.rhs[n + i] -= S(2 * gains.alpha) * phi_dot + S(gains.beta * gains.beta) * data.Phi[ws.rows[i]];
    }
  }
  ws.kkt_lu.compute(ws.K);
  ws.solution = ws.kkt_lu.solve(ws.rhs);
  ws.qdd = ws.solution.head(n);
  ws.lambda = -ws.solution.tail(r);
  return ws.qdd;
}

/// Forward dynamics in independent coordinates at a consistent state (q closed, v = G vy):
/// ws.qdd = G ydd + g_acc (nv), also returned. Meaningful only where Phi_z is regular: the status
/// (Singular at a dead point, by options.singular_tolerance) comes back through `status`.
template <typename S>
const VecX<S>& forward_dynamics_independent(const Model& model, Data<S>& data, ConstrainedDynamicsWorkspace<S>& ws,
                                            const ConstVecRef<S>& q, const ConstVecRef<S>& v, const ConstVecRef<S>& tau,
                                            ClosureStatus* status = nullptr, const ClosureOptions& options = {}) {
  velocity_map<S>(model, data, q, ws.G);
  if (status)
    *status = subsystem_pivot_ratio<S>(model, data) >= S(options.singular_tolerance) ? ClosureStatus::Converged : ClosureStatus::Singular;
  // g from the sub-systems' G at q (just computed) and v: acceleration_bias would redo the maps.
  subsystem_acceleration_biases<S>(model, data, q, v);
  ws.rhs_y.setZero();
  detail::expand_independent<S>(model, data, ws.rhs_y, true, ws.g);
  const MatX<S>& M = crba<S>(model, data, q);
  ws.bias = nonlinear_effects<S>(model, data, q, v);
  ws.force = tau - ws.bias;
  ws.force.noalias() -= M * ws.g;
  ws.MG.noalias() = M * ws.G;
  ws.Mr.noalias() = ws.G.transpose() * ws.MG;
  ws.rhs_y.noalias() = ws.G.transpose() * ws.force;
  ws.Mr_llt.compute(ws.Mr);
  ws.ydd = ws.Mr_llt.solve(ws.rhs_y);
  ws.qdd = ws.g;
  ws.qdd.noalias() += ws.G * ws.ydd;
  return ws.qdd;
}

}  // namespace mbgen
