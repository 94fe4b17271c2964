#pragma once
// A dense convex QP solver for the differential IK's size (tens of variables, up to a few hundred
// inequalities): the dual active-set method of Goldfarb and Idnani (Math. Programming 27, 1983).
//
//   minimise 1/2 x^T G x + a^T x   subject to   E x = e,   C x >= c,
//
// G symmetric positive semi-definite (n x n), E (me x n), C (mi x n), each constraint a row.
// Debian packages no QP solver for C++ (only LP and NLP ones: GLPK, Clp, Ipopt), hence this one.
//
// Why the dual method: it starts from the unconstrained minimum -G^-1 a, which is where the IK's
// step is when no limit or distance is near, and adds only the constraints that minimum violates,
// one at a time, each with a full step in primal and dual space (or a partial one that drops a
// constraint whose multiplier would turn negative). Every iterate is the optimum of the problem
// restricted to its active set, with non-negative multipliers (dual feasible), so the method needs
// no feasible starting point and reports infeasibility when a violated constraint can be reached
// by no step (it is then proven: a certificate of the Farkas kind, not a guess).
//
// Factorisation. G = L L^T; J = L^-T Q and R (upper triangular) with Q^T L^-1 N = [R; 0] for the
// active constraints' normals N (n x q). Then J1 = J[:, :q] spans G^-1 N's range and J2 = J[:, q:]
// the null space of N^T in G's metric: the step for a new constraint n+ is z = J2 J2^T n+ (primal)
// and r = R^-1 J1^T n+ (dual). Adding a constraint rotates J's trailing columns with Givens
// rotations; dropping one restores R's triangle with Givens rotations on its rows. O(n^2) per
// change, no refactorisation.
//
// Semi-definite G (zero-curvature directions). The dual method needs G positive definite. When
// G's Cholesky factor fails or has a pivot below `regularization_threshold` times its largest,
// the solver runs proximal-point iterations (Rockafellar 1976): x_{k+1} = argmin f(x) +
// eps/2 |x - x_k|^2 over the constraints, each warm-started from the previous active set. For a
// convex QP they converge to a minimiser of the original problem, and for a polyhedral problem in
// finitely many steps when the iterates' active set settles (Ferris 1991); unboundedness shows as
// iterates that grow without bound, reported as `unbounded`.
//
// Warm start. solve(..., warm_start = true) first makes the previous solution's active
// inequalities active (as equalities), drops those whose multipliers come out negative, and
// continues from there: the same optimum (the method only needs dual feasibility to start), in
// fewer iterations when the active set changes little between calls, as in a control loop.
//
// Allocation: everything is sized at construction (n, the most equalities, the most inequalities);
// solve() accepts any number of rows up to those and neither allocates nor throws. Statuses, not
// exceptions, report what went wrong; the solution is then not to be used.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "mbgen/spatial/types.hpp"

namespace mbgen::control {

enum class QpStatus {
  solved,          ///< x is optimal: KKT conditions hold to the tolerances
  infeasible,      ///< no x satisfies the constraints (a violated constraint no step can reach)
  unbounded,       ///< G singular and the objective decreases without bound along a feasible ray
  max_iterations,  ///< the active-set iterations (or the proximal ones) did not finish: cycling
  invalid_input,   ///< sizes beyond the construction's, or a value that is not finite
  not_convex,      ///< G has a negative eigenvalue (its Cholesky factor fails with regularisation)
};

inline const char* to_string(QpStatus s) {
  switch (s) {
    case QpStatus::solved: return "solved";
    case QpStatus::infeasible: return "infeasible";
    case QpStatus::unbounded: return "unbounded";
    case QpStatus::max_iterations: return "max_iterations";
    case QpStatus::invalid_input: return "invalid_input";
    case QpStatus::not_convex: return "not_convex";
  }
  return "unknown";
}

struct DenseQpOptions {
  int max_iterations = 0;                ///< active-set changes per solve; 0: 5 (n + me + mi) + 20
  /// A constraint counts as violated when its residual is below -tolerance * (1 + |c_i| + |row| |x|).
  double feasibility_tolerance = 1e-12;
  /// G is treated as semi-definite (proximal iterations) when a Cholesky pivot is below this times
  /// the largest diagonal entry of G.
  double regularization_threshold = 1e-12;
  int max_proximal_iterations = 500;
};

template <typename S> class DenseQp {
 public:
  using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using ConstMat = Eigen::Ref<const Mat>;
  using ConstVec = Eigen::Ref<const Vec>;

  /// Sized for n variables, at most max_equalities rows of E and max_inequalities rows of C.
  DenseQp(int n, int max_equalities, int max_inequalities, const DenseQpOptions& options = {})
      : n_(n), me_max_(max_equalities), mi_max_(max_inequalities), options_(options) {
    if (n < 1 || max_equalities < 0 || max_inequalities < 0)
      throw std::invalid_argument("DenseQp: needs n >= 1 and non-negative constraint counts, got n = " + std::to_string(n) +
                                  ", " + std::to_string(max_equalities) + " equalities, " + std::to_string(max_inequalities) +
                                  " inequalities");
    if (!(options.feasibility_tolerance > 0) || !(options.regularization_threshold > 0) || options.max_iterations < 0 ||
        options.max_proximal_iterations < 1)
      throw std::invalid_argument("DenseQp: tolerances must be > 0 and iteration limits non-negative");
    G_ = Mat::Zero(n, n);
    llt_ = Eigen::LLT<Mat>(n);
    llt_.compute(Mat::Identity(n, n));  // its status set: a copy before the first solve reads no unset member
    J_ = Mat::Zero(n, n);
    R_ = Mat::Zero(n, n);
    x_ = Vec::Zero(n);
    x_previous_ = Vec::Zero(n);
    a_ = Vec::Zero(n);
    d_ = Vec::Zero(n);
    z_ = Vec::Zero(n);
    r_ = Vec::Zero(n);
    u_ = Vec::Zero(n + 1);
    active_.assign(static_cast<std::size_t>(n), -1);
    multipliers_ = Vec::Zero(me_max_ + mi_max_);
    warm_.assign(static_cast<std::size_t>(n), -1);
  }

  int variables() const { return n_; }

  /// Solves the QP (see the file comment); E, e may have 0 rows, as may C, c. With warm_start the
  /// last solve's active inequalities (their row indices into C) start active: C's rows must then
  /// mean what they meant (indices beyond C's rows are ignored).
  QpStatus solve(const ConstMat& G, const ConstVec& a, const ConstMat& E, const ConstVec& e, const ConstMat& C, const ConstVec& c,
                 bool warm_start = false) {
    iterations_ = 0;
    proximal_iterations_ = 0;
    num_warm_ = 0;
    if (warm_start)
      for (int k = 0; k < q_; ++k)
        if (active_[static_cast<std::size_t>(k)] >= me_) warm_[static_cast<std::size_t>(num_warm_++)] = active_[static_cast<std::size_t>(k)] - me_;
    me_ = static_cast<int>(E.rows());
    mi_ = static_cast<int>(C.rows());
    q_ = 0;
    status_ = check_input(G, a, E, e, C, c);
    if (status_ != QpStatus::solved) return status_;
    // Factor G; a pivot too small for it (semi-definite G) switches to proximal iterations.
    S scale = S(0);
    for (int i = 0; i < n_; ++i) scale = std::max(scale, std::abs(G(i, i)));
    const S floor = S(options_.regularization_threshold) * std::max(scale, S(1));
    llt_.compute(G);
    bool definite = llt_.info() == Eigen::Success;
    if (definite)
      for (int i = 0; i < n_; ++i) definite = definite && llt_.matrixLLT()(i, i) * llt_.matrixLLT()(i, i) > floor;
    if (definite) {
      status_ = solve_definite(a, E, e, C, c);
      return status_;
    }
    // Proximal point: G + eps I with the linear term a - eps x_k; eps = sqrt(machine epsilon) times
    // G's scale keeps G + eps I's condition number near 1 / sqrt(machine epsilon).
    const S eps = std::sqrt(std::numeric_limits<S>::epsilon()) * std::max(scale, S(1));
    const S size = S(1) + a.norm() + e.norm() + c.norm();
    G_ = G;
    G_.diagonal().array() += eps;
    llt_.compute(G_);
    if (llt_.info() != Eigen::Success) return status_ = QpStatus::not_convex;
    x_.setZero();
    for (proximal_iterations_ = 1; proximal_iterations_ <= options_.max_proximal_iterations; ++proximal_iterations_) {
      x_previous_ = x_;
      a_ = a - eps * x_previous_;
      if (proximal_iterations_ > 1) collect_warm_start();
      const QpStatus inner = solve_definite(a_, E, e, C, c);
      if (inner != QpStatus::solved) return status_ = inner;
      // An unbounded problem's iterates grow by about |a| / eps a step: a hundred such steps are
      // taken as proof (no bounded problem of this scale has its solution that far out).
      if (!(x_.norm() < S(100) * size / eps)) return status_ = QpStatus::unbounded;
      // Converged when the proximal term's share of the stationarity residual, eps (x - x_k), is
      // within the tolerance: x then satisfies the original problem's KKT conditions.
      if (eps * (x_ - x_previous_).norm() <= S(options_.feasibility_tolerance) * (size + scale * x_.norm())) {
        for (int j = 0; j < q_; ++j) multipliers_[active_[static_cast<std::size_t>(j)]] = u_[j];
        return status_ = QpStatus::solved;
      }
    }
    return status_ = QpStatus::max_iterations;
  }

  QpStatus status() const { return status_; }
  const Vec& solution() const { return x_; }
  /// Lagrange multipliers: the equalities' (me, any sign) then the inequalities' (mi, >= 0;
  /// zero for the inactive ones), with G x + a = E^T lambda_E + C^T lambda_C at the solution.
  Eigen::Ref<const Vec> multipliers() const { return multipliers_.head(me_ + mi_); }
  /// The active inequalities' row indices into C, in the order they were added.
  int num_active_inequalities() const {
    int k = 0;
    for (int j = 0; j < q_; ++j) k += active_[static_cast<std::size_t>(j)] >= me_ ? 1 : 0;
    return k;
  }
  int active_inequality(int i) const {
    int k = 0;
    for (int j = 0; j < q_; ++j)
      if (active_[static_cast<std::size_t>(j)] >= me_ && k++ == i) return active_[static_cast<std::size_t>(j)] - me_;
    return -1;
  }
  int iterations() const { return iterations_; }  ///< constraints added and dropped, over all proximal iterations
  int proximal_iterations() const { return proximal_iterations_; }  ///< 0: G was definite

 private:
  QpStatus check_input(const ConstMat& G, const ConstVec& a, const ConstMat& E, const ConstVec& e, const ConstMat& C, const ConstVec& c) const {
    if (G.rows() != n_ || G.cols() != n_ || a.size() != n_ || (E.cols() != n_ && E.rows() > 0) || (C.cols() != n_ && C.rows() > 0) ||
        e.size() != E.rows() || c.size() != C.rows() || E.rows() > me_max_ || C.rows() > mi_max_)
      return QpStatus::invalid_input;
    if (!G.allFinite() || !a.allFinite() || !E.allFinite() || !e.allFinite() || !C.allFinite() || !c.allFinite())
      return QpStatus::invalid_input;
    return QpStatus::solved;
  }

  /// The previous proximal iteration's active inequalities become the next one's warm start.
  void collect_warm_start() {
    num_warm_ = 0;
    for (int k = 0; k < q_; ++k)
      if (active_[static_cast<std::size_t>(k)] >= me_) warm_[static_cast<std::size_t>(num_warm_++)] = active_[static_cast<std::size_t>(k)] - me_;
    q_ = 0;
  }

  /// Goldfarb-Idnani on the factor in llt_, linear term a.
  QpStatus solve_definite(const ConstVec& a, const ConstMat& E, const ConstVec& e, const ConstMat& C, const ConstVec& c) {
    const int max_iterations = options_.max_iterations > 0 ? options_.max_iterations : 5 * (n_ + me_ + mi_) + 20;
    // J = L^-T, x = -G^-1 a.
    J_.setIdentity();
    llt_.matrixU().solveInPlace(J_);
    d_.noalias() = J_.transpose() * a;
    x_.noalias() = J_ * d_;
    x_ = -x_;
    q_ = 0;
    multipliers_.head(me_ + mi_).setZero();
    // Equalities: each added with the step that satisfies it (any sign: their multipliers are free).
    for (int k = 0; k < me_; ++k) {
      if (!add_as_equality(E.row(k), e[k], k)) return QpStatus::infeasible;
    }
    // Warm start: the previous active inequalities, as equalities, then those with negative
    // multipliers dropped (most negative first) until the start is dual feasible.
    if (num_warm_ > 0) {
      for (int w = 0; w < num_warm_; ++w) {
        const int i = warm_[static_cast<std::size_t>(w)];
        if (i < 0 || i >= mi_ || is_active(me_ + i)) continue;
        if (!add_as_equality(C.row(i), c[i], me_ + i)) {
          // Dependent and inconsistent with those already added: leave it to the main loop.
        }
      }
      for (;;) {
        subproblem_optimum(a, e, c);
        int worst = -1;
        S most = S(0);
        for (int j = 0; j < q_; ++j)
          if (active_[static_cast<std::size_t>(j)] >= me_ && u_[j] < most) most = u_[j], worst = j;
        if (worst < 0) break;
        drop(worst);
        if (++iterations_ > max_iterations) return QpStatus::max_iterations;
      }
    }
    const S eps = std::numeric_limits<S>::epsilon();
    for (;;) {
      // The most violated inequality, its residual scaled by its row's size.
      int p = -1;
      S worst = S(0);
      const S x_norm = x_.norm();
      for (int i = 0; i < mi_; ++i) {
        if (is_active(me_ + i)) continue;
        const S s = C.row(i).dot(x_) - c[i];
        const S size = S(1) + std::abs(c[i]) + C.row(i).norm() * x_norm;
        if (s < -S(options_.feasibility_tolerance) * size && s / size < worst) worst = s / size, p = i;
      }
      if (p < 0) break;
      // Bring constraint p in: dual steps drop blocking constraints until a full primal step adds it.
      S u_p = S(0);
      for (;;) {
        if (++iterations_ > max_iterations) return QpStatus::max_iterations;
        step_directions(C.row(p));
        S t1 = std::numeric_limits<S>::infinity();
        int blocking = -1;
        for (int j = 0; j < q_; ++j)
          if (active_[static_cast<std::size_t>(j)] >= me_ && r_[j] > S(0) && u_[j] / r_[j] < t1) t1 = u_[j] / r_[j], blocking = j;
        const S dependence = d_.tail(n_ - q_).squaredNorm();
        const S s_p = C.row(p).dot(x_) - c[p];
        const bool independent = dependence > S(1e6) * eps * eps * d_.squaredNorm();
        const S t2 = independent ? -s_p / dependence : std::numeric_limits<S>::infinity();
        const S t = std::min(t1, t2);
        if (!(t < std::numeric_limits<S>::infinity())) return QpStatus::infeasible;
        if (!independent) {  // dual step only: constraint p depends on the active ones
          u_.head(q_) -= t * r_.head(q_);
          u_p += t;
          drop(blocking);
          continue;
        }
        x_ += t * z_;
        u_.head(q_) -= t * r_.head(q_);
        u_p += t;
        if (t2 <= t1) {
          add(me_ + p);
          u_[q_ - 1] = u_p;
          break;
        }
        drop(blocking);
      }
    }
    for (int j = 0; j < q_; ++j) multipliers_[active_[static_cast<std::size_t>(j)]] = u_[j];
    return QpStatus::solved;
  }

  bool is_active(int id) const {
    for (int j = 0; j < q_; ++j)
      if (active_[static_cast<std::size_t>(j)] == id) return true;
    return false;
  }

  /// d = J^T n, z = J2 d2 (primal step), r = R^-1 d1 (dual step).
  template <typename Row> void step_directions(const Row& normal) {
    d_.noalias() = J_.transpose() * normal.transpose();
    z_.noalias() = J_.rightCols(n_ - q_) * d_.tail(n_ - q_);
    r_.head(q_) = d_.head(q_);
    R_.topLeftCorner(q_, q_).template triangularView<Eigen::Upper>().solveInPlace(r_.head(q_));
  }

  /// Adds the constraint `normal x = value` (id) with the step that satisfies it; false if it
  /// depends on the active ones and contradicts them (the problem is infeasible). A dependent,
  /// consistent one is skipped (its multiplier stays zero).
  template <typename Row> bool add_as_equality(const Row& normal, const S& value, int id) {
    if (q_ >= n_) {
      return std::abs(normal.dot(x_) - value) <= S(options_.feasibility_tolerance) * (S(1) + std::abs(value) + normal.norm() * x_.norm());
    }
    step_directions(normal);
    const S eps = std::numeric_limits<S>::epsilon();
    const S dependence = d_.tail(n_ - q_).squaredNorm();
    const S s = normal.dot(x_) - value;
    if (!(dependence > S(1e6) * eps * eps * d_.squaredNorm()))
      return std::abs(s) <= S(options_.feasibility_tolerance) * (S(1) + std::abs(value) + normal.norm() * x_.norm());
    const S t = -s / dependence;
    x_ += t * z_;
    u_.head(q_) -= t * r_.head(q_);
    add(id);
    u_[q_ - 1] = t;
    return true;
  }

  /// Appends the constraint whose d = J^T n is in d_: Givens rotations zero d's entries below q,
  /// rotating J's columns alike; R gains the column d[0..q].
  void add(int id) {
    for (int j = n_ - 1; j > q_; --j) {
      S cs, sn, h;
      if (!givens(d_[j - 1], d_[j], cs, sn, h)) continue;
      d_[j - 1] = h;
      d_[j] = S(0);
      rotate_columns(J_, j - 1, j, cs, sn);
    }
    R_.col(q_).head(q_ + 1) = d_.head(q_ + 1);
    active_[static_cast<std::size_t>(q_)] = id;
    ++q_;
  }

  /// Removes active constraint j: R loses column j, its upper Hessenberg rest is made triangular
  /// by Givens rotations on rows (J's columns rotated alike), the multipliers follow.
  void drop(int j) {
    for (int k = j; k + 1 < q_; ++k) {
      R_.col(k).head(k + 2) = R_.col(k + 1).head(k + 2);
      active_[static_cast<std::size_t>(k)] = active_[static_cast<std::size_t>(k + 1)];
      u_[k] = u_[k + 1];
    }
    --q_;
    for (int k = j; k < q_; ++k) {
      S cs, sn, h;
      if (!givens(R_(k, k), R_(k + 1, k), cs, sn, h)) continue;
      R_(k, k) = h;
      R_(k + 1, k) = S(0);
      for (int col = k + 1; col < q_; ++col) {
        const S top = R_(k, col), bottom = R_(k + 1, col);
        R_(k, col) = cs * top + sn * bottom;
        R_(k + 1, col) = -sn * top + cs * bottom;
      }
      rotate_columns(J_, k, k + 1, cs, sn);
    }
    R_.col(q_).setZero();
  }

  /// The optimum of the equality-constrained subproblem on the active set and its multipliers:
  /// x = -J2 J2^T a + J1 R^-T b and u = R^-1 J1^T (G x + a) (Goldfarb and Idnani's N* = R^-1 J1^T).
  void subproblem_optimum(const ConstVec& a, const ConstVec& e, const ConstVec& c) {
    // b_A, the active constraints' right-hand sides, in r_.
    for (int j = 0; j < q_; ++j) {
      const int id = active_[static_cast<std::size_t>(j)];
      r_[j] = id < me_ ? e[id] : c[id - me_];
    }
    // w = R^-T b (forward substitution), x = J1 w - J2 J2^T a.
    R_.topLeftCorner(q_, q_).template triangularView<Eigen::Upper>().transpose().solveInPlace(r_.head(q_));
    d_.noalias() = J_.transpose() * a;
    x_.noalias() = J_.leftCols(q_) * r_.head(q_);
    x_.noalias() -= J_.rightCols(n_ - q_) * d_.tail(n_ - q_);
    // J^T G J = I makes J1^T G x = w, so u = R^-1 (J1^T a + w).
    u_.head(q_) = d_.head(q_) + r_.head(q_);
    R_.topLeftCorner(q_, q_).template triangularView<Eigen::Upper>().solveInPlace(u_.head(q_));
  }

  static bool givens(const S& a, const S& b, S& c, S& s, S& h) {
    if (b == S(0)) return false;
    h = std::hypot(a, b);
    c = a / h;
    s = b / h;
    return true;
  }
  static void rotate_columns(Mat& M, int i, int j, const S& c, const S& s) {
    for (int r = 0; r < M.rows(); ++r) {
      const S left = M(r, i), right = M(r, j);
      M(r, i) = c * left + s * right;
      M(r, j) = -s * left + c * right;
    }
  }

  int n_, me_max_, mi_max_;
  DenseQpOptions options_;
  int me_ = 0, mi_ = 0, q_ = 0, iterations_ = 0, proximal_iterations_ = 0, num_warm_ = 0;
  QpStatus status_ = QpStatus::solved;
  Mat G_, J_, R_;
  Eigen::LLT<Mat> llt_;
  Vec x_, x_previous_, a_, d_, z_, r_, u_, multipliers_;
  std::vector<int> active_, warm_;
};

}  // namespace mbgen::control
