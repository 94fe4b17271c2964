#pragma once
// Derivatives of the spanning tree's forward dynamics qdd = FD(q, v, tau). From M(q) qdd + h(q, v) = tau,
// differentiating at fixed tau: M dqdd + dID(q, v, qdd) = 0, so
//   dqdd/dq = -M^-1 dtau/dq (q, v, qdd),  dqdd/dv = -M^-1 dtau/dv (q, v, qdd),  dqdd/dtau = M^-1,
// the inverse dynamics' derivatives (rnea_derivatives.hpp) taken at the accelerations the forward
// dynamics returns. M^-1 is applied with the mass matrix's sparse L^T D L factor
// (mass_matrix_factor.hpp): L unit lower triangular with L(k, i) nonzero only for i an ancestor of
// k, so each solve is as sparse as the factor. M^-1 itself is Z^T D^-1 Z with Z = L^-T, whose column
// k is nonzero only at k's ancestors: M^-1(r, k) sums over the ancestors r and k share (the floating
// base's six for two limbs), a fifth of the work of nv solves. The generator traces
// forward_dynamics_derivatives_before_solves (M^-1 included) and prints the two solves as loops
// over whole rows (emit_derivatives.hpp): the same factor and sweeps.
// Same tangent convention for q as rnea_derivatives.hpp.
#include "mbgen/algorithm/mass_matrix_factor.hpp"
#include "mbgen/algorithm/rnea.hpp"
#include "mbgen/algorithm/rnea_derivatives.hpp"

namespace mbgen {

namespace detail {
/// x = M^-1 x in place from the factor and its inverse pivots (mass_matrix_solve_in_place with
/// multiplications for the divisions).
template <typename S, typename Vector>
void factor_solve(const Model& model, const MatX<S>& factor, const VecX<S>& inverse_pivot, Vector&& b) {
  const int n = model.nv();
  for (int k = n - 1; k >= 0; --k)
    for (int i = model.velocity_parent(k); i >= 0; i = model.velocity_parent(i)) b[i] -= factor(k, i) * b[k];
  for (int k = 0; k < n; ++k) b[k] *= inverse_pivot[k];
  for (int k = 0; k < n; ++k)
    for (int i = model.velocity_parent(k); i >= 0; i = model.velocity_parent(i)) b[k] -= factor(k, i) * b[i];
}

/// From M's factor L (mass_matrix_factor): its entries of ancestor pairs in d.factor_entries, 1 / D
/// in d.inverse_pivot (the tables the solves read), and M^-1 in d.Minv.
template <typename S> void mass_matrix_factor_tables(const Model& model, const MatX<S>& L, DynamicsDerivatives<S>& d) {
  const int n = model.nv();
  int e = 0;
  for (int k = 0; k < n; ++k) {
    d.inverse_pivot[k] = S(1) / L(k, k);
    for (int i = model.velocity_parent(k); i >= 0; i = model.velocity_parent(i)) d.factor_entries[e++] = L(k, i);
  }
  // Z = L^-T column by column (L^T z = e_k from the leaves up touches k's ancestors only), Y = D^-1 Z.
  d.Z.setZero();
  for (int k = 0; k < n; ++k) {
    d.Z(k, k) = S(1);
    for (int j = k; j >= 0; j = model.velocity_parent(j))
      for (int i = model.velocity_parent(j); i >= 0; i = model.velocity_parent(i)) d.Z(i, k) -= L(j, i) * d.Z(j, k);
    for (int i = k; i >= 0; i = model.velocity_parent(i)) d.Y(i, k) = d.Z(i, k) * d.inverse_pivot[i];
  }
  // M^-1(r, k) = sum over k's ancestors i of Z(i, r) Y(i, k) (Z(i, r) = 0 unless i is r's too).
  for (int k = 0; k < n; ++k)
    for (int r = k; r < n; ++r) {
      S x = S(0);
      for (int i = k; i >= 0; i = model.velocity_parent(i)) x += d.Z(i, r) * d.Y(i, k);
      d.Minv(r, k) = x;
      d.Minv(k, r) = x;
    }
}
}  // namespace detail

/// What comes before the solves with M (the part the generator unrolls; the solves it prints as
/// loops over whole rows, docs/derivatives.md): d.ddq = qdd at (q, v, tau), d.dddq_dq = -dtau/dq and
/// d.dddq_dv = -dtau/dv at (q, v, qdd), the factor of M in data.M, its entries of ancestor pairs in
/// d.factor_entries, 1 / D in d.inverse_pivot, and M^-1 in d.Minv. No allocation.
template <typename S>
void forward_dynamics_derivatives_before_solves(const Model& model, Data<S>& data, DynamicsDerivatives<S>& d,
                                                const ConstVecRef<S>& q, const ConstVecRef<S>& v, const ConstVecRef<S>& tau) {
  // qdd from the factor the solves need anyway (M qdd = tau - h, h the inverse dynamics at qdd = 0)
  // rather than from the articulated-body algorithm: the bias sweep and one solve cost less than
  // a second recursion (talos_reduced, traced: 63,571 -> 59,551 operations).
  // The solve multiplies by the tables' inverse pivots: no division of its own.
  const MatX<S>& factor = mass_matrix_factor<S>(model, data, q);
  detail::mass_matrix_factor_tables<S>(model, factor, d);
  d.ddq = tau - nonlinear_effects<S>(model, data, q, v);
  detail::factor_solve<S>(model, factor, d.inverse_pivot, d.ddq);
  inverse_dynamics_derivatives<S>(model, data, d, q, v, d.ddq);
  d.dddq_dq = -d.dtau_dq;
  d.dddq_dv = -d.dtau_dv;
}

/// The solves that finish forward_dynamics_derivatives_before_solves: d.dddq_dq and d.dddq_dv
/// times M^-1 in place, from the factor in data.M. No allocation.
template <typename S> void forward_dynamics_derivatives_solves(const Model& model, const Data<S>& data, DynamicsDerivatives<S>& d) {
  for (int k = 0; k < model.nv(); ++k) {
    detail::factor_solve<S>(model, data.M, d.inverse_pivot, d.dddq_dq.col(k));
    detail::factor_solve<S>(model, data.M, d.inverse_pivot, d.dddq_dv.col(k));
  }
}

/// qdd (d.ddq), dqdd/dq (d.dddq_dq), dqdd/dv (d.dddq_dv) and M^-1 (d.Minv) of the spanning tree at
/// (q, v, tau); d.tau, d.dtau_dq and d.dtau_dv hold the inverse dynamics' at (q, v, qdd), and
/// data.M the mass matrix's factor. No allocation.
template <typename S>
void forward_dynamics_derivatives(const Model& model, Data<S>& data, DynamicsDerivatives<S>& d, const ConstVecRef<S>& q,
                                  const ConstVecRef<S>& v, const ConstVecRef<S>& tau) {
  forward_dynamics_derivatives_before_solves<S>(model, data, d, q, v, tau);
  forward_dynamics_derivatives_solves<S>(model, data, d);
}

}  // namespace mbgen
