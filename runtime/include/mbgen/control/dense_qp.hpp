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
// Factorisation. G = L L^T (written out: it works on a corner of storage sized at construction); J = L^-T Q and R (upper triangular) with Q^T L^-1 N = [R; 0] for the
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
// A caller whose rows are renumbered between calls (constraints come and go) hands over the rows
// to start from instead: solve(..., start_rows, count).
//
// Allocation: everything is sized at construction (the most variables, equalities, inequalities);
// solve() accepts any problem within those and neither allocates nor throws. Statuses, not
// exceptions, report what went wrong; the solution is then not to be used.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

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

  /// Sized for at most max_variables variables, max_equalities rows of E and max_inequalities
  /// rows of C: solve() takes any problem within those (the IK's null space changes its size).
  DenseQp(int max_variables, int max_equalities, int max_inequalities, const DenseQpOptions& options = {})
      : n_max_(max_variables), me_max_(max_equalities), mi_max_(max_inequalities), options_(options) {
    if (max_variables < 1 || max_equalities < 0 || max_inequalities < 0)
      throw std::invalid_argument("DenseQp: needs at least one variable and non-negative constraint counts, got " +
                                  std::to_string(max_variables) + " variables, " + std::to_string(max_equalities) + " equalities, " +
                                  std::to_string(max_inequalities) + " inequalities");
    if (!(options.feasibility_tolerance > 0) || !(options.regularization_threshold > 0) || options.max_iterations < 0 ||
        options.max_proximal_iterations < 1)
      throw std::invalid_argument("DenseQp: tolerances must be > 0 and iteration limits non-negative");
    const int n = n_max_;
    L_ = Mat::Zero(n, n);
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
    slack_ = Vec::Zero(std::max(mi_max_, 1));
    row_norm_ = Vec::Zero(std::max(mi_max_, 1));
    flags_.assign(static_cast<std::size_t>(me_max_ + mi_max_ + 1), 0);
    warm_.assign(static_cast<std::size_t>(n), -1);
  }

  int max_variables() const { return n_max_; }

  /// Solves the QP (see the file comment): G is n x n for any n up to max_variables(); E, e may
  /// have 0 rows, as may C, c. With warm_start the last solve's active inequalities (their row
  /// indices into C) start active: C's rows must then mean what they meant (indices beyond C's
  /// rows are ignored).
  QpStatus solve(const ConstMat& G, const ConstVec& a, const ConstMat& E, const ConstVec& e, const ConstMat& C, const ConstVec& c,
                 bool warm_start = false) {
    num_warm_ = 0;
    if (warm_start && G.rows() == n_)
      for (int k = 0; k < q_; ++k)
        if (active_[static_cast<std::size_t>(k)] >= me_) warm_[static_cast<std::size_t>(num_warm_++)] = active_[static_cast<std::size_t>(k)] - me_;
    return solve_from_warm_start(G, a, E, e, C, c);
  }
  /// solve() started from the given inequalities (row indices into C) as its active set: the warm
  /// start for a caller whose rows are renumbered between solves (the IK's come and go as limits
  /// and pairs approach), which maps the last solve's active rows to their new indices. Any set
  /// gives the same optimum (the method needs only a dual-feasible start, and the warm start drops
  /// rows until it has one); a set close to the optimum's saves the iterations that would add it.
  /// Indices out of range and repeated ones are ignored; at most max_variables() are taken.
  QpStatus solve(const ConstMat& G, const ConstVec& a, const ConstMat& E, const ConstVec& e, const ConstMat& C, const ConstVec& c,
                 const int* start_rows, int count) {
    num_warm_ = 0;
    for (int k = 0; k < count && num_warm_ < n_max_; ++k) warm_[static_cast<std::size_t>(num_warm_++)] = start_rows[k];
    return solve_from_warm_start(G, a, E, e, C, c);
  }

  QpStatus status() const { return status_; }
  Eigen::Ref<const Vec> solution() const { return x_.head(n_); }
  /// Lagrange multipliers: the equalities' (me, any sign) then the inequalities' (mi, >= 0;
  /// zero for the inactive ones), with G x + a = E^T lambda_E + C^T lambda_C at the solution.
  Eigen::Ref<const Vec> multipliers() const { return multipliers_.head(me_ + mi_); }
  int num_active_inequalities() const {
    int k = 0;
    for (int j = 0; j < q_; ++j) k += active_[static_cast<std::size_t>(j)] >= me_ ? 1 : 0;
    return k;
  }
  /// The i-th active inequality's row index into C, in the order they were added.
  int active_inequality(int i) const {
    int k = 0;
    for (int j = 0; j < q_; ++j)
      if (active_[static_cast<std::size_t>(j)] >= me_ && k++ == i) return active_[static_cast<std::size_t>(j)] - me_;
    return -1;
  }
  int iterations() const { return iterations_; }  ///< constraints added and dropped, over all proximal iterations
  int proximal_iterations() const { return proximal_iterations_; }  ///< 0: G was definite

 private:
  /// solve()'s body, the warm start's rows in warm_ (num_warm_ of them).
  QpStatus solve_from_warm_start(const ConstMat& G, const ConstVec& a, const ConstMat& E, const ConstVec& e, const ConstMat& C,
                                 const ConstVec& c) {
    iterations_ = 0;
    proximal_iterations_ = 0;
    q_ = 0;
    status_ = check_input(G, a, E, e, C, c);
    if (status_ != QpStatus::solved) {
      n_ = me_ = mi_ = 0;
      return status_;
    }
    n_ = static_cast<int>(G.rows());
    me_ = static_cast<int>(E.rows());
    mi_ = static_cast<int>(C.rows());
    // Factor G; a pivot too small for it (semi-definite G) switches to proximal iterations.
    S scale = S(0);
    for (int i = 0; i < n_; ++i) scale = std::max(scale, std::abs(G(i, i)));
    const S floor = S(options_.regularization_threshold) * std::max(scale, S(1));
    if (cholesky(G, S(0), floor)) {
      status_ = solve_definite(a, E, e, C, c);
      return status_;
    }
    // Proximal point: G + eps I with the linear term a - eps x_k; eps = sqrt(machine epsilon) times
    // G's scale keeps G + eps I's condition number near 1 / sqrt(machine epsilon).
    const S eps = std::sqrt(std::numeric_limits<S>::epsilon()) * std::max(scale, S(1));
    const S size = S(1) + a.norm() + e.norm() + c.norm();
    if (!cholesky(G, eps, S(0))) return status_ = QpStatus::not_convex;
    x_.head(n_).setZero();
    for (proximal_iterations_ = 1; proximal_iterations_ <= options_.max_proximal_iterations; ++proximal_iterations_) {
      x_previous_.head(n_) = x_.head(n_);
      a_.head(n_) = a - eps * x_previous_.head(n_);
      if (proximal_iterations_ > 1) collect_warm_start();
      const QpStatus inner = solve_definite(a_.head(n_), E, e, C, c);
      if (inner != QpStatus::solved) return status_ = inner;
      // An unbounded problem's iterates grow by about |a| / eps a step: a hundred such steps are
      // taken as proof (no bounded problem of this scale has its solution that far out).
      if (!(x_.head(n_).norm() < S(100) * size / eps)) return status_ = QpStatus::unbounded;
      // Converged when the proximal term's share of the stationarity residual, eps (x - x_k), is
      // within the tolerance: x then satisfies the original problem's KKT conditions.
      if (eps * (x_.head(n_) - x_previous_.head(n_)).norm() <= S(options_.feasibility_tolerance) * (size + scale * x_.head(n_).norm()))
        return status_ = QpStatus::solved;
    }
    return status_ = QpStatus::max_iterations;
  }

  QpStatus check_input(const ConstMat& G, const ConstVec& a, const ConstMat& E, const ConstVec& e, const ConstMat& C, const ConstVec& c) const {
    const Eigen::Index n = G.rows();
    if (n < 1 || n > n_max_ || G.cols() != n || a.size() != n || (E.cols() != n && E.rows() > 0) || (C.cols() != n && C.rows() > 0) ||
        e.size() != E.rows() || c.size() != C.rows() || E.rows() > me_max_ || C.rows() > mi_max_)
      return QpStatus::invalid_input;
    if (!all_finite(G) || !all_finite(a) || !all_finite(E) || !all_finite(e) || !all_finite(C) || !all_finite(c)) return QpStatus::invalid_input;
    return QpStatus::solved;
  }
  /// Whether every entry is finite. A finite sum proves it (a NaN or an infinity makes the sum
  /// one), in one vectorised pass; only a sum that is not finite, which finite entries can reach
  /// by overflow, is checked entry by entry. (Eigen's allFinite, entry by entry, was 15 % of the
  /// IK's solve.)
  template <typename M> static bool all_finite(const M& m) { return std::isfinite(m.sum()) || m.allFinite(); }

  /// L L^T = G + shift I (lower triangle of L_), then J = L^-T. False when a pivot is not above
  /// floor (G + shift I not definite enough for the dual method).
  bool cholesky(const ConstMat& G, const S& shift, const S& floor) {
    auto L = L_.topLeftCorner(n_, n_);
    for (int j = 0; j < n_; ++j) {
      S pivot = G(j, j) + shift - L.row(j).head(j).squaredNorm();
      if (!(pivot > floor)) return false;
      L(j, j) = std::sqrt(pivot);
      for (int i = j + 1; i < n_; ++i) L(i, j) = (G(i, j) - L.row(i).head(j).dot(L.row(j).head(j))) / L(j, j);
    }
    // J = L^-T: upper triangular, column by column (L^T J = I).
    auto J = J_.topLeftCorner(n_, n_);
    J.setZero();
    for (int c = 0; c < n_; ++c) {
      for (int i = c; i >= 0; --i) {
        S sum = i == c ? S(1) : S(0);
        for (int k = i + 1; k <= c; ++k) sum -= L(k, i) * J(k, c);
        J(i, c) = sum / L(i, i);
      }
    }
    return true;
  }

  /// The previous proximal iteration's active inequalities become the next one's warm start.
  void collect_warm_start() {
    num_warm_ = 0;
    for (int k = 0; k < q_; ++k)
      if (active_[static_cast<std::size_t>(k)] >= me_) warm_[static_cast<std::size_t>(num_warm_++)] = active_[static_cast<std::size_t>(k)] - me_;
    q_ = 0;
  }

  auto J() { return J_.topLeftCorner(n_, n_); }
  auto x() { return x_.head(n_); }

  /// Goldfarb-Idnani on the factor in J_, linear term a.
  QpStatus solve_definite(const ConstVec& a, const ConstMat& E, const ConstVec& e, const ConstMat& C, const ConstVec& c) {
    const int max_iterations = options_.max_iterations > 0 ? options_.max_iterations : 5 * (n_ + me_ + mi_) + 20;
    // x = -G^-1 a = -J J^T a.
    d_.head(n_).noalias() = J().transpose() * a;
    x().noalias() = J() * d_.head(n_);
    x() = -x();
    q_ = 0;
    multipliers_.head(me_ + mi_).setZero();
    std::fill(flags_.begin(), flags_.begin() + me_ + mi_, 0);
    row_norm_.head(mi_) = C.rowwise().norm();
    // Equalities: each added with the step that satisfies it (any sign: their multipliers are free).
    for (int k = 0; k < me_; ++k)
      if (!add_as_equality(E.row(k), e[k], k)) return QpStatus::infeasible;
    // Warm start: the previous active inequalities, as equalities, then those with negative
    // multipliers dropped (most negative first) until the start is dual feasible. One that
    // depends on those already added and contradicts them is left to the main loop.
    if (num_warm_ > 0) {
      for (int w = 0; w < num_warm_; ++w) {
        const int i = warm_[static_cast<std::size_t>(w)];
        if (i < 0 || i >= mi_ || is_active(me_ + i)) continue;
        (void)add_as_equality(C.row(i), c[i], me_ + i);
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
    for (;;) {
      // The most violated inequality, its residual scaled by its row's size (all residuals in one
      // matrix-vector product: C is column-major, its rows strided).
      int p = -1;
      S worst = S(0);
      const S x_norm = x().norm();
      slack_.head(mi_).noalias() = C * x();
      for (int i = 0; i < mi_; ++i) {
        if (flags_[static_cast<std::size_t>(me_ + i)]) continue;
        const S s = slack_[i] - c[i];
        const S size = S(1) + std::abs(c[i]) + row_norm_[i] * x_norm;
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
        const S dependence = d_.segment(q_, n_ - q_).squaredNorm();
        const S s_p = C.row(p).dot(x()) - c[p];
        const bool independent = is_independent(dependence);
        const S t2 = independent ? -s_p / dependence : std::numeric_limits<S>::infinity();
        const S t = std::min(t1, t2);
        if (!(t < std::numeric_limits<S>::infinity())) return QpStatus::infeasible;
        if (!independent) {  // dual step only: constraint p depends on the active ones
          u_.head(q_) -= t * r_.head(q_);
          u_p += t;
          drop(blocking);
          continue;
        }
        x() += t * z_.head(n_);
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

  bool is_active(int id) const { return flags_[static_cast<std::size_t>(id)] != 0; }
  /// Whether a new normal keeps |d2| = |J2^T n| above round-off relative to |d| = |J^T n|.
  bool is_independent(const S& dependence) const {
    const S eps = std::numeric_limits<S>::epsilon();
    return dependence > S(1e6) * eps * eps * d_.head(n_).squaredNorm();
  }

  /// d = J^T n, z = J2 d2 (primal step), r = R^-1 d1 (dual step).
  template <typename Row> void step_directions(const Row& normal) {
    d_.head(n_).noalias() = J().transpose() * normal.transpose();
    z_.head(n_).noalias() = J().rightCols(n_ - q_) * d_.segment(q_, n_ - q_);
    r_.head(q_) = d_.head(q_);
    R_.topLeftCorner(q_, q_).template triangularView<Eigen::Upper>().solveInPlace(r_.head(q_));
  }

  /// Adds the constraint `normal x = value` (id) with the step that satisfies it; false if it
  /// depends on the active ones and contradicts them (the problem is infeasible). A dependent,
  /// consistent one is skipped (its multiplier stays zero).
  template <typename Row> bool add_as_equality(const Row& normal, const S& value, int id) {
    const S s = normal.dot(x()) - value;
    const bool consistent = std::abs(s) <= S(options_.feasibility_tolerance) * (S(1) + std::abs(value) + normal.norm() * x().norm());
    if (q_ >= n_) return consistent;
    step_directions(normal);
    const S dependence = d_.segment(q_, n_ - q_).squaredNorm();
    if (!is_independent(dependence)) return consistent;
    const S t = -s / dependence;
    x() += t * z_.head(n_);
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
      rotate_columns(j - 1, j, cs, sn);
    }
    R_.col(q_).head(q_ + 1) = d_.head(q_ + 1);
    active_[static_cast<std::size_t>(q_)] = id;
    flags_[static_cast<std::size_t>(id)] = 1;
    ++q_;
  }

  /// Removes active constraint j: R loses column j, its upper Hessenberg rest is made triangular
  /// by Givens rotations on rows (J's columns rotated alike), the multipliers follow.
  void drop(int j) {
    flags_[static_cast<std::size_t>(active_[static_cast<std::size_t>(j)])] = 0;
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
      rotate_columns(k, k + 1, cs, sn);
    }
    R_.col(q_).setZero();
  }

  /// The optimum of the equality-constrained subproblem on the active set and its multipliers:
  /// x = -J2 J2^T a + J1 R^-T b and u = R^-1 J1^T (G x + a) (Goldfarb and Idnani's N* = R^-1 J1^T).
  void subproblem_optimum(const ConstVec& a, const ConstVec& e, const ConstVec& c) {
    // b_A, the active constraints' right-hand sides, in r_; then w = R^-T b.
    for (int j = 0; j < q_; ++j) {
      const int id = active_[static_cast<std::size_t>(j)];
      r_[j] = id < me_ ? e[id] : c[id - me_];
    }
    R_.topLeftCorner(q_, q_).template triangularView<Eigen::Upper>().transpose().solveInPlace(r_.head(q_));
    d_.head(n_).noalias() = J().transpose() * a;
    x().noalias() = J().leftCols(q_) * r_.head(q_);
    x().noalias() -= J().rightCols(n_ - q_) * d_.segment(q_, n_ - q_);
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
  void rotate_columns(int i, int j, const S& c, const S& s) {
    for (int r = 0; r < n_; ++r) {
      const S left = J_(r, i), right = J_(r, j);
      J_(r, i) = c * left + s * right;
      J_(r, j) = -s * left + c * right;
    }
  }

  int n_max_, me_max_, mi_max_;
  DenseQpOptions options_;
  int n_ = 0, me_ = 0, mi_ = 0, q_ = 0, iterations_ = 0, proximal_iterations_ = 0, num_warm_ = 0;
  QpStatus status_ = QpStatus::solved;
  Mat L_, J_, R_;
  Vec x_, x_previous_, a_, d_, z_, r_, u_, multipliers_, slack_, row_norm_;
  std::vector<int> active_, warm_;
  std::vector<unsigned char> flags_;  ///< per constraint id (equalities, then inequalities): active
};

}  // namespace mbgen::control
