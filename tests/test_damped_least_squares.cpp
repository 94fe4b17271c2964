// Damped least squares with its null-space projector (runtime/include/mbgen/control/damped_least_squares.hpp),
// against independent closed forms:
//  - constant damping (no singular region): A^T (A A^T + lambda^2 I)^-1 e by an LDL^T of the
//    m x m normal matrix, to 1e-12 relative;
//  - no damping at a regular A: Eigen's complete orthogonal decomposition pseudo-inverse, and
//    A x = e, to 1e-12;
//  - the damping schedule at the singular (stretched) pose of a planar two-link arm: the
//    per-eigenvalue formula from an eigen-decomposition of J J^T, bounded by |e| / (2 lambda)
//    along the lost direction, and continuous as the arm approaches the singularity;
//  - the projector: symmetric, idempotent, A N = 0 (1e-14 |A|), rank of a rank-deficient A, and
//    the rank with a singular value 100 times above / below the rank tolerance;
//  - no allocation in compute / solve / project_to_null.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <cstdio>
#include <random>

#include "malloc_guard.hpp"
#include "mbgen/control/damped_least_squares.hpp"

namespace mbgen::test {
namespace {

using control::DampedLeastSquares;
using control::DampingOptions;

MatX<double> random_matrix(int m, int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  MatX<double> A(m, n);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = u(rng);
  return A;
}

/// Null-space projector of dls as a dense matrix (n x n), column by column.
MatX<double> projector(DampedLeastSquares<double>& dls, int n) {
  MatX<double> N(n, n);
  VecX<double> e(n);
  for (int j = 0; j < n; ++j) {
    e.setZero();
    e[j] = 1;
    dls.project_to_null(e);
    N.col(j) = e;
  }
  return N;
}

TEST(DampedLeastSquares, ConstantDampingIsTheClassicalClosedForm) {
  const MatX<double> A = random_matrix(6, 10, 1);
  const VecX<double> e = random_matrix(6, 1, 2);
  for (double lambda : {1e-3, 0.1, 1.0}) {
    DampedLeastSquares<double> dls(6, 10, DampingOptions{lambda, 0.0, 0.0, 1e-10});
    ASSERT_TRUE(dls.compute(A));
    VecX<double> x(10);
    dls.solve(e, x);
    const MatX<double> normal = A * A.transpose() + lambda * lambda * MatX<double>::Identity(6, 6);
    const VecX<double> reference = A.transpose() * normal.ldlt().solve(e);
    EXPECT_LT((x - reference).norm(), 1e-12 * reference.norm()) << "lambda " << lambda;
  }
}

// Copied and moved before its first compute() (a controller built by value), the solver is a
// whole object: the copies give a fresh solver's solution bit for bit, and the sanitized build
// finds no unset status read (Eigen's sized LLT and eigen-solver leave theirs unset; issue 61).
TEST(DampedLeastSquares, CopiedAndMovedBeforeFirstComputeIsWhole) {
  const MatX<double> A = random_matrix(6, 10, 5);
  const VecX<double> e = random_matrix(6, 1, 6);
  const DampingOptions options{0.0, 1e-1, 0.1, 1e-10};
  DampedLeastSquares<double> original(6, 10, options);
  DampedLeastSquares<double> copied(original);
  DampedLeastSquares<double> moved(std::move(original));
  DampedLeastSquares<double> fresh(6, 10, options);
  VecX<double> expected(10), x(10);
  ASSERT_TRUE(fresh.compute(A));
  fresh.solve(e, expected);
  for (DampedLeastSquares<double>* dls : {&copied, &moved}) {
    ASSERT_TRUE(dls->compute(A));
    dls->solve(e, x);
    EXPECT_EQ(x, expected);
  }
}

TEST(DampedLeastSquares, RegularMatrixGivesTheExactMinimumNormSolution) {
  const MatX<double> A = random_matrix(6, 10, 3);
  const VecX<double> e = random_matrix(6, 1, 4);
  // The singular region is below every singular value of A: no damping at all.
  DampedLeastSquares<double> dls(6, 10, DampingOptions{0.0, 1e-3, 0.1, 1e-10});
  ASSERT_TRUE(dls.compute(A));
  ASSERT_GT(dls.smallest_singular_value(), 1e-3);
  VecX<double> x(10);
  dls.solve(e, x);
  const VecX<double> reference = A.completeOrthogonalDecomposition().pseudoInverse() * e;
  EXPECT_LT((x - reference).norm(), 1e-12 * reference.norm());
  EXPECT_LT((A * x - e).norm(), 1e-12 * e.norm());
  EXPECT_EQ(dls.rank(), 6);
}

TEST(DampedLeastSquares, ProjectorIsOrthogonalAndAnnihilatesTheRowSpace) {
  // Rank 4: the last two rows are combinations of the first four.
  MatX<double> A = random_matrix(6, 10, 5);
  A.row(4) = 0.3 * A.row(0) - 2.0 * A.row(3);
  A.row(5) = A.row(1) + A.row(2);
  DampedLeastSquares<double> dls(6, 10);
  ASSERT_TRUE(dls.compute(A));
  EXPECT_EQ(dls.rank(), 4);
  const MatX<double> N = projector(dls, 10);
  const double scale = A.norm();
  EXPECT_LT((A * N).cwiseAbs().maxCoeff(), 1e-14 * scale);
  EXPECT_LT((N - N.transpose()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((N * N - N).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_NEAR(N.trace(), 6.0, 1e-13);  // dimension of the null space: 10 - 4
}

// The projector's two halves (to_null_space, from_null_space) applied to several columns at once
// compose to the projector applied column by column, and products taken between them are the
// projected vectors' products: on a rank-deficient A (the pivoted QR) and a regular one (the fast
// path's unpivoted QR).
TEST(DampedLeastSquares, NullSpaceCoordinatesComposeToTheProjector) {
  MatX<double> deficient = random_matrix(6, 10, 21);
  deficient.row(5) = deficient.row(0) - 0.5 * deficient.row(2);
  for (const MatX<double>& A : {deficient, random_matrix(6, 10, 22)}) {
    DampedLeastSquares<double> dls(6, 10, DampingOptions{0.0, 1e-3, 1e-3, 1e-10});
    ASSERT_TRUE(dls.compute(A));
    const MatX<double> N = projector(dls, 10);
    const MatX<double> Y = random_matrix(10, 4, 23);
    Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> Z = Y;
    dls.to_null_space(Z);
    EXPECT_LT((Z.topRows(dls.rank())).cwiseAbs().maxCoeff(), 1e-300) << "D0 zeroes the first rank rows";
    const MatX<double> gram = Z.transpose() * Z, projected_gram = (N * Y).transpose() * (N * Y);
    EXPECT_LT((gram - projected_gram).cwiseAbs().maxCoeff(), 1e-14 * projected_gram.norm()) << "rank " << dls.rank();
    dls.from_null_space(Z);
    EXPECT_LT((MatX<double>(Z) - N * Y).cwiseAbs().maxCoeff(), 1e-14 * Y.norm()) << "rank " << dls.rank();
    EXPECT_LT((A * MatX<double>(Z)).cwiseAbs().maxCoeff(), 1e-14 * A.norm() * Y.norm());
  }
}

TEST(DampedLeastSquares, NullSpaceBasisIsOrthonormalAndSpansTheProjector) {
  MatX<double> deficient = random_matrix(6, 10, 24);
  deficient.row(5) = deficient.row(0) - 0.5 * deficient.row(2);
  for (const MatX<double>& A : {deficient, random_matrix(6, 10, 25), random_matrix(12, 30, 26)}) {
    const int m = static_cast<int>(A.rows()), n = static_cast<int>(A.cols());
    DampedLeastSquares<double> dls(m, n, DampingOptions{0.0, 1e-3, 1e-3, 1e-10});
    ASSERT_TRUE(dls.compute(A));
    MatX<double> Z = MatX<double>::Constant(n, n, 7.0);
    const int k = dls.null_space_basis(Z);
    ASSERT_EQ(k, n - dls.rank());
    const MatX<double> basis = Z.leftCols(k);
    EXPECT_LT((basis.transpose() * basis - MatX<double>::Identity(k, k)).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_LT((basis * basis.transpose() - projector(dls, n)).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_LT((A * basis).cwiseAbs().maxCoeff(), 1e-14 * A.norm());
    EXPECT_EQ(Z.rightCols(n - k), MatX<double>::Constant(n, n - k, 7.0)) << "the columns past k stay untouched";
  }
}

/// U diag(s) V^T (m x n) with seeded random orthogonal U, V; returns V too.
MatX<double> with_singular_values(int m, int n, const VecX<double>& s, unsigned seed, MatX<double>& V) {
  const MatX<double> U = Eigen::HouseholderQR<MatX<double>>(random_matrix(m, m, seed)).householderQ();
  V = Eigen::HouseholderQR<MatX<double>>(random_matrix(n, n, seed + 1)).householderQ();
  MatX<double> S = MatX<double>::Zero(m, n);
  for (int i = 0; i < s.size(); ++i) S(i, i) = s[i];
  return U * S * V.transpose();
}

TEST(DampedLeastSquares, ProjectorRankFollowsTheToleranceAtTinySingularValues) {
  // 18 x 38, singular values 3 .. 0.5 and a last one 100 times above or below the rank
  // tolerance (1e-10 relative): 1e-8 is a direction the task sees (the projector must remove it),
  // 1e-12 is null space (the projector must keep it). A projector of the wrong rank fails the
  // trace and the check on v_17, the right singular vector of the tiny singular value.
  // With no singular region (0) every bound passes the fast path's first test, so its unpivoted
  // QR must find the rank from the tolerance alone: 1e-8 takes the fast path, 1e-12 must not.
  for (const double region : {1e-2, 0.0})
  for (const double tiny : {1e-8, 1e-12}) {
    VecX<double> s = VecX<double>::LinSpaced(18, 3.0, 0.5);
    s[17] = tiny;
    MatX<double> V;
    const MatX<double> A = with_singular_values(18, 38, s, 11, V);
    DampedLeastSquares<double> dls(18, 38, DampingOptions{0.0, region, 1e-2, 1e-10});
    ASSERT_TRUE(dls.compute(A));
    const int expected_rank = tiny > 1e-10 * 3.0 ? 18 : 17;
    EXPECT_EQ(dls.rank(), expected_rank) << "tiny " << tiny;
    EXPECT_EQ(dls.exact_singular_values(), !(region == 0.0 && expected_rank == 18)) << "tiny " << tiny << ", region " << region;
    const MatX<double> N = projector(dls, 38);
    EXPECT_NEAR(N.trace(), 38.0 - expected_rank, 1e-13) << "tiny " << tiny;
    // A wrong rank fails here by orders of magnitude. Rank 18: A N = 0 to round-off (keeping the
    // direction of the 1e-8 singular value would leave |A N| = 1e-8). Its singular vector v17 is
    // removed up to its own uncertainty: the constructed A carries rounding errors ~u |A|, which
    // tilt v17 towards the null space (singular value 0) by ~1e-15 / 1e-8 = 1e-7, for an SVD
    // just as here. Rank 17: v17 is kept, |N v17| = 1 (its tilt towards the range is
    // ~1e-15 / 0.5), and A N = A v17 v17^T-like terms of size 1e-12.
    VecX<double> v17 = V.col(17);
    dls.project_to_null(v17);
    if (expected_rank == 18) {
      EXPECT_LT(v17.norm(), 1e-6) << "tiny " << tiny;
      EXPECT_LT((A * N).cwiseAbs().maxCoeff(), 1e-14) << "tiny " << tiny;
    } else {
      EXPECT_NEAR(v17.norm(), 1.0, 1e-13) << "tiny " << tiny;
      EXPECT_LT((A * N).cwiseAbs().maxCoeff(), 2e-12) << "tiny " << tiny;
    }
    // Singular values, decreasing, to an absolute 1e-14 (3 sigma_max u x a few): the tiny one
    // too, which the square root of a Gram eigenvalue could only give to ~1e-8.
    // The fast path has no singular values, only its bound: at most sigma_min, and within
    // sqrt(18) of it (1 / |R^-1|_F, the Frobenius norm of the inverse).
    if (!dls.exact_singular_values()) {
      EXPECT_LE(dls.smallest_singular_value(), tiny * (1 + 1e-6));
      EXPECT_GE(dls.smallest_singular_value(), tiny / std::sqrt(18.0));
      continue;
    }
    for (int i = 0; i < 18; ++i) EXPECT_NEAR(dls.singular_values()[i], s[i], 1e-14) << "tiny " << tiny << " i " << i;
    EXPECT_NEAR(dls.smallest_singular_value(), tiny, 1e-14);
  }
}

/// Jacobian of the tip of a planar two-link arm (lengths l1, l2) at angles q1, q2.
Eigen::Matrix2d two_link_jacobian(double q1, double q2, double l1 = 0.5, double l2 = 0.4) {
  Eigen::Matrix2d J;
  J << -l1 * std::sin(q1) - l2 * std::sin(q1 + q2), -l2 * std::sin(q1 + q2),  //
      l1 * std::cos(q1) + l2 * std::cos(q1 + q2), l2 * std::cos(q1 + q2);
  return J;
}

TEST(DampedLeastSquares, SingularPoseIsDampedAsTheScheduleSays) {
  const DampingOptions options{0.0, 0.05, 0.02, 1e-10};  // epsilon 0.05, lambda_max 0.02
  DampedLeastSquares<double> dls(2, 2, options);
  const Eigen::Vector2d e(0.3, -0.2);
  double worst = 0, largest_norm = 0;
  VecX<double> previous;
  for (int k = 0; k <= 200; ++k) {
    const double q2 = 0.2 * (1.0 - k / 200.0);  // down to the stretched arm, q2 = 0 exactly
    const Eigen::Matrix2d J = two_link_jacobian(0.4, q2);
    ASSERT_TRUE(dls.compute(J));
    VecX<double> x(2);
    dls.solve(e, x);
    ASSERT_TRUE(x.allFinite());
    // Independent closed form: J J^T = U diag(s^2) U^T, x = J^T U diag(1 / (s^2 + lambda(s)^2)) U^T e.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(J * J.transpose());
    Eigen::Vector2d y = eig.eigenvectors().transpose() * e;
    for (int i = 0; i < 2; ++i) {
      const double s = std::sqrt(std::max(0.0, eig.eigenvalues()[i]));
      const double lambda2 = s < 0.05 ? 0.02 * 0.02 * (1 - (s / 0.05) * (s / 0.05)) : 0.0;
      y[i] /= eig.eigenvalues()[i] + lambda2;
    }
    const Eigen::Vector2d reference = J.transpose() * eig.eigenvectors() * y;
    worst = std::max(worst, (x - reference).norm() / reference.norm());
    // Gain along a singular direction: sigma / (sigma^2 + lambda_max^2 (1 - sigma^2 / eps^2)) peaks at
    // 1 / (2 lambda_max sqrt(1 - lambda_max^2 / eps^2)) = 27.3 inside the region, 1 / sigma <= 20 outside.
    EXPECT_LE(x.norm(), e.norm() / (2 * 0.02 * std::sqrt(1 - 0.16)) + 1e-12);
    if (previous.size()) largest_norm = std::max(largest_norm, (x - previous).norm());
    previous = x;
  }
  std::printf("  two-link arm to the stretched pose: max relative error vs closed form %.2e, largest step in x %.2e\n", worst,
              largest_norm);
  EXPECT_LT(worst, 1e-10);
  EXPECT_LT(largest_norm, 0.5);  // continuous: 201 poses over 0.2 rad, no jump of the size of x (~10)
  // At q2 = 0 the lost direction (along the arm) gets nothing; the other is the plain inverse.
  EXPECT_EQ(dls.rank(), 1);
}

TEST(DampedLeastSquares, NonFiniteMatrixIsRefused) {
  DampedLeastSquares<double> dls(2, 3);
  MatX<double> A = MatX<double>::Zero(2, 3);
  A(1, 2) = std::nan("");
  EXPECT_FALSE(dls.compute(A));
  EXPECT_FALSE(dls.valid());
}

TEST(DampedLeastSquares, NegativeOptionsAreRefusedWithAMessage) {
  try {
    DampedLeastSquares<double> dls(2, 3, DampingOptions{-1.0, 0.0, 0.0, 1e-10});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "DampedLeastSquares: damping options must be non-negative (constant, singular_region, max_damping, rank_tolerance)");
  }
}

TEST(DampedLeastSquares, DoesNotAllocate) {
  // Both paths: a regular matrix (the fast path) and one with a singular value in the region.
  MatX<double> regular = random_matrix(18, 40, 7), near_singular = regular;
  near_singular.row(17) = near_singular.row(16) + 1e-4 * near_singular.row(3);
  const VecX<double> e = random_matrix(18, 1, 8);
  for (const MatX<double>* A : {&regular, &near_singular}) {
    DampedLeastSquares<double> dls(18, 40, DampingOptions{0.01, 0.05, 0.02, 1e-10});
    VecX<double> x(40), v = random_matrix(40, 1, 9);
    {
      MallocGuard guard;
      dls.compute(*A);
      dls.solve(e, x);
      dls.project_to_null(v);
      EXPECT_EQ(guard.count(), 0u);
    }
    EXPECT_EQ(dls.exact_singular_values(), A == &near_singular);
    EXPECT_LT((*A * v).norm(), 1e-13);
  }
}

// The fast path (no singular value in the singular region: the eigen-decomposition skipped) gives
// the same solution as the full scheme, with and without constant damping: against the closed
// forms, and against the eigen path on the same matrix (forced by a wider singular region whose
// schedule still leaves these singular values undamped: max_damping 0).
TEST(DampedLeastSquares, FastPathEqualsTheFullScheme) {
  const MatX<double> A = random_matrix(18, 30, 11);
  const VecX<double> e = random_matrix(18, 1, 12);
  const Eigen::JacobiSVD<MatX<double>> svd(A);
  const double sigma_min = svd.singularValues()[17];
  for (double lambda : {0.0, 0.05}) {
    DampedLeastSquares<double> fast(18, 30, DampingOptions{lambda, 1e-2, 1e-2, 1e-10});
    DampedLeastSquares<double> full(18, 30, DampingOptions{lambda, 10.0, 0.0, 1e-10});
    ASSERT_TRUE(fast.compute(A));
    ASSERT_TRUE(full.compute(A));
    EXPECT_FALSE(fast.exact_singular_values());
    EXPECT_TRUE(full.exact_singular_values());
    EXPECT_GE(fast.smallest_singular_value(), 1e-2);
    EXPECT_LE(fast.smallest_singular_value(), sigma_min * (1 + 1e-12));
    EXPECT_NEAR(full.smallest_singular_value(), sigma_min, 1e-13);
    VecX<double> x_fast(30), x_full(30);
    fast.solve(e, x_fast);
    full.solve(e, x_full);
    const MatX<double> normal = A * A.transpose() + lambda * lambda * MatX<double>::Identity(18, 18);
    const VecX<double> reference = A.transpose() * normal.ldlt().solve(e);
    EXPECT_LT((x_fast - reference).norm(), 1e-12 * reference.norm()) << "lambda " << lambda;
    EXPECT_LT((x_fast - x_full).norm(), 1e-12 * reference.norm()) << "lambda " << lambda;
    std::printf("  18 x 30, lambda_0 %.2f: sigma_min %.3f, fast path's bound %.3f, |x_fast - x_full| / |x| %.1e\n", lambda,
                sigma_min, fast.smallest_singular_value(), (x_fast - x_full).norm() / reference.norm());
  }
}

}  // namespace
}  // namespace mbgen::test
