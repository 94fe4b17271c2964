// givens_qr_factor / givens_qr_apply / upper_triangular_solve (runtime/include/mbgen/algorithm/
// givens_qr.hpp), the factor of each sub-system's Phi_z: solves against Eigen's LU with full
// pivoting, and R against Q^T A.
#include <gtest/gtest.h>

#include <Eigen/LU>
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
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < i; ++j) R(i, j) = 0;  // what the rotations leave there is rounding
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
