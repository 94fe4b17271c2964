// ldlt_factor / ldlt_solve (runtime/include/mbgen/algorithm/small_ldlt.hpp), the factor ABA
// uses for multi-DoF joints (a floating base's 6 x 6) and for sub-systems' independent
// coordinates, against Eigen's pivoted LDLT and the reconstruction L diag(d) L^T; ltdl_factor /
// ltdl_solve (the closed system's M_y in its derivatives) against the reconstruction L^T D L,
// Eigen's solve, and the no-fill-in property on a tree's sparsity.
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

// L^T D L from the bottom up: the reconstruction (1e-12 relative) and the solve against Eigen's
// (1e-11), for sizes 1 .. 12.
TEST(SmallLtdl, FactorReconstructsAndSolves) {
  std::mt19937_64 rng(13);
  double worst = 0;
  for (int n = 1; n <= 12; ++n)
    for (int trial = 0; trial < 20; ++trial) {
      const MatX<double> A = random_spd(n, rng);
      MatX<double> F = A;
      ltdl_factor<double>(F, n);
      MatX<double> L = MatX<double>::Identity(n, n);
      VecX<double> d(n);
      for (int i = 0; i < n; ++i) {
        d[i] = 1 / F(i, i);
        for (int k = 0; k < i; ++k) L(i, k) = F(i, k);
      }
      ASSERT_LT((L.transpose() * d.asDiagonal() * L - A).norm(), 1e-12 * A.norm()) << "n " << n;
      const VecX<double> b = VecX<double>::Random(n), expected = A.ldlt().solve(b);
      VecX<double> x = b;
      ltdl_solve<double>(F, n, x.data());
      worst = std::max(worst, (x - expected).norm() / expected.norm());
    }
  EXPECT_LT(worst, 1e-11);
}

// A matrix whose nonzeros follow a tree (parents first: entry (i, j) nonzero only for i an
// ancestor of j or j of i) factors without fill-in: L(k, i) is exactly zero unless i is an
// ancestor of k. (ldlt_factor's top-down order fills in the two branches' cross entries.)
TEST(SmallLtdl, ATreesSparsityHasNoFillIn) {
  // 0 - 1 - 2 and 0 - 3 - 4: two branches off a root.
  const int parent[] = {-1, 0, 1, 0, 3};
  const auto ancestor = [&](int a, int k) {
    for (int i = k; i >= 0; i = parent[i])
      if (i == a) return true;
    return false;
  };
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.1, 1);
  MatX<double> A = MatX<double>::Zero(5, 5);
  for (int i = 0; i < 5; ++i) {
    A(i, i) = 10;
    for (int j = 0; j < i; ++j)
      if (ancestor(j, i)) A(i, j) = A(j, i) = u(rng);
  }
  MatX<double> F = A;
  ltdl_factor<double>(F, 5);
  for (int k = 0; k < 5; ++k)
    for (int i = 0; i < k; ++i)
      if (!ancestor(i, k)) {
        EXPECT_EQ(F(k, i), 0.0) << k << ", " << i;
      }
  MatX<double> G(5, 5);
  ldlt_factor<double>(A, 5, G);
  EXPECT_NE(G(3, 1), 0.0) << "the top-down factor fills the cross entry in";
}

}  // namespace
}  // namespace mbgen
