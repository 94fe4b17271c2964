#pragma once
// LDL^T of a small symmetric positive-definite matrix without pivoting: no branch depends on the
// values, so a symbolic scalar can record it (Eigen's LDLT pivots). Used for the joint-space
// inertia D = S^T IA S of multi-DoF joints (a floating base: 6 x 6, in a Mat6) and of a
// sub-system's independent coordinates (p x p, in a MatX: a parallel leg with six actuators and
// six idle spins has p = 12). A singular matrix shows as an infinite or NaN 1/d.
#include "mbgen/spatial/types.hpp"

namespace mbgen {

/// Factors the leading n x n block of A (SPD; F at least n x n) as L diag(d) L^T. F receives L
/// strictly below its diagonal, 1/d on its diagonal (one division per pivot) and, strictly above
/// it, F(k, i) = L(i, k) d_k: the products the later columns subtract, kept so that they need no
/// division by F(k, k) = 1/d_k. Those divisions were most of a floating base's (a 6 x 6 D: 35 of
/// 41), each waiting on the pivot before it, at the end of ABA's backward pass.
template <typename S, typename MatrixA, typename MatrixF> void ldlt_factor(const MatrixA& A, int n, MatrixF& F) {
  for (int j = 0; j < n; ++j) {
    S dj = A(j, j);
    for (int k = 0; k < j; ++k) dj -= F(j, k) * F(k, j);
    F(j, j) = S(1) / dj;
    for (int i = j + 1; i < n; ++i) {
      S s = A(i, j);
      for (int k = 0; k < j; ++k) s -= F(i, k) * F(k, j);
      F(j, i) = s;
      F(i, j) = s * F(j, j);
    }
  }
}

/// Solves A x = b in place (b has n entries) from the factor F of ldlt_factor (its diagonal and
/// lower triangle).
template <typename S, typename MatrixF> void ldlt_solve(const MatrixF& F, int n, S* b) {
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < i; ++k) b[i] -= F(i, k) * b[k];
  for (int i = 0; i < n; ++i) b[i] *= F(i, i);
  for (int i = n - 1; i >= 0; --i)
    for (int k = i + 1; k < n; ++k) b[i] -= F(k, i) * b[k];
}

/// Factors the leading n x n block of A (SPD) in place as L^T D L, L unit lower triangular,
/// eliminating from the last row up (Featherstone's LTDL): for a matrix whose nonzeros follow a
/// tree with parents before children (a mass matrix, the closed system's M_y in independent
/// coordinates) there is no fill-in, so the symbolic scalar's folding of exact zeros leaves the
/// factor as sparse as the tree, where ldlt_factor's top-down order would fill it. A's lower
/// triangle receives L strictly below the diagonal and 1/d on it (one division per pivot); its
/// strict upper triangle is left as it was. No branch on values.
template <typename S, typename MatrixA> void ltdl_factor(MatrixA& A, int n) {
  for (int k = n - 1; k >= 0; --k) {
    const S inverse_pivot = S(1) / A(k, k);
    for (int i = k - 1; i >= 0; --i) {
      const S a = A(k, i) * inverse_pivot;
      for (int j = i; j >= 0; --j) A(i, j) -= a * A(k, j);
      A(k, i) = a;
    }
    A(k, k) = inverse_pivot;
  }
}

/// Solves A x = b in place (b has n entries) from ltdl_factor's L^T D L of A: L^T y = b from the
/// bottom up, y scaled by 1/d, then L x = y from the top down.
template <typename S, typename MatrixF> void ltdl_solve(const MatrixF& F, int n, S* b) {
  for (int k = n - 1; k >= 0; --k)
    for (int i = k - 1; i >= 0; --i) b[i] -= F(k, i) * b[k];
  for (int k = 0; k < n; ++k) b[k] *= F(k, k);
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < k; ++i) b[k] -= F(k, i) * b[i];
}

}  // namespace mbgen
