#pragma once
// Damped least squares with a null-space projector, from a column-pivoted QR of A^T and the
// eigen-decomposition of a small Gram matrix.
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
// The scheme (k = min(m, n)). A Jacobi SVD of A was most of a controller step; this costs a
// quarter of it (18 x 38: 26-35 us against 110-134 us, bench/bench_control.cpp, docs/control.md):
//  1. A^T P = Q R, Householder QR with column pivoting (Q: n x n orthogonal, kept as k reflectors;
//     R: k x m upper trapezoidal; P a permutation of the m task rows). So A = P R^T Q^T and A has
//     the singular values of R.
//  2. R R^T = W diag(sigma_i^2) W^T, symmetric eigen-decomposition of the k x k Gram matrix
//     (tridiagonalisation, implicit QR). With R = W S Z^T, A's right singular vectors are Q W
//     and its left ones P Z = P R^T W S^-1, so
//        x = Q W diag(1 / (sigma_i^2 + lambda_i^2)) W^T R P^T e :
//     no division by sigma (a zero sigma_i has W^T R = 0 in its row, whatever the factor), and x
//     lies in range(A^T) = range(Q) exactly as the SVD's did.
//  3. sigma_i = |R^T w_i| (not the square root of the eigenvalue): the eigenvalues of the formed
//     Gram matrix carry absolute errors ~ u sigma_max^2 (u the unit round-off), so their square
//     roots cannot resolve a singular value below ~sqrt(u) sigma_max = 1e-8 sigma_max. An error
//     delta_j of w_i towards w_j adds ~ sigma_j delta_j to |R^T w_i|, and delta_j ~
//     u sigma_max^2 / |sigma_j^2 - sigma_i^2|: typically a few u sigma_max (1e-14 absolute at
//     sigma_max = 3 down to sigma_i = 1e-12 in the tests), never worse than the square root.
//
// Accuracy of the solve. Each factor 1 / (sigma_i^2 + lambda_i^2) has relative error
// ~ u sigma_max^2 / (sigma_i^2 + lambda_i^2). Outside the singular region sigma_i >= epsilon, so
// the error is <= u (sigma_max / epsilon)^2: ~4e-12 for a Jacobian with sigma_max = 2 and the
// differential IK's epsilon = 0.01. Inside the region the damping dominates the denominator
// (lambda_i^2 >= lambda_0^2, and lambda_max^2 (1 - (sigma/epsilon)^2) + sigma^2 >=
// min(lambda_max^2, epsilon^2)), so the error stays <= u sigma_max^2 / min(lambda_max, epsilon)^2.
// The eigenvectors' errors (~ u sigma_max^2 / gap, large for close singular values) do not add
// to this: x depends on W only through W g(S^2) W^T = g(R R^T), g(t) = 1 / (t + lambda(t)^2),
// whose error is bounded by the Gram matrix's (~ u sigma_max^2) times g's Lipschitz constant,
// the bound above times max(1, lambda_max^2 / epsilon^2). Q and R P^T e are backward stable.
// Where it matters: an undamped solve (lambda_0 = epsilon = 0) of an ill-conditioned A loses
// u kappa^2 instead of the SVD's u kappa (the Gram matrix squares the condition number); the
// default options of the differential IK never run undamped.
//
// Fast path. When A has full row rank (m <= n) and no singular value can lie in the singular
// region, every lambda_i is lambda_0 and the eigen-decomposition is not needed: with R square
// (m x m) and sigma_min(R) >= 1 / |R^-1|_F (the Frobenius norm bounds the spectral one), a bound
// >= epsilon proves it. Then x = Q R^-T P^T e (lambda_0 = 0: the exact pseudo-inverse, by one
// triangular solve, backward stable) or x = Q (R R^T + lambda_0^2 I)^-1 R P^T e (Cholesky, the
// Gram matrix's accuracy as above). R^-1 costs m^3 / 3, against the eigen-solver's ~10 m^3: the
// differential IK's regular steps take this path (18 x 30: docs/control.md has the figures).
// smallest_singular_value() is then the bound 1 / |R^-1|_F (<= sigma_min), and singular_values()
// is not computed (exact_singular_values() says which).
// The fast path is tried first on a QR without pivoting (P = I; householder_qr, written out:
// Eigen's pivoted QR spent four instructions per flop at this size on dynamic block expressions):
// |R^-1|_F^2 = trace((A A^T)^-1) whatever the pivoting, so the bound is the pivoted one's, and a
// bound above rank_tolerance times A's largest row norm proves the rank m the pivoted QR would
// find (each of its pivots is at least sigma_min). A matrix that fails the bound is factored
// again with pivoting (near-singular poses pay for both QRs). On Lola's controller step the two
// written-out factorisations and the projections below took the step from 25 to 22 us.
//
// The null-space projector comes from the QR alone: N = I - Q_r Q_r^T, with Q_r the first r
// columns of Q, applied as v <- H_0 .. H_{r-1} diag(0_r, I) H_{r-1} .. H_0 v with the Householder
// reflectors (no explicit Q). Q is orthogonal to round-off, so N is symmetric and idempotent to
// ~u, as the SVD's I - V_r V_r^T was (I - A^+ A with a damped A^+ is not a projector: it leaks
// lambda^2 / sigma^2 of a secondary motion into the primary task; I - A^T (A A^T)^-1 A squares
// the condition number). The rank r counts the pivots |R_jj| > rank_tolerance * |R_00|: pivoted
// QR's R_jj carry absolute errors ~ u |A| (not the sqrt(u) |A| of the Gram eigenvalues), and
// |R_00| (the largest row norm of A) lies within sqrt(m) of sigma_max. Directions the primary task
// sees, damped or not, are never handed to a secondary objective. to_null_space and
// from_null_space split N = P^T D0 P (P = H_{r-1} .. H_0, D0 = diag(0_r, I)) for several columns
// at once, so that products of projected vectors are taken between the halves.
//
// Allocation: every buffer is sized by the constructor; compute(), solve() and project_to_null()
// do not allocate for an A of the constructed size (tests/test_damped_least_squares.cpp).
// SelfAdjointEigenSolver::compute, and Eigen's application of a HouseholderSequence to a dynamic
// matrix, allocate temporaries; hence Tridiagonalization + computeFromTridiagonal, and both the
// QR's and the tridiagonalisation's reflectors applied by a hand-written loop over their stored
// essential parts.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "mbgen/spatial/types.hpp"

namespace mbgen::control {

/// How much a damped least-squares solve damps (see the file comment for the schedule).
struct DampingOptions {
  double constant = 0.0;        ///< lambda_0: damping everywhere (0: exact pseudo-inverse when regular)
  double singular_region = 0.0; ///< epsilon: singular values below it are damped more the smaller they are
  double max_damping = 0.0;     ///< lambda_max: damping reached at sigma = 0 inside the singular region
  double rank_tolerance = 1e-10;///< relative to the largest QR pivot (~sigma_max): smaller pivots count as zero (null space)
};

template <typename S> class DampedLeastSquares {
 public:
  /// Sized for m x n matrices. Throws std::invalid_argument on negative options or sizes.
  DampedLeastSquares(int m, int n, const DampingOptions& options = {})
      : m_(m), n_(n), k_(std::max(0, std::min(m, n))), options_(options), qr_(std::max(n, 0), std::max(m, 0)),
        plain_(MatX<S>::Zero(m <= n ? std::max(n, 0) : 0, m <= n ? std::max(m, 0) : 0)), plain_tau_(VecX<S>::Zero(std::max(0, std::min(m, n)))),
        rows_(VecX<S>::Zero(m <= n ? std::max(n, 0) * (std::max(m, 0) + kChunk - 1) : 0)),
        r_(MatX<S>::Zero(k_, std::max(m, 0))), gram_(MatX<S>::Zero(k_, k_)), tri_(std::max(k_, 1)), eig_(std::max(k_, 1)),
        w_(MatX<S>::Zero(k_, k_)), rtw_(MatX<S>::Zero(std::max(m, 0), k_)), sigma_(VecX<S>::Zero(k_)),
        sorted_sigma_(VecX<S>::Zero(k_)), permuted_e_(VecX<S>::Zero(std::max(m, 0))), coeffs_(VecX<S>::Zero(k_)),
        coeffs2_(VecX<S>::Zero(k_)), diag_(VecX<S>::Zero(k_)), subdiag_(VecX<S>::Zero(std::max(k_ - 1, 0))),
        r_inverse_(MatX<S>::Zero(m <= n ? std::max(m, 0) : 0, m <= n ? std::max(m, 0) : 0)),
        inverse_diagonal_(VecX<S>::Zero(std::max(0, std::min(m, n)))), llt_(m <= n ? std::max(m, 0) : 0),
        null_rows_(VecX<S>::Zero(static_cast<Eigen::Index>(std::max(n, 0)) * padded(n))), null_work_(VecX<S>::Zero(padded(n))) {
    if (m < 0 || n < 0) throw std::invalid_argument("DampedLeastSquares: negative size " + std::to_string(m) + " x " + std::to_string(n));
    if (!(options.constant >= 0) || !(options.singular_region >= 0) || !(options.max_damping >= 0) || !(options.rank_tolerance >= 0))
      throw std::invalid_argument("DampedLeastSquares: damping options must be non-negative (constant, singular_region, max_damping, rank_tolerance)");
    // Eigen's sized constructors of LLT and SelfAdjointEigenSolver leave their status enum unset
    // (ColPivHouseholderQR its pivot count and threshold), and copying or moving this object
    // before its first compute() would read them: each is computed once, of the identity, so
    // that every member holds a value (issue 61). PartialPivLU's sized constructor sets all.
    qr_.compute(MatX<S>::Identity(qr_.rows(), qr_.cols()));
    eig_.compute(MatX<S>::Identity(std::max(k_, 1), std::max(k_, 1)), Eigen::EigenvaluesOnly);
    llt_.compute(MatX<S>::Identity(llt_.rows(), llt_.rows()));
  }

  int rows() const { return m_; }
  int cols() const { return n_; }
  const DampingOptions& options() const { return options_; }

  /// Decomposes A (rows() x cols()). Returns false (and keeps nothing usable) if A is not finite.
  bool compute(const MatX<S>& A) {
    valid_ = false;
    fast_ = false;
    exact_sigma_ = false;
    rank_ = 0;
    if (!A.allFinite()) return false;
    if (k_ == 0) {
      valid_ = true;
      return true;
    }
    if (m_ <= n_ && unpivoted_fast_path(A)) {
      valid_ = true;
      return true;
    }
    pivoted_ = true;
    qr_.compute(A.transpose());
    copy_r();
    const auto& packed = qr_.matrixQR();
    const S largest_pivot = std::abs(packed(0, 0));
    for (int j = 0; j < k_; ++j) {
      // Pivoting makes |R_jj| non-increasing: the rank is the leading run above the tolerance.
      const S pivot = std::abs(packed(j, j));
      if (!(pivot > S(options_.rank_tolerance) * largest_pivot && pivot > S(0))) break;
      rank_ = j + 1;
    }

    // m <= n: the unpivoted try above already decided the fast path (its bound is this R's).
    exact_sigma_ = true;
    gram_.noalias() = r_ * r_.transpose();
    tri_.compute(gram_);
    // Through plain vectors: computeFromTridiagonal takes the sub-diagonal as a VectorX, and
    // the expression would be copied into a heap temporary.
    diag_ = tri_.diagonal();
    subdiag_ = tri_.subDiagonal();
    eig_.computeFromTridiagonal(diag_, subdiag_, Eigen::ComputeEigenvectors);
    if (eig_.info() != Eigen::Success) return false;
    // W = Q_t Z with Z the tridiagonal matrix's eigenvectors (increasing eigenvalues): columns
    // reversed so that w_0 belongs to the largest singular value.
    const auto& z = eig_.eigenvectors();
    for (int i = 0; i < k_; ++i) w_.col(i) = z.col(k_ - 1 - i);
    const auto& tri_packed = tri_.packedMatrix();
    const auto& tri_coeffs = tri_.coefficients();
    for (int j = k_ - 2; j >= 0; --j)  // W <- H_0 .. H_{k-2} W, reflector j acting on rows j+1 ..
      for (int c = 0; c < k_; ++c) reflect(tri_packed.col(j).tail(k_ - j - 2), tri_coeffs[j], j + 1, w_.col(c));

    rtw_.noalias() = r_.transpose() * w_;
    for (int i = 0; i < k_; ++i) sigma_[i] = rtw_.col(i).norm();
    sorted_sigma_ = sigma_;
    // Already decreasing up to round-off between (nearly) equal singular values.
    std::sort(sorted_sigma_.data(), sorted_sigma_.data() + k_, std::greater<S>());
    valid_ = true;
    return true;
  }

  bool valid() const { return valid_; }
  /// Number of QR pivots |R_jj| above rank_tolerance * |R_00| (the dimension of the range of A^T
  /// the projector removes).
  int rank() const { return rank_; }
  /// The min(m, n) singular values of A, decreasing (when exact_singular_values()).
  const VecX<S>& singular_values() const { return sorted_sigma_; }
  /// Whether the last compute() found the singular values (false on the fast path).
  bool exact_singular_values() const { return exact_sigma_; }
  /// sigma_min of A; on the fast path the lower bound 1 / |R^-1|_F (>= singular_region).
  S smallest_singular_value() const { return fast_ ? sigma_bound_ : (k_ ? sorted_sigma_[k_ - 1] : S(0)); }

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
    if (k_ == 0) {
      x.setZero();
      return;
    }
    if (pivoted_) {
      const auto& perm = qr_.colsPermutation().indices();
      for (int j = 0; j < m_; ++j) permuted_e_[j] = e[perm[j]];  // P^T e
    } else {
      permuted_e_ = e;
    }
    if (fast_) {
      if (options_.constant == 0) {  // x = Q R^-T P^T e
        x.head(k_) = permuted_e_;
        r_.topLeftCorner(k_, k_).template triangularView<Eigen::Upper>().transpose().solveInPlace(x.head(k_));
      } else {  // x = Q (R R^T + lambda_0^2 I)^-1 R P^T e
        coeffs_.noalias() = r_ * permuted_e_;
        x.head(k_) = llt_.solve(coeffs_);
      }
      x.tail(n_ - k_).setZero();
      for (int j = k_ - 1; j >= 0; --j) reflect_qr(j, x);
      return;
    }
    coeffs_.noalias() = r_ * permuted_e_;                       // R P^T e
    coeffs2_.noalias() = w_.transpose() * coeffs_;
    for (int i = 0; i < k_; ++i) {
      const S denom = sigma_[i] * sigma_[i] + damping_squared(sigma_[i]);
      coeffs2_[i] = denom > S(0) ? coeffs2_[i] / denom : S(0);
    }
    x.head(k_).noalias() = w_ * coeffs2_;
    x.tail(n_ - k_).setZero();
    // x <- Q x = H_0 .. H_{k-1} x.
    for (int j = k_ - 1; j >= 0; --j) reflect_qr(j, x);
  }

  /// v <- N v for a vector v (cols()), N = I - Q_r Q_r^T the orthogonal projector onto the null
  /// space of A. Needs compute().
  template <typename Vec> void project_to_null(Vec&& v) {
    for (int j = 0; j < rank_; ++j) reflect_qr(j, v);  // Q_r^T v in the first r entries
    v.head(rank_).setZero();
    for (int j = rank_ - 1; j >= 0; --j) reflect_qr(j, v);
  }

  /// The projector in two halves, N = P^T D0 P with P = H_{r-1} .. H_0 (the first r reflectors)
  /// and D0 = diag(0_r, I): to_null_space(Y) sets Y <- D0 P Y, from_null_space(Y) sets Y <- P^T Y,
  /// for the K columns of Y (cols() x K, row-major), one pass over each reflector for all of them
  /// (its entries loaded once, the K dot products in one vector of K lanes). Between the two, Y
  /// holds coordinates in which N is D0, so products such as (N a)^T (N b) = (D0 P a)^T (D0 P b)
  /// need no second pass (the differential IK's momentum objective).
  template <int K> void to_null_space(Eigen::Matrix<S, Eigen::Dynamic, K, Eigen::RowMajor>& Y) const {
    S* y = Y.data();
    for (int j = 0; j < rank_; ++j) reflect_rows<K>(j, y);
    for (int i = 0; i < rank_ * K; ++i) y[i] = S(0);
  }
  template <int K> void from_null_space(Eigen::Matrix<S, Eigen::Dynamic, K, Eigen::RowMajor>& Y) const {
    S* y = Y.data();
    for (int j = rank_ - 1; j >= 0; --j) reflect_rows<K>(j, y);
  }
  /// An orthonormal basis of the null space of A in the first cols() - rank() columns of Z (at
  /// least cols() x (cols() - rank()); the rest untouched): Z = P^T [0; I], so N = Z Z^T. The QP
  /// form of the differential IK solves in these coordinates. Returns the number of columns.
  /// All k columns go through each reflector together, in a row-major scratch: the k dot products
  /// with a reflector are k independent sums in one loop. Column by column, each was one chain of
  /// dependent additions (no reassociation without -ffast-math): Lola's QP step took 45.5 us that
  /// way, 43.7 this way. (reflect_rows<K> is the same pass with K a constant, for its unrolling.)
  int null_space_basis(MatX<S>& Z) const {
    const int k = n_ - rank_;
    if (k <= 0) return 0;
    // The rows are padded to a multiple of 4 columns (zero columns stay zero under the
    // reflectors): the inner loops then have a trip count the compiler unrolls and vectorises
    // in whole registers, where k itself (12 for Lola) left a scalar remainder in every row
    // (Lola's basis: 56,207 instructions a call before, 46,326 padded; callgrind).
    const int kp = padded(k);
    S* y = null_rows_.data();  // n_ x kp, row-major
    S* w = null_work_.data();
    for (int i = 0; i < n_ * kp; ++i) y[i] = S(0);
    for (int c = 0; c < k; ++c) y[(rank_ + c) * kp + c] = S(1);
    for (int j = rank_ - 1; j >= 0; --j) {  // rows above j are still zero: H_j acts on rows j .. n-1
      const S* essential = packed().col(j).data() + j + 1;
      const S tau = householder_coefficients()[j];
      S* top = y + j * kp;
      const int len = n_ - j - 1;
      for (int c0 = 0; c0 < kp; c0 += 4) {
        S acc[4] = {top[c0], top[c0 + 1], top[c0 + 2], top[c0 + 3]};
        for (int i = 0; i < len; ++i) {
          const S e = essential[i];
          const S* row = top + (i + 1) * kp + c0;
          for (int c = 0; c < 4; ++c) acc[c] += e * row[c];
        }
        for (int c = 0; c < 4; ++c) {
          w[c0 + c] = tau * acc[c];
          top[c0 + c] -= w[c0 + c];
        }
      }
      for (int i = 0; i < len; ++i) {
        const S e = essential[i];
        S* row = top + (i + 1) * kp;
        for (int c0 = 0; c0 < kp; c0 += 4)
          for (int c = 0; c < 4; ++c) row[c0 + c] -= e * w[c0 + c];
      }
    }
    for (int c = 0; c < k; ++c)
      for (int i = 0; i < n_; ++i) Z(i, c) = y[i * kp + c];
    return k;
  }

 private:
  /// The fast path's test and factor on R (r_; see the file comment): true when it applies, that
  /// is when the bound on sigma_min is at least the singular region and above rank_floor.
  bool fast_path(const S& rank_floor) {
    // R^-1 by back substitution, column by column, each step an update of the entries above by a
    // column of R (Eigen's triangular solve with a matrix right-hand side packs and blocks: six
    // times the instructions at this size).
    for (int i = 0; i < k_; ++i) inverse_diagonal_[i] = S(1) / r_(i, i);
    S frobenius2 = S(0);
    for (int j = 0; j < k_; ++j) {
      S* __restrict x = r_inverse_.col(j).data();
      for (int i = 0; i <= j; ++i) x[i] = S(0);
      x[j] = S(1);
      for (int i = j; i >= 0; --i) {
        x[i] *= inverse_diagonal_[i];
        const S xi = x[i];
        const S* __restrict above = r_.col(i).data();
        for (int t = 0; t < i; ++t) x[t] -= xi * above[t];
      }
      for (int i = 0; i <= j; ++i) frobenius2 += x[i] * x[i];
    }
    const S bound = S(1) / std::sqrt(frobenius2);
    if (!(bound >= S(options_.singular_region)) || !(bound > rank_floor)) return false;
    if (options_.constant != 0) {
      gram_.noalias() = r_ * r_.transpose();
      gram_.diagonal().array() += S(options_.constant) * S(options_.constant);
      llt_.compute(gram_);
      if (llt_.info() != Eigen::Success) return false;
    }
    rank_ = m_;
    sigma_bound_ = bound;
    fast_ = true;
    return true;
  }

  /// The fast path without pivoting (m <= n): A^T = Q R by Householder QR alone (see
  /// householder_qr). Its R has the singular values of A as the pivoted one has
  /// (|R^-1|_F^2 = trace((A A^T)^-1) either way), and a bound on sigma_min above rank_tolerance
  /// times the largest row norm of A (the pivoted QR's |R_00|) proves the rank the pivoted QR would
  /// find: each of its pivots is at least sigma_min (a triangular matrix's diagonal entries are its
  /// eigenvalues). When the bound fails, compute() factors again with pivoting, as before.
  bool unpivoted_fast_path(const MatX<S>& A) {
    pivoted_ = false;
    householder_qr(A);
    copy_r();
    S largest_row = S(0);
    for (int i = 0; i < m_; ++i) largest_row = std::max(largest_row, A.row(i).norm());
    return fast_path(S(options_.rank_tolerance) * largest_row);
  }

  /// plain_ = A^T factored by Householder reflections without pivoting (R on and above the
  /// diagonal, each reflector's essential part below it, its coefficient in plain_tau_), in
  /// LAPACK's convention (dlarfg: beta = -sign(alpha) |x|, v = [1; x_tail / (alpha - beta)],
  /// tau = (beta - alpha) / beta), the layout Eigen's QRs use. Written out: Eigen's column-pivoted
  /// QR spent about four instructions per flop at 30 x 18 on its dynamic block expressions (column
  /// norm updates, a matrix-vector product and a rank-one update per column). A column whose part
  /// below the diagonal is zero gets no reflection (tau 0).
  ///
  /// Why row by row: the factorisation works on A^T stored row-major, so that applying reflector
  /// j to the trailing columns, w = tau (y_j + h^T Y) and Y -= h w^T, runs along rows: for each
  /// entry h_i of the reflector, kChunk trailing columns' w_c += h_i Y(i, c) at once, held in
  /// registers across i (independent lanes g++ vectorises without reassociating anything).
  /// Written as a dot product per column (the previous form), each w_c was one serial chain of
  /// dependent additions, which g++ may not vectorise under IEEE rules: latency-bound (the QR
  /// alone, 18 x 30: 2.7 -> 2.1 us, best of 6 interleaved runs). Each w_c still sums h_i Y(i, c)
  /// in the order of i, as the dot products did. Rows are padded with kChunk - 1 zero columns: a
  /// chunk may run past the last column, where it reads and writes zeros. plain_ gets the
  /// column-major copy the reflections read.
  void householder_qr(const MatX<S>& A) {
    const int ld = row_stride();
    S* const work = rows_.data();
    for (int i = 0; i < n_; ++i)
      for (int c = 0; c < m_; ++c) work[i * ld + c] = A(c, i);
    for (int j = 0; j < k_; ++j) {
      const int len = n_ - j - 1;
      S* const top = work + j * ld;  // row j: the pivot row of A^T
      S tail = S(0);
      for (int i = 1; i <= len; ++i) tail += top[i * ld + j] * top[i * ld + j];
      if (tail == S(0)) {
        plain_tau_[j] = S(0);
        continue;
      }
      const S alpha = top[j];
      const S norm = std::sqrt(alpha * alpha + tail);
      const S beta = alpha >= S(0) ? -norm : norm;
      const S tau = (beta - alpha) / beta;
      const S scale = S(1) / (alpha - beta);
      for (int i = 1; i <= len; ++i) top[i * ld + j] *= scale;
      top[j] = beta;
      plain_tau_[j] = tau;
      for (int first = j + 1; first < m_; first += kChunk) {
        using Chunk = Eigen::Array<S, kChunk, 1>;
        Chunk w = Eigen::Map<const Chunk>(top + first);
        for (int i = 1; i <= len; ++i) w += top[i * ld + j] * Eigen::Map<const Chunk>(top + i * ld + first);
        w *= tau;
        Eigen::Map<Chunk>(top + first) -= w;
        for (int i = 1; i <= len; ++i) Eigen::Map<Chunk>(top + i * ld + first) -= w * top[i * ld + j];
      }
    }
    for (int c = 0; c < m_; ++c)
      for (int i = 0; i < n_; ++i) plain_(i, c) = work[i * ld + c];
  }
  /// householder_qr's columns per pass (the registers' worth of w: 4 SSE2 or 2 AVX vectors).
  static constexpr int kChunk = 8;
  int row_stride() const { return m_ + kChunk - 1; }

  /// The QR in use: plain (fast path without pivoting) or column-pivoted.
  const MatX<S>& packed() const { return pivoted_ ? qr_.matrixQR() : plain_; }
  const VecX<S>& householder_coefficients() const { return pivoted_ ? qr_.hCoeffs() : plain_tau_; }

  /// r_ = R with explicit zeros below the diagonal: dense products need no triangular views.
  void copy_r() {
    const MatX<S>& qr = packed();
    r_.setZero();
    for (int j = 0; j < m_; ++j) {
      const int top = std::min(j + 1, k_);
      r_.col(j).head(top) = qr.col(j).head(top);
    }
  }

  /// y <- (I - tau h h^T) y with h = [0 (offset), 1, essential].
  template <typename Ess, typename Vec> static void reflect(const Ess& essential, const S& tau, int offset, Vec&& y) {
    const int len = static_cast<int>(essential.size());
    const S w = tau * (y[offset] + essential.dot(y.segment(offset + 1, len)));
    y[offset] -= w;
    y.segment(offset + 1, len) -= w * essential;
  }
  /// Rows j .. n-1 of y (n x K, row-major) <- H_j y, H_j the j-th reflector of the QR of A^T.
  template <int K> void reflect_rows(int j, S* y) const {
    const S* essential = packed().col(j).data() + j + 1;
    const S tau = householder_coefficients()[j];
    S* top = y + j * K;
    S* below = top + K;
    const int len = n_ - j - 1;
    S w[K];
    for (int c = 0; c < K; ++c) w[c] = top[c];
    for (int i = 0; i < len; ++i)
      for (int c = 0; c < K; ++c) w[c] += essential[i] * below[i * K + c];
    for (int c = 0; c < K; ++c) {
      w[c] *= tau;
      top[c] -= w[c];
    }
    for (int i = 0; i < len; ++i)
      for (int c = 0; c < K; ++c) below[i * K + c] -= essential[i] * w[c];
  }
  /// The j-th reflector of the QR of A^T (n x n, acting on rows j .. n-1).
  template <typename Vec> void reflect_qr(int j, Vec& y) const {
    reflect(packed().col(j).tail(n_ - j - 1), householder_coefficients()[j], j, y);
  }

  int m_, n_, k_;
  DampingOptions options_;
  Eigen::ColPivHouseholderQR<MatX<S>> qr_;
  MatX<S> plain_;     ///< the fast path's unpivoted QR of A^T (m <= n; householder_qr)
  VecX<S> plain_tau_;
  VecX<S> rows_;  ///< householder_qr's working copy of A^T, row-major, row_stride() apart
  MatX<S> r_, gram_;
  /// Eigen's tridiagonalisation with its Householder coefficients by reference
  /// (householderCoefficients() returns a copy, a heap allocation).
  struct Tridiagonalization : Eigen::Tridiagonalization<MatX<S>> {
    using Eigen::Tridiagonalization<MatX<S>>::Tridiagonalization;
    const typename Eigen::Tridiagonalization<MatX<S>>::CoeffVectorType& coefficients() const { return this->m_hCoeffs; }
  };
  Tridiagonalization tri_;
  Eigen::SelfAdjointEigenSolver<MatX<S>> eig_;
  MatX<S> w_, rtw_;
  VecX<S> sigma_, sorted_sigma_, permuted_e_, coeffs_, coeffs2_, diag_, subdiag_;
  MatX<S> r_inverse_;  ///< fast path: R^-1 (m x m), for the bound on sigma_min
  VecX<S> inverse_diagonal_;
  Eigen::LLT<MatX<S>> llt_;
  /// null_space_basis' scratch (n x padded(n) row-major, and padded(n)): mutable, as the method is a const query.
  static int padded(int n) { return (std::max(n, 0) + 3) / 4 * 4; }
  mutable VecX<S> null_rows_, null_work_;
  S sigma_bound_ = S(0);
  int rank_ = 0;
  bool valid_ = false, fast_ = false, exact_sigma_ = false, pivoted_ = false;
};

}  // namespace mbgen::control
