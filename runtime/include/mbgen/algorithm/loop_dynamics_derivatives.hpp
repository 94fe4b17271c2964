#pragma once
// Derivatives of a closed-loop system's dynamics in its independent coordinates y
// (ModelStructure::independent_v), the loops held exactly closed: the configuration is q(y) (the
// dependent coordinates z follow y through Phi(q) = 0), the velocity v = T(q) yd and the
// acceleration qdd = T ydd + g(q, v) (subsystem_maps.hpp). With f(q, v, qdd) = ID(q, v, qdd) - tau
// (the tree's inverse dynamics minus the joint forces: the loops' constraint forces) the closed
// system's equations of motion are
//   T^T f(q(y), T yd, T ydd + g) = 0,        M_y = T^T M T = d/d ydd of the left-hand side,
// and differentiating them at fixed tau along y_c (q moves along T e_c, z with it) and yd_c gives
//   R_q e_c = dT_c^T f + T^T (dtau/dq T e_c + dtau/dv dT_c yd + M (dT_c ydd + dg/dy_c)),
//   R_v e_c = T^T (dtau/dv T e_c + M dg/dyd_c),
//   dydd/dy = -M_y^-1 R_q,  dydd/dyd = -M_y^-1 R_v,  dydd/dtau = M_y^-1 T^T,
// with dtau/dq, dtau/dv the spanning tree's analytic derivatives (rnea_derivatives.hpp) at
// (q, v, qdd). The inverse dynamics in y, tau_y = T^T ID(q, T yd, T ydd + g), has the same
// derivatives with f = ID: dtau_y/dy = R_q, dtau_y/dyd = R_v, dtau_y/dydd = M_y.
//
// dT_c and dg/dy_c, dg/dyd_c are how the closure's own maps change: sub-system by sub-system, the
// implicit-function theorem through Phi_z (Phi_z factored by Givens rotations already, at q):
//   Phi_q G = 0      =>  dG_z = -Phi_z^-1 (dPhi_q G)
//   Phi_q g = gamma  =>  dg_z =  Phi_z^-1 (dgamma - dPhi_q g)          (g is zero on y)
// where dPhi_q and dgamma, the closure's second-order kinematics along a direction, come from
// the cycles' own kinematics (closure.hpp: the few bodies of each loop, relative to its top) run
// in forward-mode dual numbers (Eigen's AutoDiffScalar, one direction per pass: per independent
// coordinate of the largest sub-system, three passes serve every sub-system at once, as no two
// share a coordinate). A sub-system's maps depend on its own coordinates alone (closure.hpp
// computes every row relative to the cycle's top), so dT_c is zero unless y_c is one of a
// sub-system's independent coordinates, and then nonzero only on that sub-system's block.
//
// Exact (to round-off) at closed, consistent states away from dead points. Near a dead point
// Phi_z and M_y lose rank: the status is Singular, as forward_dynamics_loops reports it, and the
// results must not be used. On a model without loops T = I and these are the tree's derivatives
// (aba_derivatives.hpp) in plain coordinates, the floating base by the same tangent convention.
#include <cmath>
#include <type_traits>
#include <vector>

#include <unsupported/Eigen/AutoDiff>

#include "mbgen/algorithm/crba.hpp"
#include "mbgen/algorithm/loop_forward_dynamics.hpp"
#include "mbgen/algorithm/rnea_derivatives.hpp"
#include "mbgen/algorithm/small_ldlt.hpp"

namespace mbgen {

/// The elimination tree of the closed system's mass matrix M_y = T^T M T in its L^T D L factor
/// (small_ldlt.hpp's ltdl_factor, from the last row up): per independent coordinate k, the nearest
/// i < k with L(k, i) possibly nonzero, -1 for none; L(k, i) is zero unless i is on k's chain of
/// parents. Without loops, the velocity parents.
inline std::vector<int> closed_mass_matrix_elimination_tree(const Model& model) {
  const int ny = model.structure().num_independent();
  std::vector<int> y_parent;
  // M_y(k, i) can be nonzero where a coordinate y_k moves (itself, its sub-system's dependent
  // ones) is an ancestor of, or below, one that y_i moves (M's own sparsity); elimination from the
  // last row up then fills in only along the elimination tree it builds.
  const ModelStructure& st = model.structure();
  std::vector<std::vector<int>> moves(static_cast<std::size_t>(ny));
  for (int i = 0; i < ny; ++i) moves[static_cast<std::size_t>(i)].push_back(st.independent_v[static_cast<std::size_t>(i)]);
  for (const SubSystem& sub : model.subsystems)
    for (int c : sub.independent)
      for (int z : sub.dependent) moves[static_cast<std::size_t>(st.column_of_v[static_cast<std::size_t>(c)])].push_back(z);
  const auto above = [&](int a, int b) {  // a is b or one of its ancestors
    for (int x = b; x >= 0; x = model.velocity_parent(x))
      if (x == a) return true;
    return false;
  };
  std::vector<std::vector<bool>> pattern(static_cast<std::size_t>(ny), std::vector<bool>(static_cast<std::size_t>(ny), false));
  for (int k = 0; k < ny; ++k)
    for (int i = 0; i < k; ++i)
      for (int a : moves[static_cast<std::size_t>(k)])
        for (int b : moves[static_cast<std::size_t>(i)])
          if (above(a, b) || above(b, a)) pattern[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)] = true;
  y_parent.assign(static_cast<std::size_t>(ny), -1);
  for (int k = ny - 1; k >= 0; --k) {
    const std::vector<bool>& row = pattern[static_cast<std::size_t>(k)];
    int parent = -1;
    for (int i = 0; i < k; ++i)
      if (row[static_cast<std::size_t>(i)]) parent = i;
    y_parent[static_cast<std::size_t>(k)] = parent;
    for (int i = 0; i < parent; ++i)
      if (row[static_cast<std::size_t>(i)]) pattern[static_cast<std::size_t>(parent)][static_cast<std::size_t>(i)] = true;
  }
  return y_parent;
}

/// Results and work memory of the closed system's derivatives. Making it allocates; the
/// algorithms then do not. All matrices are Eigen's column-major; row r, column c is
/// d(output r)/d(input c), y and yd in ModelStructure::independent_v order.
template <typename S> struct LoopDynamicsDerivatives {
  using Dual = Eigen::AutoDiffScalar<Eigen::Matrix<S, 1, 1>>;
  explicit LoopDynamicsDerivatives(const Model& model);

  // Forward dynamics (forward_dynamics_loops_derivatives).
  VecX<S> ydd;        ///< ny: the independent accelerations at (q, yd, tau)
  MatX<S> dydd_dy;    ///< ny x ny, along q(y) (the loops closed; a floating base by integrate)
  MatX<S> dydd_dyd;   ///< ny x ny
  MatX<S> dydd_dtau;  ///< ny x nv: M_y^-1 T^T (tau on a dependent joint acts through T^T)
  // Inverse dynamics in y (inverse_dynamics_loops_derivatives).
  VecX<S> tau_y;      ///< ny: T^T ID(q, T yd, T ydd + g)
  MatX<S> dtauy_dy;   ///< ny x ny
  MatX<S> dtauy_dyd;  ///< ny x ny (dtau_y/dydd is M_y)
  // Both.
  MatX<S> T;    ///< nv x ny: the velocity map at q, dq/dy (Phi_q T = 0)
  MatX<S> M_y;  ///< ny x ny: T^T M T
  VecX<S> qdd;  ///< nv: T ydd + g, every tree joint's acceleration

  // Work.
  DynamicsDerivatives<S> tree;  ///< the spanning tree's derivatives at (q, v, qdd)
  Data<Dual> closure;           ///< the cycles' kinematics in dual numbers
  VecX<Dual> q_dual, v_dual;
  VecX<S> v, f;                 ///< nv: T yd; ID - tau
  MatX<S> dV, dQdd, dQdd_v, A;  ///< nv x ny: dT_c yd, dT_c ydd + dg/dy_c, dg/dyd_c; products
  MatX<S> R_q, R_v;             ///< ny x ny
  std::vector<std::vector<int>> coordinate_q;  ///< per sub-system: q index of each coordinate
  std::vector<MatX<S>> dG;        ///< per sub-system: k x p^2, block c = dG/dy_c
  std::vector<MatX<S>> dg_y, dg_v;  ///< per sub-system: k x p, column c = dg/dy_c, dg/dyd_c
  std::vector<MatX<S>> rhs;       ///< per sub-system: rank x p
  MatX<S> M_y_factor;  ///< ny x ny: M_y = L^T D L (small_ldlt.hpp's ltdl_factor: branch-free, and as sparse as M_y's tree)
  /// The factor's sparsity, a property of the model: y_parent[k] is the nearest i < k with L(k, i)
  /// possibly nonzero (-1: none), and L(k, i) is zero unless i is on k's chain of y_parents (M_y's
  /// elimination tree; for a tree without loops, the velocity parents). factor_entries holds
  /// L(k, i) along the chains, k's from factor_first[k]; inverse_pivot 1/d. The solves run along
  /// the chains (detail::factor_chain_solve), as the generated code's loops do.
  std::vector<int> y_parent, factor_first;
  VecX<S> factor_entries, inverse_pivot;
  int max_independent = 0;  ///< the largest sub-system's p: the dual passes per call, times 3
};

template <typename S>
LoopDynamicsDerivatives<S>::LoopDynamicsDerivatives(const Model& model) : tree(model), closure(model) {
  const int nv = model.nv(), ny = model.structure().num_independent();
  ydd = tau_y = VecX<S>::Zero(ny);
  dydd_dy = dydd_dyd = dtauy_dy = dtauy_dyd = M_y = M_y_factor = R_q = R_v = MatX<S>::Zero(ny, ny);
  dydd_dtau = MatX<S>::Zero(ny, nv);
  T = dV = dQdd = dQdd_v = A = MatX<S>::Zero(nv, ny);
  qdd = v = f = VecX<S>::Zero(nv);
  q_dual = VecX<Dual>::Zero(model.nq());
  v_dual = VecX<Dual>::Zero(nv);
  for (const SubSystem& sub : model.subsystems) {
    const int k = static_cast<int>(sub.coordinates.size()), p = static_cast<int>(sub.independent.size());
    std::vector<int> cq;
    for (int c : sub.coordinates) cq.push_back(model.q_index_of_v(c));
    coordinate_q.push_back(cq);
    dG.push_back(MatX<S>::Zero(k, p * p));
    dg_y.push_back(MatX<S>::Zero(k, p));
    dg_v.push_back(MatX<S>::Zero(k, p));
    rhs.push_back(MatX<S>::Zero(sub.rank(), p));
    max_independent = std::max(max_independent, p);
  }
  y_parent = closed_mass_matrix_elimination_tree(model);
  int entries = 0;
  for (int k = 0; k < ny; ++k) {
    factor_first.push_back(entries);
    for (int i = y_parent[static_cast<std::size_t>(k)]; i >= 0; i = y_parent[static_cast<std::size_t>(i)]) ++entries;
  }
  factor_entries = VecX<S>::Zero(std::max(entries, 1));
  inverse_pivot = VecX<S>::Zero(ny);
}

namespace detail {

/// Seeds the dual configuration and velocity: values q and ld.v; on every sub-system's
/// coordinates the derivative column `column` of `q_seed` / `v_seed` (k x p per sub-system, or
/// null for zero), zero where the sub-system has fewer independent coordinates.
template <typename S, typename SeedQ, typename SeedV>
void seed_closure_direction(const Model& model, LoopDynamicsDerivatives<S>& ld, int column, SeedQ&& q_seed, SeedV&& v_seed) {
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    const bool active = column < static_cast<int>(sub.independent.size());
    for (std::size_t j = 0; j < sub.coordinates.size(); ++j) {
      const int r = static_cast<int>(j);
      ld.q_dual[ld.coordinate_q[k][j]].derivatives()[0] = active ? q_seed(k, r, column) : S(0);
      ld.v_dual[sub.coordinates[j]].derivatives()[0] = active ? v_seed(k, r, column) : S(0);
    }
  }
}

/// Phi_z^-1 times the first m columns of ld.rhs[k] in place (the factor data.subsystem[k] holds).
template <typename S> void solve_with_closure_factor(const Model& model, const Data<S>& data, LoopDynamicsDerivatives<S>& ld, std::size_t k, int m) {
  const SubSystemWork<S>& w = data.subsystem[k];
  const int r = model.subsystems[k].rank();
  givens_qr_apply<S>(w.rotation_c, w.rotation_s, r, ld.rhs[k], m);
  upper_triangular_solve<S>(w.R, r, ld.rhs[k], m);
}

/// dG, dg/dy and dg/dyd of every sub-system (ld.dG, ld.dg_y, ld.dg_v) at q with v = ld.v, from
/// the maps and Phi_z's factor data.subsystem holds at q (see the top of this file).
template <typename S> void closure_map_derivatives(const Model& model, const Data<S>& data, LoopDynamicsDerivatives<S>& ld, const ConstVecRef<S>& q) {
  using Dual = typename LoopDynamicsDerivatives<S>::Dual;
  for (int i = 0; i < q.size(); ++i) ld.q_dual[i] = Dual(q[i], Eigen::Matrix<S, 1, 1>(S(0)));
  for (int i = 0; i < ld.v.size(); ++i) ld.v_dual[i] = Dual(ld.v[i], Eigen::Matrix<S, 1, 1>(S(0)));
  const auto G_entry = [&](std::size_t k, int j, int c) { return data.subsystem[k].G(j, c); };
  const auto zero = [](std::size_t, int, int) { return S(0); };
  const auto dPhi = [&](std::size_t k, int i, int j) {
    const SubSystem& sub = model.subsystems[k];
    return ld.closure.Phi_q(sub.rows[static_cast<std::size_t>(i)], sub.coordinates[static_cast<std::size_t>(j)]).derivatives()[0];
  };
  for (int c = 0; c < ld.max_independent; ++c) {
    // q along G e_c: dPhi_q, then dG_z = -Phi_z^-1 (dPhi_q G).
    seed_closure_direction<S>(model, ld, c, G_entry, zero);
    cycle_placements<Dual>(model, ld.closure, ld.q_dual.data());
    jacobian_from_placements<Dual>(model, ld.closure);
    for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
      const SubSystem& sub = model.subsystems[k];
      const int r = sub.rank(), p = static_cast<int>(sub.independent.size()), n = static_cast<int>(sub.coordinates.size());
      if (c >= p) continue;
      const MatX<S>& G = data.subsystem[k].G;
      for (int i = 0; i < r; ++i)
        for (int col = 0; col < p; ++col) {
          S x = S(0);
          for (int j = 0; j < n; ++j) x += dPhi(k, i, j) * G(j, col);
          ld.rhs[k](i, col) = x;
        }
      solve_with_closure_factor<S>(model, data, ld, k, p);
      const std::vector<int>& role = model.structure().subsystems[k].coordinate_role;
      for (int j = 0; j < n; ++j)
        for (int col = 0; col < p; ++col) ld.dG[k](j, c * p + col) = role[static_cast<std::size_t>(j)] >= 0 ? S(0) : -ld.rhs[k](-1 - role[static_cast<std::size_t>(j)], col);
    }
    // q along G e_c and v along dG_c yd: dgamma, then dg_z/dy_c = Phi_z^-1 (dgamma - dPhi_q g).
    const auto dv_along_y = [&](std::size_t k, int j, int col) {
      const SubSystem& sub = model.subsystems[k];
      const int p = static_cast<int>(sub.independent.size());
      S x = S(0);
      for (int i = 0; i < p; ++i) x += ld.dG[k](j, col * p + i) * ld.v[sub.independent[static_cast<std::size_t>(i)]];
      return x;
    };
    seed_closure_direction<S>(model, ld, c, G_entry, dv_along_y);
    bias_from_placements<Dual>(model, ld.closure, ld.v_dual.data());  // the placements are pass one's
    for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
      const SubSystem& sub = model.subsystems[k];
      const int r = sub.rank(), n = static_cast<int>(sub.coordinates.size());
      if (c >= static_cast<int>(sub.independent.size())) continue;
      const VecX<S>& g = data.subsystem[k].g;
      for (int i = 0; i < r; ++i) {
        S x = ld.closure.gamma[sub.rows[static_cast<std::size_t>(i)]].derivatives()[0];
        for (int j = 0; j < n; ++j) x -= dPhi(k, i, j) * g[j];
        ld.rhs[k](i, 0) = x;
      }
      solve_with_closure_factor<S>(model, data, ld, k, 1);
      const std::vector<int>& role = model.structure().subsystems[k].coordinate_role;
      for (int j = 0; j < n; ++j) ld.dg_y[k](j, c) = role[static_cast<std::size_t>(j)] >= 0 ? S(0) : ld.rhs[k](-1 - role[static_cast<std::size_t>(j)], 0);
    }
    // q fixed, v along G e_c: dg_z/dyd_c = Phi_z^-1 dgamma.
    seed_closure_direction<S>(model, ld, c, zero, G_entry);
    cycle_placements<Dual>(model, ld.closure, ld.q_dual.data());
    bias_from_placements<Dual>(model, ld.closure, ld.v_dual.data());
    for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
      const SubSystem& sub = model.subsystems[k];
      const int r = sub.rank(), n = static_cast<int>(sub.coordinates.size());
      if (c >= static_cast<int>(sub.independent.size())) continue;
      for (int i = 0; i < r; ++i) ld.rhs[k](i, 0) = ld.closure.gamma[sub.rows[static_cast<std::size_t>(i)]].derivatives()[0];
      solve_with_closure_factor<S>(model, data, ld, k, 1);
      const std::vector<int>& role = model.structure().subsystems[k].coordinate_role;
      for (int j = 0; j < n; ++j) ld.dg_v[k](j, c) = role[static_cast<std::size_t>(j)] >= 0 ? S(0) : ld.rhs[k](-1 - role[static_cast<std::size_t>(j)], 0);
    }
  }
}

/// R_q, R_v (top of this file) into ld.R_q, ld.R_v and M_y into ld.M_y, from the tree's
/// derivatives in ld.tree at (q, ld.v, ld.qdd), the mass matrix M, the closure's map derivatives
/// and ld.f; ydd the independent accelerations.
template <typename S>
void closed_residual_derivatives(const Model& model, LoopDynamicsDerivatives<S>& ld, const MatX<S>& M, const ConstVecRef<S>& ydd) {
  const ModelStructure& st = model.structure();
  ld.dV.setZero();
  ld.dQdd.setZero();
  ld.dQdd_v.setZero();
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    const int p = static_cast<int>(sub.independent.size());
    for (int c = 0; c < p; ++c) {
      const int column = st.column_of_v[static_cast<std::size_t>(sub.independent[static_cast<std::size_t>(c)])];
      for (std::size_t j = 0; j < sub.coordinates.size(); ++j) {
        const int row = sub.coordinates[j], jj = static_cast<int>(j);
        S dv = S(0), da = ld.dg_y[k](jj, c);
        for (int i = 0; i < p; ++i) {
          const S dG = ld.dG[k](jj, c * p + i);
          const int yi = st.column_of_v[static_cast<std::size_t>(sub.independent[static_cast<std::size_t>(i)])];
          dv += dG * ld.v[sub.independent[static_cast<std::size_t>(i)]];
          da += dG * ydd[yi];
        }
        ld.dV(row, column) = dv;
        ld.dQdd(row, column) = da;
        ld.dQdd_v(row, column) = ld.dg_v[k](jj, c);
      }
    }
  }
  ld.A.noalias() = ld.tree.dtau_dq * ld.T;
  ld.A.noalias() += ld.tree.dtau_dv * ld.dV;
  ld.A.noalias() += M * ld.dQdd;
  ld.R_q.noalias() = ld.T.transpose() * ld.A;
  // dT_c^T f: column c of T changes only on c's sub-system's block.
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    const int p = static_cast<int>(sub.independent.size());
    for (int c = 0; c < p; ++c) {
      const int column = st.column_of_v[static_cast<std::size_t>(sub.independent[static_cast<std::size_t>(c)])];
      for (int i = 0; i < p; ++i) {
        S x = S(0);
        for (std::size_t j = 0; j < sub.coordinates.size(); ++j) x += ld.dG[k](static_cast<int>(j), c * p + i) * ld.f[sub.coordinates[j]];
        ld.R_q(st.column_of_v[static_cast<std::size_t>(sub.independent[static_cast<std::size_t>(i)])], column) += x;
      }
    }
  }
  ld.A.noalias() = ld.tree.dtau_dv * ld.T;
  ld.A.noalias() += M * ld.dQdd_v;
  ld.R_v.noalias() = ld.T.transpose() * ld.A;
  ld.A.noalias() = M * ld.T;
  ld.M_y.noalias() = ld.T.transpose() * ld.A;
}

/// b = M_y^-1 b in place from the factor along its chains (ld.factor_entries, ld.inverse_pivot):
/// L^T z = b from the last row up, D^-1, L x = z from the first down; the generated code's row
/// loops are these sweeps (emit_derivatives.cpp).
template <typename S, typename Vector> void factor_chain_solve(const LoopDynamicsDerivatives<S>& ld, Vector&& b) {
  const int n = static_cast<int>(ld.y_parent.size());
  const auto parent = [&](int k) { return ld.y_parent[static_cast<std::size_t>(k)]; };
  for (int k = n - 1; k >= 0; --k) {
    int e = ld.factor_first[static_cast<std::size_t>(k)];
    for (int i = parent(k); i >= 0; i = parent(i), ++e) b[i] -= ld.factor_entries[e] * b[k];
  }
  for (int k = 0; k < n; ++k) b[k] *= ld.inverse_pivot[k];
  for (int k = 0; k < n; ++k) {
    int e = ld.factor_first[static_cast<std::size_t>(k)];
    for (int i = parent(k); i >= 0; i = parent(i), ++e) b[k] -= ld.factor_entries[e] * b[i];
  }
}

}  // namespace detail

/// What comes before the solves with M_y (the part the generator unrolls; it prints the solves as
/// loops over whole rows): ld.ydd, ld.dydd_dy = -R_q, ld.dydd_dyd = -R_v, ld.dydd_dtau = T^T, the
/// factor of M_y (ld.M_y_factor, and along its chains ld.factor_entries, ld.inverse_pivot), ld.T,
/// ld.M_y, ld.qdd. The status as forward_dynamics_loops_derivatives'. No allocation.
template <typename S>
ClosureStatus forward_dynamics_loops_derivatives_before_solves(const Model& model, Data<S>& data, LoopDynamicsDerivatives<S>& ld,
                                                               const ConstVecRef<S>& q, const ConstVecRef<S>& yd, const ConstVecRef<S>& tau,
                                                               const ClosureOptions& options = {}) {
  const ModelStructure& st = model.structure();
  const int ny = st.num_independent();
  forward_dynamics_loops_independent<S>(model, data, q, yd, tau);
  bool regular = true;
  if constexpr (std::is_floating_point_v<S>) regular = subsystem_pivot_ratio<S>(model, data) > S(options.singular_tolerance);
  ld.qdd = data.ddq;
  ld.v = data.v_full;
  for (int i = 0; i < ny; ++i) ld.ydd[i] = ld.qdd[st.independent_v[static_cast<std::size_t>(i)]];
  detail::velocity_map_from_maps<S>(model, data, ld.T);
  detail::closure_map_derivatives<S>(model, data, ld, q);
  inverse_dynamics_derivatives<S>(model, data, ld.tree, q, ld.v, ld.qdd);
  ld.f = ld.tree.tau - tau;
  detail::closed_residual_derivatives<S>(model, ld, crba<S>(model, data, q), ld.ydd);
  ld.M_y_factor = ld.M_y;
  ltdl_factor<S>(ld.M_y_factor, ny);
  for (int k = 0; k < ny; ++k) {
    ld.inverse_pivot[k] = ld.M_y_factor(k, k);
    int e = ld.factor_first[static_cast<std::size_t>(k)];
    for (int i = ld.y_parent[static_cast<std::size_t>(k)]; i >= 0; i = ld.y_parent[static_cast<std::size_t>(i)]) ld.factor_entries[e++] = ld.M_y_factor(k, i);
  }
  ld.dydd_dy = -ld.R_q;
  ld.dydd_dyd = -ld.R_v;
  ld.dydd_dtau = ld.T.transpose();
  if constexpr (std::is_floating_point_v<S>)  // M_y positive definite: every 1/d positive and finite
    for (int i = 0; i < ny; ++i) regular = regular && std::isfinite(ld.inverse_pivot[i]) && ld.inverse_pivot[i] > S(0);
  return regular ? ClosureStatus::Converged : ClosureStatus::Singular;
}

/// ydd (ld.ydd), dydd/dy (ld.dydd_dy), dydd/dyd (ld.dydd_dyd) and dydd/dtau (ld.dydd_dtau) of the
/// closed system at the closed configuration q (nq; closure_positions), the independent
/// velocities yd (ny) and the joint forces tau (nv), as forward_dynamics_loops_independent
/// computes ydd. Also ld.T, ld.M_y, ld.qdd. Singular (results not to be used) within
/// options.singular_tolerance of a dead point or where M_y is not positive definite. No allocation.
template <typename S>
ClosureStatus forward_dynamics_loops_derivatives(const Model& model, Data<S>& data, LoopDynamicsDerivatives<S>& ld, const ConstVecRef<S>& q,
                                                 const ConstVecRef<S>& yd, const ConstVecRef<S>& tau, const ClosureOptions& options = {}) {
  const ClosureStatus status = forward_dynamics_loops_derivatives_before_solves<S>(model, data, ld, q, yd, tau, options);
  for (int c = 0; c < ld.dydd_dy.cols(); ++c) {
    detail::factor_chain_solve<S>(ld, ld.dydd_dy.col(c));
    detail::factor_chain_solve<S>(ld, ld.dydd_dyd.col(c));
  }
  for (int c = 0; c < ld.dydd_dtau.cols(); ++c) detail::factor_chain_solve<S>(ld, ld.dydd_dtau.col(c));
  return status;
}

/// tau_y = T^T ID(q, T yd, T ydd + g) (ld.tau_y, as inverse_dynamics_independent computes it),
/// dtau_y/dy (ld.dtauy_dy) and dtau_y/dyd (ld.dtauy_dyd) at the closed configuration q, yd and
/// ydd (ny each); dtau_y/dydd is ld.M_y. Also ld.T, ld.qdd. Singular within
/// options.singular_tolerance of a dead point (results not to be used). No allocation.
template <typename S>
ClosureStatus inverse_dynamics_loops_derivatives(const Model& model, Data<S>& data, LoopDynamicsDerivatives<S>& ld, const ConstVecRef<S>& q,
                                                 const ConstVecRef<S>& yd, const ConstVecRef<S>& ydd, const ClosureOptions& options = {}) {
  subsystem_velocity_maps<S>(model, data, q);
  bool regular = true;
  if constexpr (std::is_floating_point_v<S>) regular = subsystem_pivot_ratio<S>(model, data) > S(options.singular_tolerance);
  detail::expand_independent<S>(model, data, yd, false, ld.v);
  subsystem_acceleration_biases<S>(model, data, q, ld.v);
  detail::expand_independent<S>(model, data, ydd, true, ld.qdd);
  detail::velocity_map_from_maps<S>(model, data, ld.T);
  detail::closure_map_derivatives<S>(model, data, ld, q);
  inverse_dynamics_derivatives<S>(model, data, ld.tree, q, ld.v, ld.qdd);
  ld.f = ld.tree.tau;
  detail::closed_residual_derivatives<S>(model, ld, crba<S>(model, data, q), ydd);
  ld.tau_y.noalias() = ld.T.transpose() * ld.tree.tau;
  ld.dtauy_dy = ld.R_q;
  ld.dtauy_dyd = ld.R_v;
  return regular ? ClosureStatus::Converged : ClosureStatus::Singular;
}

}  // namespace mbgen
