#pragma once
// Damped least squares with a null-space projector, from one singular value decomposition.
//
// For A (m x n, m <= n expected but not required) and a right-hand side e (m), computes
//   x = sum_i  sigma_i / (sigma_i^2 + lambda_i^2) v_i u_i^T e
// with the damping schedule (Nakamura; Chiaverini's singular region, per singular value)
//   lambda_i^2 = lambda_0^2 + (sigma_i < epsilon ? lambda_max^2 (1 - (sigma_i / epsilon)^2) : 0).
// With lambda_0 = 0 this is the exact pseudo-inverse away from singularities (sigma_min >= epsilon)
// and stays bounded at them; with max_damping = singular_region (the default of the
// differential IK) the gain sigma / (sigma^2 + lambda^2) rises linearly to 1 / epsilon inside the
// region and never exceeds it, so |x| <= |e| / epsilon whatever the pose. With
// epsilon = 0 it is the classical A^T (A A^T + lambda_0^2 I)^-1 e.
//
// Why an SVD: it gives the damping schedule (the singular values) and the rank at once, and its
// V is orthonormal to round-off, so the projector N = I - V_r V_r^T onto the null space of A is
// symmetric and idempotent to ~eps. The textbook I - A^+ A with a damped A^+ is not a projector
// (it leaks lambda^2 / sigma^2 of a secondary motion into the primary task), and
// I - A^T (A A^T)^-1 A squares the condition number. V_r holds the right singular vectors with
// sigma_i > rank_tolerance * sigma_max: directions the primary task sees, damped or not, are
// never handed to a secondary objective.
//
// Allocation: every buffer is sized by the constructor; compute(), solve() and project_to_null()
// do not allocate for an A of the constructed size (tests/test_damped_least_squares.cpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/SVD>

#include "mbgen/spatial/types.hpp"

namespace mbgen::control {

/// How much a damped least-squares solve damps (see the file comment for the schedule).
struct DampingOptions {
  double constant = 0.0;        ///< lambda_0: damping everywhere (0: exact pseudo-inverse when regular)
  double singular_region = 0.0; ///< epsilon: singular values below it are damped more the smaller they are
  double max_damping = 0.0;     ///< lambda_max: damping reached at sigma = 0 inside the singular region
  double rank_tolerance = 1e-10;///< relative to sigma_max: smaller singular values count as zero (null space)
};

template <typename S> class DampedLeastSquares {
 public:
  /// Sized for m x n matrices. Throws std::invalid_argument on negative options or sizes.
  DampedLeastSquares(int m, int n, const DampingOptions& options = {})
      : m_(m), n_(n), options_(options), svd_(m, n, Eigen::ComputeThinU | Eigen::ComputeThinV),
        tmp_(VecX<S>::Zero(std::min(m, n))), range_coeffs_(VecX<S>::Zero(std::min(m, n))) {
    if (m < 0 || n < 0) throw std::invalid_argument("DampedLeastSquares: negative size " + std::to_string(m) + " x " + std::to_string(n));
    if (!(options.constant >= 0) || !(options.singular_region >= 0) || !(options.max_damping >= 0) || !(options.rank_tolerance >= 0))
      throw std::invalid_argument("DampedLeastSquares: damping options must be non-negative (constant, singular_region, max_damping, rank_tolerance)");
  }

  int rows() const { return m_; }
  int cols() const { return n_; }
  const DampingOptions& options() const { return options_; }

  /// Decomposes A (rows() x cols()). Returns false (and keeps nothing usable) if A is not finite.
  /// Takes a plain matrix: JacobiSVD::compute takes a MatX, so any other expression (an
  /// Eigen::Ref, a block) would be copied into a heap temporary.
  bool compute(const MatX<S>& A) {
    if (!A.allFinite()) {
      rank_ = 0;
      valid_ = false;
      return false;
    }
    svd_.compute(A);
    const auto& sigma = svd_.singularValues();
    const S largest = sigma.size() > 0 ? sigma[0] : S(0);
    rank_ = 0;
    for (int i = 0; i < sigma.size(); ++i)
      if (sigma[i] > S(options_.rank_tolerance) * largest && sigma[i] > S(0)) rank_ = i + 1;
    valid_ = true;
    return true;
  }

  bool valid() const { return valid_; }
  /// Number of singular values above rank_tolerance * sigma_max.
  int rank() const { return rank_; }
  const VecX<S>& singular_values() const { return svd_.singularValues(); }
  S smallest_singular_value() const { return svd_.singularValues().size() ? svd_.singularValues().minCoeff() : S(0); }

  /// lambda_i^2 for singular value sigma.
  S damping_squared(const S& sigma) const {
    const S l0(options_.constant), eps(options_.singular_region), lmax(options_.max_damping);
    S l2 = l0 * l0;
    if (sigma < eps) {
      const S ratio = sigma / eps;
      l2 += lmax * lmax * (S(1) - ratio * ratio);
    }
    return l2;
  }

  /// x (cols()) = damped least-squares solution of A x = e (e: rows()). Needs compute().
  template <typename In, typename Out> void solve(const In& e, Out&& x) {
    const auto& sigma = svd_.singularValues();
    tmp_.noalias() = svd_.matrixU().transpose() * e;
    for (int i = 0; i < sigma.size(); ++i) {
      const S denom = sigma[i] * sigma[i] + damping_squared(sigma[i]);
      tmp_[i] = denom > S(0) ? tmp_[i] * sigma[i] / denom : S(0);
    }
    x.noalias() = svd_.matrixV() * tmp_;
  }

  /// v <- N v for a vector v (cols()), N = I - V_r V_r^T the orthogonal projector onto the null
  /// space of A. Needs compute().
  template <typename Vec> void project_to_null(Vec&& v) {
    auto coeffs = range_coeffs_.head(rank_);
    coeffs.noalias() = svd_.matrixV().leftCols(rank_).transpose() * v;
    v.noalias() -= svd_.matrixV().leftCols(rank_) * coeffs;
  }

 private:
  int m_, n_;
  DampingOptions options_;
  Eigen::JacobiSVD<MatX<S>> svd_;
  VecX<S> tmp_, range_coeffs_;
  int rank_ = 0;
  bool valid_ = false;
};

}  // namespace mbgen::control
