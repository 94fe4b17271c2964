#pragma once
// The mass matrix's sparse L^T D L factor and solves with it (Featherstone, Rigid Body Dynamics
// Algorithms, section 6.5): M = L^T D L with L unit lower triangular and L(k, i) nonzero only
// where i is an ancestor of k (model.velocity_parent). Factoring from the leaves up makes no
// fill-in: every entry the factor writes is one M already had structurally, so the work is
// sum over coordinates of depth^2 instead of nv^3 / 3, and a traced factor keeps only those.
//
// Layout of a factor (nv x nv, what mass_matrix_factor returns and generated code writes
// row-major): D on the diagonal, L strictly below it, zeros above.
#include "mbgen/algorithm/crba.hpp"

namespace mbgen {

/// Overwrites the mass matrix M (both triangles, as crba fills it) with its L^T D L factor.
/// M must be positive definite (a valid model's is); a zero pivot divides by zero.
template <typename S> void factor_mass_matrix_in_place(const Model& model, MatX<S>& M) {
  const int n = model.nv();
  for (int k = n - 1; k >= 0; --k) {
    // One division per coordinate: the ancestors' multipliers scale by 1 / D_k.
    const S inverse_pivot = S(1) / M(k, k);
    for (int i = model.velocity_parent(k); i >= 0; i = model.velocity_parent(i)) {
      const S a = M(k, i) * inverse_pivot;
      for (int j = i; j >= 0; j = model.velocity_parent(j)) M(i, j) -= a * M(k, j);
      M(k, i) = a;
    }
  }
  for (int r = 0; r < n; ++r)
    for (int c = r + 1; c < n; ++c) M(r, c) = S(0);
}

/// The L^T D L factor of the mass matrix at q (in data.M, also returned).
template <typename S> const MatX<S>& mass_matrix_factor(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  crba<S>(model, data, q);
  factor_mass_matrix_in_place<S>(model, data.M);
  return data.M;
}

/// x = M^-1 b from the factor (L^T D L x = b), in place: b holds x on return. Three sweeps over
/// the ancestors, as sparse as the factor.
template <typename S, typename Vector> void mass_matrix_solve_in_place(const Model& model, const MatX<S>& factor, Vector& b) {
  const int n = model.nv();
  // L^T z = b, from the leaves up: z_k is final once every descendant has been taken off.
  for (int k = n - 1; k >= 0; --k)
    for (int i = model.velocity_parent(k); i >= 0; i = model.velocity_parent(i)) b[i] -= factor(k, i) * b[k];
  for (int k = 0; k < n; ++k) b[k] /= factor(k, k);
  // L x = D^-1 z, from the root down.
  for (int k = 0; k < n; ++k)
    for (int i = model.velocity_parent(k); i >= 0; i = model.velocity_parent(i)) b[k] -= factor(k, i) * b[i];
}

}  // namespace mbgen
