#pragma once
// QR by Givens rotations of a small square matrix, without pivoting: no branch depends on the
// values (a rotation is skipped only where the entry to zero is a structural, exact zero), so a
// symbolic scalar can record it, and orthogonal transformations keep it stable where LU without
// pivoting is not. Used for each sub-system's dependent block Phi_z (a rank x rank matrix).
//
// Two entries can also be zero by value only: Phi_z of loops that merely share a body has
// blocks of rows that rotations leave exactly zero in each other's columns (wl16_like's, away
// from the closed pose). A symbolic scalar cannot skip those, so the rotation is guarded:
// with h = 1 / max(r, tiny), c = a h + (1 - r h) and s = b h are a / r and b / r to rounding
// for r >= tiny (r h is 1 within an ulp, so c and s stay a rotation to rounding) and the
// identity for r = 0. The max is the one value-dependent choice the tracer records (a select
// in the generated code). One division per rotation, not three: the divider does not pipeline,
// and a sub-system's QR is a chain of rotations (the generated closure_positions of
// cassie_like and digit_like_2legs 5-7 % faster).
#include <algorithm>
#include <cmath>
#include <limits>

#include "mbgen/spatial/types.hpp"

namespace mbgen {

/// Reduces the leading n x n block of A to R (upper triangular) by rotations of adjacent rows,
/// recording each rotation's cosine and sine in c, s (n (n - 1) / 2 entries each, in order).
/// A singular A shows as a zero (or, from 0 / 0, NaN) diagonal entry of R.
template <typename S> void givens_qr_factor(MatX<S>& A, int n, VecX<S>& c, VecX<S>& s) {
  using std::max;
  using std::sqrt;
  // Float's smallest normal: the generated float code uses the same constant.
  const S tiny = S(std::numeric_limits<float>::min());
  int k = 0;
  for (int j = 0; j < n; ++j) {
    // Column j's rotations run up from its last row; each leaves the norm r of the part below it
    // in A(i - 1, j) (c a + s b = r exactly) and 0 in A(i, j), set rather than computed, and the
    // next rotation takes r^2 as the sum it had under its square root. So the column's chain is
    // one multiplication and one addition per rotation; the square roots and divisions hang off it
    // and overlap (they were on it: a rotation's b was the previous one's c a + s b).
    S b2 = A(n - 1, j) * A(n - 1, j);  // the square of the next rotation's b
    for (int i = n - 1; i > j; --i, ++k) {
      const S a = A(i - 1, j), b = A(i, j);
      if (b == S(0)) {  // already zero (structurally, for a symbolic scalar): the identity rotation
        c[k] = S(1);
        s[k] = S(0);
        b2 = a * a;  // the next rotation's b is this a, unrotated
        continue;
      }
      b2 = a * a + b2;  // r^2, and the next rotation's b^2
      const S r = sqrt(b2);
      const S h = S(1) / max(r, tiny);
      c[k] = a * h + (S(1) - r * h);
      s[k] = b * h;
      A(i - 1, j) = r;
      A(i, j) = S(0);
      for (int col = j + 1; col < n; ++col) {
        const S x = A(i - 1, col), y = A(i, col);
        A(i - 1, col) = c[k] * x + s[k] * y;
        A(i, col) = c[k] * y - s[k] * x;
      }
    }
  }
}

/// Applies the recorded rotations to the first m columns of B (n rows): B <- Q^T B.
template <typename S, typename Block> void givens_qr_apply(const VecX<S>& c, const VecX<S>& s, int n, Block&& B, int m) {
  int k = 0;
  for (int j = 0; j < n; ++j)
    for (int i = n - 1; i > j; --i, ++k) {
      if (s[k] == S(0) && c[k] == S(1)) continue;
      for (int col = 0; col < m; ++col) {
        const S x = B(i - 1, col), y = B(i, col);
        B(i - 1, col) = c[k] * x + s[k] * y;
        B(i, col) = c[k] * y - s[k] * x;
      }
    }
}

/// Solves R X = B in place for the first m columns of B (R upper triangular, n x n). Each row
/// divides once, for 1 / R(i, i), which depends on R alone: the substitution's chain from row to
/// row is then multiplications and subtractions, not a division per row and column.
template <typename S, typename Block> void upper_triangular_solve(const MatX<S>& R, int n, Block&& B, int m) {
  for (int i = n - 1; i >= 0; --i) {
    const S inverse_pivot = S(1) / R(i, i);
    for (int col = 0; col < m; ++col) {
      S x = B(i, col);
      for (int k = i + 1; k < n; ++k) x -= R(i, k) * B(k, col);
      B(i, col) = x * inverse_pivot;
    }
  }
}

}  // namespace mbgen
