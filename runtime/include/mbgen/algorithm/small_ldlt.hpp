#pragma once
// Inverse of a small symmetric positive-definite matrix by LDL^T without pivoting: no branch
// depends on the values, so a symbolic scalar can record it (Eigen's LDLT pivots).
#include "mbgen/spatial/types.hpp"

namespace mbgen {

/// Writes the inverse of the leading n x n block of A (SPD, n <= 6) into the same block of out.
template <typename S> void spd_inverse(const Mat6<S>& A, int n, Mat6<S>& out) {
  S L[6][6];
  S d[6];
  for (int j = 0; j < n; ++j) {
    S dj = A(j, j);
    for (int k = 0; k < j; ++k) dj -= L[j][k] * L[j][k] * d[k];
    d[j] = dj;
    for (int i = j + 1; i < n; ++i) {
      S s = A(i, j);
      for (int k = 0; k < j; ++k) s -= L[i][k] * L[j][k] * d[k];
      L[i][j] = s / dj;
    }
  }
  // Solve A x = e_c column by column: L y = e_c, D z = y, L^T x = z.
  for (int c = 0; c < n; ++c) {
    S y[6];
    for (int i = 0; i < n; ++i) {
      S s = i == c ? S(1) : S(0);
      for (int k = c; k < i; ++k) s -= L[i][k] * y[k];
      y[i] = i < c ? S(0) : s;
    }
    for (int i = 0; i < n; ++i) y[i] = y[i] / d[i];
    for (int i = n - 1; i >= 0; --i) {
      S s = y[i];
      for (int k = i + 1; k < n; ++k) s -= L[k][i] * out(k, c);
      out(i, c) = s;
    }
  }
}

}  // namespace mbgen
