// ldlt_factor / ldlt_solve (runtime/include/mbgen/algorithm/small_ldlt.hpp), the factor ABA
// uses for multi-DoF joints (a floating base's 6 x 6) and for sub-systems' independent
// coordinates, against Eigen's pivoted LDLT and the reconstruction L diag(d) L^T.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "mbgen/algorithm/small_ldlt.hpp"

namespace mbgen {
namespace {

/// A random symmetric positive-definite n x n matrix, condition ~1e2 to 1e3.
MatX<double> random_spd(int n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  MatX<double> B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = u(rng);
  return B * B.transpose() + 0.05 * MatX<double>::Identity(n, n);
}

// The factor's three parts: L below the diagonal, 1/d on it, L(i, k) d_k above it (the products
// the factor subtracts instead of dividing by 1/d_k). 1e-12 relative to the matrix.
TEST(SmallLdlt, FactorReconstructsTheMatrixAndKeepsScaledProductsAbove) {
  std::mt19937_64 rng(11);
  for (int n = 1; n <= 12; ++n) {
    for (int trial = 0; trial < 20; ++trial) {
      const MatX<double> A = random_spd(n, rng);
      MatX<double> F = MatX<double>::Constant(n, n, 1e300);
      ldlt_factor<double>(A, n, F);
      MatX<double> L = MatX<double>::Identity(n, n);
      VecX<double> d(n);
      for (int i = 0; i < n; ++i) {
        d[i] = 1 / F(i, i);
        for (int k = 0; k < i; ++k) L(i, k) = F(i, k);
      }
      const MatX<double> rebuilt = L * d.asDiagonal() * L.transpose();
      ASSERT_LT((rebuilt - A).norm(), 1e-12 * A.norm()) << "n " << n;
      for (int i = 0; i < n; ++i)
        for (int k = 0; k < i; ++k) ASSERT_NEAR(F(k, i), L(i, k) * d[k], 1e-12 * A.norm()) << "n " << n << " (" << k << ", " << i << ")";
    }
  }
}

// The solve against Eigen's pivoted LDLT, in a Mat6 as ABA holds a floating base's factor.
TEST(SmallLdlt, SolveMatchesEigen) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1, 1);
  double worst = 0;
  for (int n = 1; n <= 6; ++n) {
    for (int trial = 0; trial < 50; ++trial) {
      const MatX<double> A = random_spd(n, rng);
      Mat6<double> F = Mat6<double>::Zero();
      ldlt_factor<double>(A, n, F);
      VecX<double> b(n);
      for (int i = 0; i < n; ++i) b[i] = u(rng);
      const VecX<double> expected = A.ldlt().solve(b);
      VecX<double> x = b;
      ldlt_solve<double>(F, n, x.data());
      worst = std::max(worst, (x - expected).norm() / expected.norm());
    }
  }
  // Condition numbers up to ~1e3: both solves are good to ~1e-13.
  EXPECT_LT(worst, 1e-11);
}

// A singular matrix shows as a non-finite 1/d, not as a plausible factor.
TEST(SmallLdlt, SingularMatrixGivesANonFinitePivot) {
  MatX<double> A(3, 3);
  A << 1, 2, 3, 2, 4, 6, 3, 6, 10;  // the second row is twice the first
  MatX<double> F(3, 3);
  ldlt_factor<double>(A, 3, F);
  EXPECT_FALSE(std::isfinite(F(1, 1)));
}

}  // namespace
}  // namespace mbgen
