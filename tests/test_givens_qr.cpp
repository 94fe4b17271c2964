// givens_qr_factor / givens_qr_apply / upper_triangular_solve (runtime/include/mbgen/algorithm/
// givens_qr.hpp), the factor of each sub-system's Phi_z: solves against Eigen's LU with full
// pivoting, and R against Q^T A.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <initializer_list>
#include <random>

#include "mbgen/algorithm/givens_qr.hpp"

namespace mbgen {
namespace {

// A X = B for n = 1..8 and 1..3 right-hand sides, A random plus a multiple of the identity
// (condition ~10-100): 1e-12 relative to X.
TEST(GivensQr, SolvesLikeLu) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1, 1);
  double worst = 0;
  for (int n = 1; n <= 8; ++n)
    for (int m = 1; m <= 3; ++m)
      for (int trial = 0; trial < 20; ++trial) {
        MatX<double> A(n, n), B(n, m);
        for (int i = 0; i < n; ++i) {
          for (int j = 0; j < n; ++j) A(i, j) = u(rng) + (i == j ? 2.0 : 0.0);
          for (int j = 0; j < m; ++j) B(i, j) = u(rng);
        }
        const MatX<double> expected = A.fullPivLu().solve(B);
        MatX<double> R = A, X = B;
        VecX<double> c(n * (n - 1) / 2), s(n * (n - 1) / 2);
        givens_qr_factor<double>(R, n, c, s);
        givens_qr_apply<double>(c, s, n, X, m);
        upper_triangular_solve<double>(R, n, X, m);
        worst = std::max(worst, (X - expected).norm() / expected.norm());
        // Q^T A = R: the rotations applied to A itself.
        MatX<double> QtA = A;
        givens_qr_apply<double>(c, s, n, QtA, n);
        ASSERT_LT((QtA - R).norm(), 1e-13 * A.norm()) << "n " << n;
      }
  EXPECT_LT(worst, 1e-12);
}

// Each rotation sets the entry it keeps to the norm r of the column part below it, and the one it
// zeroes to exactly 0: R's diagonal is non-negative (but for the last entry, which no rotation reaches), its strictly lower part is 0 bit for bit (the
// rotations' c a + s b and c b - s a left rounding there), and R(0, 0) is the first column's
// norm. Columns with zeros at the bottom and in the middle: a zero entry is skipped (the identity)
// and the next rotation squares its b itself; below a rotated entry it takes the sum of squares.
TEST(GivensQr, DiagonalIsTheColumnNormAndBelowItExactZeros) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n = 1; n <= 8; ++n)
    for (int trial = 0; trial < 20; ++trial) {
      MatX<double> A(n, n);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) A(i, j) = u(rng);
      MatX<double> R = A;
      VecX<double> c(n * (n - 1) / 2), s(n * (n - 1) / 2);
      givens_qr_factor<double>(R, n, c, s);
      for (int i = 0; i < n; ++i) {
        if (i < n - 1) {
          EXPECT_GE(R(i, i), 0.0);  // the last column has no rotation: its entry keeps its sign
        }
        for (int j = 0; j < i; ++j) EXPECT_EQ(R(i, j), 0.0) << i << "," << j;
      }
      if (n > 1) {
        EXPECT_NEAR(R(0, 0), A.col(0).norm(), 2e-15 * A.col(0).norm());
      }
      for (int k = 0; k < c.size(); ++k) EXPECT_NEAR(c[k] * c[k] + s[k] * s[k], 1.0, 2e-15);
    }
  const auto first_pivot = [](std::initializer_list<double> column) {
    const int n = static_cast<int>(column.size());
    MatX<double> A = MatX<double>::Identity(n, n);
    int i = 0;
    for (double x : column) A(i++, 0) = x;
    VecX<double> c(n * (n - 1) / 2), s(n * (n - 1) / 2);
    givens_qr_factor<double>(A, n, c, s);
    return A(0, 0);
  };
  EXPECT_EQ(first_pivot({1, 2, 3, 0}), std::sqrt(14.0));  // 0 + 9 + 4 + 1, the bottom rotation skipped
  EXPECT_EQ(first_pivot({1, 2, 0, 4}), std::sqrt(21.0));  // 16, + 4, + 1
  EXPECT_EQ(first_pivot({0, 0, 0, 5}), 5.0);
}

// A zero pivot: the solve's 1 / R(i, i) is infinite, and the result is not finite.
TEST(GivensQr, SingularMatrixGivesANonFiniteSolution) {
  MatX<double> A(2, 2);
  A << 1, 2, 2, 4;
  MatX<double> R = A, X(2, 1);
  X << 1, 1;
  VecX<double> c(1), s(1);
  givens_qr_factor<double>(R, 2, c, s);
  R(1, 0) = 0;
  R(1, 1) = 0;  // exactly singular, as a structural zero pivot
  givens_qr_apply<double>(c, s, 2, X, 1);
  upper_triangular_solve<double>(R, 2, X, 1);
  EXPECT_FALSE(std::isfinite(X(0, 0)) && std::isfinite(X(1, 0)));
}

}  // namespace
}  // namespace mbgen
