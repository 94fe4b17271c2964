#pragma once
// Position, velocity and acceleration maps of the closed system (DESIGN.md, "Kinematic loops
// and sub-systems"), sub-system by sub-system (Model::subsystems, filled by the loader):
//   position      Newton on Phi_s(y, z) = 0 for the dependent coordinates z, warm-started
//   velocity      v = G vy, G = [I; -Phi_z^-1 Phi_y] in full-coordinate order (nv x ny)
//   acceleration  qdd = G ydd + g, g = [0; Phi_z^-1 gamma] (the closures' velocity products)
// Only the kept (independent) rows of each sub-system enter, so Phi_z is square.
// y collects every coordinate that is not dependent in a sub-system, ascending: the joints off
// the loops, the actuated joints and idle spins on them. ny = nv - total rank.
//
// Status, never a silent NaN: Newton is a fixed loop with an iteration cap that reports
// Converged, NotConverged (cap reached, or a non-finite step) or Singular (Phi_z's smallest LU
// pivot below singular_tolerance times its largest, along the way or at the solution: a
// linkage at its dead point, where z is not a function of y). q is left at the last finite
// iterate. Allocation-free after the workspace is made (LU factors preallocated).
#include <Eigen/LU>
#include <cmath>
#include <vector>

#include "mbgen/algorithm/closure.hpp"

namespace mbgen {

enum class LoopSolveStatus { Converged, NotConverged, Singular };

inline const char* to_string(LoopSolveStatus s) {
  switch (s) {
    case LoopSolveStatus::Converged: return "converged";
    case LoopSolveStatus::NotConverged: return "not_converged";
    case LoopSolveStatus::Singular: return "singular";
  }
  return "unknown";
}

struct LoopSolveOptions {
  double tolerance = 1e-12;          ///< max |Phi| over the kept rows
  int max_iterations = 20;
  /// Newton steps are scaled down to at most this (rad or m) in their largest entry: with an
  /// ill-conditioned Phi_z (wl16_like's, condition ~6e3) a full first step can overshoot out of
  /// the basin; near the solution the steps are far smaller and Newton stays quadratic.
  double max_step = 0.1;
  /// Smallest / largest |LU pivot| of Phi_z below this: singular. At a dead point the closure
  /// has a double root, which Newton approaches only to ~sqrt(tolerance) = 1e-6 before the
  /// residual test stops it, and the pivot ratio there is of that order (1.7e-6 for the
  /// slider-crank of test_loop_maps): one order above it, 1e-5, is the finest distinction the
  /// residual tolerance supports (z moving 1e5 times faster than y counts as the dead point).
  double singular_tolerance = 1e-5;
};

/// Work memory of the loop maps for one model: per sub-system its Phi_z, Phi_y blocks and LU
/// factor, and the global G, g. Made once; the maps then do not allocate.
template <typename S> struct LoopWorkspace {
  explicit LoopWorkspace(const Model& model);

  std::vector<int> independent;    ///< v indices of y, ascending (ny = size)
  std::vector<int> dependent;      ///< v indices of all z, ascending
  std::vector<int> column_of;      ///< v index -> column of G (its place in `independent`), -1 if dependent
  std::vector<int> q_index_of_v;   ///< v index -> q index (1-DoF joints; -1 inside a floating joint)
  std::vector<MatX<S>> Phi_z;      ///< per sub-system, rank x rank
  std::vector<Eigen::PartialPivLU<MatX<S>>> lu;  ///< per sub-system, factor of Phi_z
  std::vector<VecX<S>> rhs, sol;   ///< per sub-system, rank: right-hand side and solution
  MatX<S> G;                       ///< nv x ny velocity map
  VecX<S> g;                       ///< nv acceleration bias
  int iterations = 0;              ///< Newton iterations of the last solve
  S residual = S(0);               ///< max |Phi| (kept rows) at the end of the last solve
};

template <typename S> LoopWorkspace<S>::LoopWorkspace(const Model& model) : column_of(model.nv(), 0), q_index_of_v(model.nv(), -1) {
  for (const SubSystem& s : model.subsystems) {
    for (int z : s.dependent) column_of[z] = -1;
    Phi_z.push_back(MatX<S>::Zero(s.rank(), s.rank()));
    lu.emplace_back(s.rank());
    rhs.push_back(VecX<S>::Zero(s.rank()));
    sol.push_back(VecX<S>::Zero(s.rank()));
  }
  for (int i = 0; i < model.nv(); ++i) {
    if (column_of[i] < 0) {
      dependent.push_back(i);
    } else {
      column_of[i] = static_cast<int>(independent.size());
      independent.push_back(i);
    }
  }
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    if (joint.nv == 1) q_index_of_v[joint.idx_v] = joint.idx_q;
  }
  G = MatX<S>::Zero(model.nv(), static_cast<int>(independent.size()));
  g = VecX<S>::Zero(model.nv());
}

namespace detail {
/// Factors every sub-system's Phi_z from data.Phi_q; false if one is singular.
template <typename S> bool factor_dependent_blocks(const Model& model, const Data<S>& data, LoopWorkspace<S>& ws, double singular_tolerance) {
  using std::abs;
  bool regular = true;
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& s = model.subsystems[k];
    MatX<S>& Phi_z = ws.Phi_z[k];
    for (int r = 0; r < s.rank(); ++r)
      for (int c = 0; c < s.rank(); ++c) Phi_z(r, c) = data.Phi_q(s.rows[r], s.dependent[c]);
    ws.lu[k].compute(Phi_z);
    S smallest = S(0), largest = S(0);
    for (int i = 0; i < s.rank(); ++i) {
      const S p = abs(ws.lu[k].matrixLU()(i, i));
      if (i == 0 || p < smallest) smallest = p;
      if (p > largest) largest = p;
    }
    // A NaN pivot fails the comparison too.
    if (s.rank() > 0 && !(smallest > S(singular_tolerance) * largest)) regular = false;
  }
  return regular;
}
}  // namespace detail

/// Position map: solves Phi(y, z) = 0 for the dependent coordinates z of every sub-system by
/// Newton, y and the warm start of z taken from q (size nq), z written back into q. Uses
/// data.Phi, data.Phi_q.
template <typename S>
LoopSolveStatus solve_dependent_coordinates(const Model& model, Data<S>& data, LoopWorkspace<S>& ws, Eigen::Ref<VecX<S>> q,
                                            const LoopSolveOptions& options = {}) {
  using std::abs;
  using std::isfinite;
  for (ws.iterations = 0;; ++ws.iterations) {
    closure_residual<S>(model, data, q);
    S worst = S(0);
    bool finite = true;
    for (const SubSystem& s : model.subsystems)
      for (int r : s.rows) {
        finite = finite && isfinite(data.Phi[r]);
        if (abs(data.Phi[r]) > worst) worst = abs(data.Phi[r]);
      }
    ws.residual = worst;
    if (!finite) return LoopSolveStatus::NotConverged;
    closure_jacobian<S>(model, data, q);
    if (!detail::factor_dependent_blocks<S>(model, data, ws, options.singular_tolerance)) return LoopSolveStatus::Singular;
    if (worst < S(options.tolerance)) return LoopSolveStatus::Converged;
    if (ws.iterations == options.max_iterations) return LoopSolveStatus::NotConverged;
    for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
      const SubSystem& s = model.subsystems[k];
      for (int r = 0; r < s.rank(); ++r) ws.rhs[k][r] = data.Phi[s.rows[r]];
      ws.sol[k] = ws.lu[k].solve(ws.rhs[k]);
      const S largest = s.rank() > 0 ? ws.sol[k].cwiseAbs().maxCoeff() : S(0);
      const S scale = largest > S(options.max_step) ? S(options.max_step) / largest : S(1);
      for (int c = 0; c < s.rank(); ++c) q[ws.q_index_of_v[s.dependent[c]]] -= scale * ws.sol[k][c];
    }
  }
}

/// Velocity map at q (nq): ws.G (nv x ny) with v = G vy for every velocity that keeps the loops
/// closed (Phi_q G = 0). Also leaves Phi_z's factors for loop_acceleration_bias at the same q.
template <typename S>
LoopSolveStatus loop_velocity_map(const Model& model, Data<S>& data, LoopWorkspace<S>& ws, const ConstVecRef<S>& q,
                                  const LoopSolveOptions& options = {}) {
  closure_jacobian<S>(model, data, q);
  const bool regular = detail::factor_dependent_blocks<S>(model, data, ws, options.singular_tolerance);
  ws.G.setZero();
  for (std::size_t i = 0; i < ws.independent.size(); ++i) ws.G(ws.independent[i], static_cast<int>(i)) = S(1);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& s = model.subsystems[k];
    for (int y : s.independent) {
      for (int r = 0; r < s.rank(); ++r) ws.rhs[k][r] = data.Phi_q(s.rows[r], y);
      ws.sol[k] = ws.lu[k].solve(ws.rhs[k]);
      for (int c = 0; c < s.rank(); ++c) ws.G(s.dependent[c], ws.column_of[y]) = -ws.sol[k][c];
    }
  }
  return regular ? LoopSolveStatus::Converged : LoopSolveStatus::Singular;
}

/// Acceleration bias at (q, v): ws.g (nv) with qdd = G ydd + g keeping the loops closed; zero
/// at the independent coordinates. Needs loop_velocity_map at the same q first.
template <typename S>
const VecX<S>& loop_acceleration_bias(const Model& model, Data<S>& data, LoopWorkspace<S>& ws, const ConstVecRef<S>& q,
                                      const ConstVecRef<S>& v) {
  closure_bias<S>(model, data, q, v);
  ws.g.setZero();
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& s = model.subsystems[k];
    for (int r = 0; r < s.rank(); ++r) ws.rhs[k][r] = data.gamma[s.rows[r]];
    ws.sol[k] = ws.lu[k].solve(ws.rhs[k]);
    for (int c = 0; c < s.rank(); ++c) ws.g[s.dependent[c]] = ws.sol[k][c];
  }
  return ws.g;
}

}  // namespace mbgen
