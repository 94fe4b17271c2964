#pragma once
// LDL^T of a symmetric positive-definite matrix of any (run-time) size, without pivoting, as
// small_ldlt.hpp does for n <= 6: no branch depends on the values, so a symbolic scalar can record
// it. Used for the p x p joint-space inertia of a sub-system's independent coordinates (a
// parallel leg with six actuators and six idle spins has p = 12).
#include "mbgen/spatial/types.hpp"

namespace mbgen {

/// Factors the leading n x n block of A as L diag(d) L^T. F (at least n x n, allocated by the
/// caller) receives L strictly below its diagonal and 1/d on its diagonal (a singular A shows as
/// an infinite or NaN 1/d, which double and float callers check).
template <typename S> void dense_ldlt_factor(const MatX<S>& A, int n, MatX<S>& F) {
  for (int j = 0; j < n; ++j) {
    S dj = A(j, j);
    for (int k = 0; k < j; ++k) dj -= F(j, k) * F(j, k) / F(k, k);
    F(j, j) = S(1) / dj;
    for (int i = j + 1; i < n; ++i) {
      S s = A(i, j);
      for (int k = 0; k < j; ++k) s -= F(i, k) * F(j, k) / F(k, k);
      F(i, j) = s * F(j, j);
    }
  }
}

/// Solves A x = b in place (b has n entries) from the factor F of dense_ldlt_factor.
template <typename S> void dense_ldlt_solve(const MatX<S>& F, int n, S* b) {
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < i; ++k) b[i] -= F(i, k) * b[k];
  for (int i = 0; i < n; ++i) b[i] *= F(i, i);
  for (int i = n - 1; i >= 0; --i)
    for (int k = i + 1; k < n; ++k) b[i] -= F(k, i) * b[k];
}

}  // namespace mbgen
