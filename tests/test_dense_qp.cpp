// control/dense_qp.hpp: the Goldfarb-Idnani solver against the KKT conditions of its problems and
// against Ipopt (Debian's coinor-libipopt-dev, an interior-point method: an independent algorithm)
// on random, degenerate, semi-definite and infeasible problems; warm start; no allocation.
#include <algorithm>
#include <numeric>

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include "malloc_guard.hpp"
#include "mbgen/control/dense_qp.hpp"
#include "test_support.hpp"

namespace {

using mbgen::control::DenseQp;
using mbgen::control::QpStatus;
using Mat = Eigen::MatrixXd;
using Vec = Eigen::VectorXd;

struct Problem {
  Mat G, E, C;
  Vec a, e, c;
  int n() const { return static_cast<int>(G.rows()); }
};

/// A random problem with a known feasible point x0: m_active inequalities hold as equalities at
/// x0, the others with slack; the unconstrained minimum is pushed outside so that several are
/// active at the optimum. rank < n gives G zero-curvature directions.
Problem random_problem(std::mt19937& rng, int n, int me, int mi, int rank = -1) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> slack(0.0, 1.0);
  Problem p;
  const int k = rank < 0 ? n : rank;
  Mat B(n, std::max(k, 1));
  for (int i = 0; i < B.size(); ++i) B.data()[i] = normal(rng);
  p.G = rank == 0 ? Mat::Zero(n, n) : Mat(B.leftCols(k) * B.leftCols(k).transpose() + (rank < 0 ? 0.1 : 0.0) * Mat::Identity(n, n));
  p.a = Vec::NullaryExpr(n, [&] { return 3 * normal(rng); });
  Vec x0 = Vec::NullaryExpr(n, [&] { return normal(rng); });
  p.E = Mat::NullaryExpr(me, n, [&] { return normal(rng); });
  p.e = p.E * x0;
  p.C = Mat::NullaryExpr(mi, n, [&] { return normal(rng); });
  p.c = p.C * x0 - Vec::NullaryExpr(mi, [&] { return slack(rng) * (slack(rng) < 0.3 ? 0.0 : 1.0); });
  return p;
}

/// min 1/2 |x|^2 in n variables, no constraint yet: the start of the hand-written cases.
Problem unit_problem(int n) {
  Problem p;
  p.G = Mat::Identity(n, n);
  p.a = Vec::Zero(n);
  p.E = Mat(0, n), p.e = Vec(0);
  p.C = Mat(0, n), p.c = Vec(0);
  return p;
}

/// The KKT residuals of (x, multipliers): stationarity, primal and dual feasibility,
/// complementarity, each relative to the problem's size.
struct Kkt {
  double stationarity, equality, inequality, dual, complementarity;
  double worst() const { return std::max({stationarity, equality, inequality, dual, complementarity}); }
};
Kkt kkt(const Problem& p, const Vec& x, const Eigen::Ref<const Vec>& lambda) {
  const int me = static_cast<int>(p.E.rows()), mi = static_cast<int>(p.C.rows());
  const Vec le = lambda.head(me), lc = lambda.tail(mi);
  const double scale = 1 + p.G.norm() * x.norm() + p.a.norm();
  Kkt k{};
  k.stationarity = (p.G * x + p.a - p.E.transpose() * le - p.C.transpose() * lc).norm() / scale;
  k.equality = me ? (p.E * x - p.e).cwiseAbs().maxCoeff() / (1 + p.e.norm()) : 0;
  const Vec s = p.C * x - p.c;
  k.inequality = mi ? std::max(0.0, -s.minCoeff()) / (1 + p.c.norm()) : 0;
  k.dual = mi ? std::max(0.0, -lc.minCoeff()) / scale : 0;
  k.complementarity = mi ? (s.cwiseProduct(lc)).cwiseAbs().maxCoeff() / (scale * (1 + p.c.norm())) : 0;
  return k;
}

/// The same QP for Ipopt: f = 1/2 x'Gx + a'x, g = [E x; C x] in [e, e] and [c, inf).
class IpoptQp : public Ipopt::TNLP {
 public:
  explicit IpoptQp(const Problem& p) : p_(p) {}
  Vec x;
  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac, Ipopt::Index& nnz_h, IndexStyleEnum& style) override {
    n = p_.n();
    m = static_cast<int>(p_.E.rows() + p_.C.rows());
    nnz_jac = n * m;
    nnz_h = n * (n + 1) / 2;
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Ipopt::Index n, double* xl, double* xu, Ipopt::Index m, double* gl, double* gu) override {
    for (int i = 0; i < n; ++i) xl[i] = -2e19, xu[i] = 2e19;
    const int me = static_cast<int>(p_.E.rows());
    for (int j = 0; j < m; ++j) {
      if (j < me) gl[j] = gu[j] = p_.e[j];
      else gl[j] = p_.c[j - me], gu[j] = 2e19;
    }
    return true;
  }
  bool get_starting_point(Ipopt::Index n, bool, double* x0, bool, double*, double*, Ipopt::Index, bool, double*) override {
    for (int i = 0; i < n; ++i) x0[i] = 0;
    return true;
  }
  bool eval_f(Ipopt::Index n, const double* x, bool, double& f) override {
    const Eigen::Map<const Vec> v(x, n);
    f = 0.5 * v.dot(p_.G * v) + p_.a.dot(v);
    return true;
  }
  bool eval_grad_f(Ipopt::Index n, const double* x, bool, double* g) override {
    Eigen::Map<Vec>(g, n) = p_.G * Eigen::Map<const Vec>(x, n) + p_.a;
    return true;
  }
  bool eval_g(Ipopt::Index n, const double* x, bool, Ipopt::Index m, double* g) override {
    const Eigen::Map<const Vec> v(x, n);
    const int me = static_cast<int>(p_.E.rows());
    Eigen::Map<Vec> out(g, m);
    out.head(me) = p_.E * v;
    out.tail(m - me) = p_.C * v;
    return true;
  }
  bool eval_jac_g(Ipopt::Index n, const double*, bool, Ipopt::Index m, Ipopt::Index, Ipopt::Index* row, Ipopt::Index* col,
                  double* values) override {
    const int me = static_cast<int>(p_.E.rows());
    for (int j = 0, k = 0; j < m; ++j)
      for (int i = 0; i < n; ++i, ++k) {
        if (values) values[k] = j < me ? p_.E(j, i) : p_.C(j - me, i);
        else row[k] = j, col[k] = i;
      }
    return true;
  }
  bool eval_h(Ipopt::Index n, const double*, bool, double sigma, Ipopt::Index, const double*, bool, Ipopt::Index, Ipopt::Index* row,
              Ipopt::Index* col, double* values) override {
    for (int i = 0, k = 0; i < n; ++i)
      for (int j = 0; j <= i; ++j, ++k) {
        if (values) values[k] = sigma * p_.G(i, j);
        else row[k] = i, col[k] = j;
      }
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const double* xs, const double*, const double*, Ipopt::Index, const double*,
                         const double*, double, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    x = Eigen::Map<const Vec>(xs, n);
  }

 private:
  const Problem& p_;
};

/// Ipopt's solution of p (tolerance 1e-12), or an empty vector if Ipopt did not converge.
Vec ipopt_solution(const Problem& p) {
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetNumericValue("tol", 1e-12);
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetStringValue("hessian_constant", "yes");
  app->Options()->SetStringValue("jac_c_constant", "yes");
  app->Options()->SetStringValue("jac_d_constant", "yes");
  if (app->Initialize() != Ipopt::Solve_Succeeded) return {};
  Ipopt::SmartPtr<IpoptQp> nlp = new IpoptQp(p);
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(nlp));
  if (status != Ipopt::Solve_Succeeded && status != Ipopt::Solved_To_Acceptable_Level) return {};
  return nlp->x;
}

QpStatus solve(DenseQp<double>& qp, const Problem& p, bool warm = false) { return qp.solve(p.G, p.a, p.E, p.e, p.C, p.c, warm); }

TEST(DenseQp, RandomFeasibleProblemsSatisfyTheKktConditions) {
  std::mt19937 rng(1);
  int with_active = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 2 + trial % 39, me = trial % 3 == 0 ? std::min(n - 1, trial % 5) : 0, mi = (trial * 7) % 101;
    const Problem p = random_problem(rng, n, me, mi);
    DenseQp<double> qp(n, me, mi);
    ASSERT_EQ(solve(qp, p), QpStatus::solved) << "trial " << trial;
    const Kkt k = kkt(p, qp.solution(), qp.multipliers());
    EXPECT_LE(k.worst(), 1e-9) << "trial " << trial << ": stationarity " << k.stationarity << ", equality " << k.equality
                               << ", inequality " << k.inequality << ", dual " << k.dual << ", complementarity " << k.complementarity;
    with_active += qp.num_active_inequalities() > 0;
  }
  EXPECT_GE(with_active, 150);  // the problems are built to have active inequalities
}

TEST(DenseQp, AgreesWithIpoptOnRandomProblemsWithActiveInequalities) {
  std::mt19937 rng(2);
  int compared = 0, active = 0;
  double worst = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 3 + trial % 28, me = trial % 4 == 0 ? 2 : 0, mi = 10 + (trial * 13) % 90;
    const Problem p = random_problem(rng, n, me, mi);
    DenseQp<double> qp(n, me, mi);
    ASSERT_EQ(solve(qp, p), QpStatus::solved) << "trial " << trial;
    const Vec reference = ipopt_solution(p);
    ASSERT_EQ(reference.size(), n) << "Ipopt failed on trial " << trial;
    const double difference = (qp.solution() - reference).norm() / (1 + reference.norm());
    worst = std::max(worst, difference);
    EXPECT_LE(difference, 1e-6) << "trial " << trial;
    ++compared;
    active += qp.num_active_inequalities() > 0;
  }
  EXPECT_EQ(compared, 60);
  EXPECT_GE(active, 50);
  std::printf("largest relative difference from Ipopt over %d problems: %.1e\n", compared, worst);
}

TEST(DenseQp, DependentActiveConstraintsAtAVertex) {
  // Minimise |x - (0, 0, 5)|^2 below a pyramid whose apex (0, 0, 1) six faces share: more active
  // constraints than variables (their multipliers not unique), one plane given three times.
  Problem p;
  p.G = 2 * Mat::Identity(3, 3);
  p.a = Eigen::Vector3d(0, 0, -10);
  p.E = Mat(0, 3), p.e = Vec(0);
  p.C = Mat(6, 3);
  p.C << -1, 0, -1,  //
      0, -1, -1,     //
      1, 0, -1,      //
      0, 1, -1,      //
      -1, 0, -1,     // the first face again
      -2, 0, -2;     // and scaled
  p.c = Vec(6);
  p.c << -1, -1, -1, -1, -1, -2;
  DenseQp<double> qp(3, 0, 6);
  ASSERT_EQ(solve(qp, p), QpStatus::solved);
  EXPECT_LE(kkt(p, qp.solution(), qp.multipliers()).worst(), 1e-12);
  const Vec reference = ipopt_solution(p);
  ASSERT_EQ(reference.size(), 3);
  EXPECT_LE((qp.solution() - reference).norm(), 1e-6);
  EXPECT_LE((qp.solution() - Eigen::Vector3d::UnitZ()).norm(), 1e-12) << qp.solution().transpose();
}

TEST(DenseQp, ZeroCurvatureDirectionsBoundedByConstraints) {
  std::mt19937 rng(3);
  int solved = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 3 + trial % 10, rank = trial % 4 == 0 ? 0 : n / 2;
    Problem p = random_problem(rng, n, 0, 0, rank);
    // A box keeps every zero-curvature direction bounded.
    p.C = Mat(2 * n, n);
    p.C << Mat::Identity(n, n), -Mat::Identity(n, n);
    p.c = -Vec::Constant(2 * n, 1.5);
    DenseQp<double> qp(n, 0, 2 * n);
    ASSERT_EQ(solve(qp, p), QpStatus::solved) << "trial " << trial << " (rank " << rank << ")";
    EXPECT_GT(qp.proximal_iterations(), 0);
    EXPECT_LE(kkt(p, qp.solution(), qp.multipliers()).worst(), 1e-9) << "trial " << trial;
    const Vec reference = ipopt_solution(p);
    ASSERT_EQ(reference.size(), n);
    // The minimiser need not be unique along a flat face: compare objective values.
    const auto f = [&](const Vec& x) { return 0.5 * x.dot(p.G * x) + p.a.dot(x); };
    EXPECT_LE(f(qp.solution()) - f(reference), 1e-7 * (1 + std::abs(f(reference)))) << "trial " << trial;
    ++solved;
  }
  EXPECT_EQ(solved, 40);
}

TEST(DenseQp, UnboundedWithoutCurvatureOrConstraint) {
  Problem p;
  p.G = Mat::Zero(2, 2);
  p.G(0, 0) = 1;
  p.a = Vec(2);
  p.a << 1, -1;  // decreasing along +x_1 forever
  p.E = Mat(0, 2), p.e = Vec(0);
  p.C = Mat(1, 2);
  p.C << 1, 0;
  p.c = Vec::Constant(1, -1);
  DenseQp<double> qp(2, 0, 1);
  EXPECT_EQ(solve(qp, p), QpStatus::unbounded);
  p.C << 0, -1;  // x_1 <= 3 bounds it
  p.c << -3;
  ASSERT_EQ(solve(qp, p), QpStatus::solved);
  EXPECT_NEAR(qp.solution()[1], 3, 1e-12);
  EXPECT_NEAR(qp.solution()[0], -1, 1e-12);
}

TEST(DenseQp, InfeasibleProblemsAreReported) {
  DenseQp<double> qp(2, 2, 3);
  Problem p = unit_problem(2);
  p.C = Mat(2, 2);
  p.C << 1, 0, -1, 0;  // x >= 1 and x <= 0
  p.c = Vec(2);
  p.c << 1, 0;
  EXPECT_EQ(solve(qp, p), QpStatus::infeasible);
  // Three half-planes with no common point: x >= 0, y >= 0, x + y <= -1.
  p.C = Mat(3, 2);
  p.C << 1, 0, 0, 1, -1, -1;
  p.c = Vec(3);
  p.c << 0, 0, 1;
  EXPECT_EQ(solve(qp, p), QpStatus::infeasible);
  // Dependent equalities that contradict each other.
  p.C = Mat(0, 2), p.c = Vec(0);
  p.E = Mat(2, 2);
  p.E << 1, 1, 2, 2;
  p.e = Vec(2);
  p.e << 1, 3;
  EXPECT_EQ(solve(qp, p), QpStatus::infeasible);
  p.e << 1, 2;  // consistent: solved, the second row ignored
  ASSERT_EQ(solve(qp, p), QpStatus::solved);
  EXPECT_NEAR(qp.solution().sum(), 1, 1e-14);
  // Random infeasible ones: a feasible problem plus the negation of one of its rows, shifted.
  std::mt19937 rng(4);
  for (int trial = 0; trial < 30; ++trial) {
    const int n = 2 + trial % 15, mi = 5 + trial;
    Problem r = random_problem(rng, n, 0, mi);
    r.C.row(mi - 1) = -r.C.row(0);
    r.c[mi - 1] = -r.c[0] + 0.5;  // C_0 x >= c_0 and C_0 x <= c_0 - 0.5
    DenseQp<double> solver(n, 0, mi);
    EXPECT_EQ(solve(solver, r), QpStatus::infeasible) << "trial " << trial;
  }
}

TEST(DenseQp, WarmStartReachesTheSameSolutionInFewerIterations) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  int cold_total = 0, warm_total = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const int n = 20, mi = 80;
    Problem p = random_problem(rng, n, 0, mi);
    DenseQp<double> cold(n, 0, mi), warm(n, 0, mi);
    ASSERT_EQ(solve(warm, p), QpStatus::solved);
    // The next control cycle: the same constraints, slightly moved data.
    p.a += 0.01 * Vec::NullaryExpr(n, [&] { return normal(rng); });
    p.c -= 0.01 * Vec::NullaryExpr(mi, [&] { return std::abs(normal(rng)); });  // x0 stays feasible
    ASSERT_EQ(solve(cold, p), QpStatus::solved);
    ASSERT_EQ(solve(warm, p, true), QpStatus::solved);
    EXPECT_LE((warm.solution() - cold.solution()).norm(), 1e-10 * (1 + cold.solution().norm())) << "trial " << trial;
    EXPECT_LE(kkt(p, warm.solution(), warm.multipliers()).worst(), 1e-9);
    cold_total += cold.iterations();
    warm_total += warm.iterations();
  }
  EXPECT_LT(warm_total, cold_total / 2) << "warm " << warm_total << ", cold " << cold_total;
}

TEST(DenseQp, WarmStartFromGivenRowsAfterTheRowsAreRenumbered) {
  // The IK's case: between two solves rows come and go, so the caller maps the last active rows
  // to their new indices. The right rows save the iterations; wrong ones, out-of-range and
  // repeated ones change nothing but the count.
  std::mt19937 rng(6);
  std::normal_distribution<double> normal;
  int cold_total = 0, mapped_total = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const int n = 20, mi = 80;
    Problem p = random_problem(rng, n, 0, mi);
    DenseQp<double> first(n, 0, mi), cold(n, 0, mi), mapped(n, 0, mi), wrong(n, 0, mi);
    ASSERT_EQ(solve(first, p), QpStatus::solved);
    ASSERT_GT(first.num_active_inequalities(), 0) << "trial " << trial;
    // The next cycle: the data moved a little and the rows shuffled (row i is now row perm[i]).
    std::vector<int> perm(static_cast<std::size_t>(mi));
    std::iota(perm.begin(), perm.end(), 0);
    std::shuffle(perm.begin(), perm.end(), rng);
    Problem next = p;
    for (int i = 0; i < mi; ++i) {
      next.C.row(perm[static_cast<std::size_t>(i)]) = p.C.row(i);
      next.c[perm[static_cast<std::size_t>(i)]] = p.c[i];
    }
    next.a += 0.01 * Vec::NullaryExpr(n, [&] { return normal(rng); });
    std::vector<int> start;
    for (int j = 0; j < first.num_active_inequalities(); ++j) start.push_back(perm[static_cast<std::size_t>(first.active_inequality(j))]);
    ASSERT_EQ(solve(cold, next), QpStatus::solved);
    ASSERT_EQ(mapped.solve(next.G, next.a, next.E, next.e, next.C, next.c, start.data(), static_cast<int>(start.size())), QpStatus::solved);
    std::vector<int> bad = {-1, mi, 1000, 3, 3, 7, 11, 19, 40, 79, 5, 6, 8, 9, 10, 12, 13, 14, 15, 16, 17, 18, 20, 21, 22};
    ASSERT_EQ(wrong.solve(next.G, next.a, next.E, next.e, next.C, next.c, bad.data(), static_cast<int>(bad.size())), QpStatus::solved);
    for (const DenseQp<double>* qp : {&mapped, &wrong}) {
      EXPECT_LE((qp->solution() - cold.solution()).norm(), 1e-10 * (1 + cold.solution().norm())) << "trial " << trial;
      EXPECT_LE(kkt(next, qp->solution(), qp->multipliers()).worst(), 1e-9) << "trial " << trial;
    }
    cold_total += cold.iterations();
    mapped_total += mapped.iterations();
  }
  EXPECT_LT(mapped_total, cold_total / 2) << "mapped " << mapped_total << ", cold " << cold_total;
}

TEST(DenseQp, InvalidInputIsReportedNotSolved) {
  DenseQp<double> qp(2, 0, 1);
  Problem p = unit_problem(2);
  p.C = Mat(2, 2);  // more rows than the solver was sized for
  p.C.setIdentity();
  p.c = Vec::Zero(2);
  EXPECT_EQ(solve(qp, p), QpStatus::invalid_input);
  p.C = Mat::Identity(1, 2);
  p.c = Vec::Zero(1);
  p.a[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(solve(qp, p), QpStatus::invalid_input);
  p.a[1] = 0;
  // Finite entries whose sum overflows are input, not garbage (the check sums first).
  p.C(0, 0) = p.C(0, 1) = 1e308;
  EXPECT_EQ(solve(qp, p), QpStatus::solved);
  p.C = Mat::Identity(1, 2);
  p.G(1, 1) = -1;  // indefinite
  EXPECT_EQ(solve(qp, p), QpStatus::not_convex);
  EXPECT_THROW(DenseQp<double>(0, 0, 0), std::invalid_argument);
}

TEST(DenseQp, SolveDoesNotAllocate) {
  std::mt19937 rng(6);
  const Problem p = random_problem(rng, 30, 3, 100), small = random_problem(rng, 12, 0, 40), flat = random_problem(rng, 10, 0, 0, 4);
  Problem boxed = flat;
  boxed.C = Mat(20, 10);
  boxed.C << Mat::Identity(10, 10), -Mat::Identity(10, 10);
  boxed.c = -Vec::Ones(20);
  DenseQp<double> qp(30, 3, 100);
  ASSERT_EQ(solve(qp, p), QpStatus::solved);
  std::size_t allocations = 0;
  QpStatus statuses[5];
  const int start_rows[3] = {4, 2, 99};
  {
    const mbgen::test::MallocGuard guard;
    statuses[0] = qp.solve(p.G, p.a, p.E, p.e, p.C.topRows(60), p.c.head(60));
    statuses[1] = qp.solve(p.G, p.a, p.E, p.e, p.C, p.c, true);
    statuses[2] = solve(qp, small);  // fewer variables: a corner of the same storage
    statuses[3] = solve(qp, boxed);  // semi-definite: proximal iterations
    statuses[4] = qp.solve(p.G, p.a, p.E, p.e, p.C, p.c, start_rows, 3);
    allocations = guard.count();
  }
  EXPECT_EQ(allocations, 0u);
  for (const QpStatus s : statuses) EXPECT_EQ(s, QpStatus::solved);
  DenseQp<double> fresh(12, 0, 40);
  ASSERT_EQ(solve(fresh, small), QpStatus::solved);
  ASSERT_EQ(solve(qp, small), QpStatus::solved);
  EXPECT_EQ(qp.solution(), fresh.solution());  // the same arithmetic whatever the capacity
}

TEST(DenseQp, FloatSolvesToItsPrecision) {
  std::mt19937 rng(7);
  const Problem p = random_problem(rng, 12, 1, 30);
  DenseQp<double> reference(12, 1, 30);
  ASSERT_EQ(solve(reference, p), QpStatus::solved);
  DenseQp<float> qp(12, 1, 30);
  const Eigen::MatrixXf G = p.G.cast<float>(), E = p.E.cast<float>(), C = p.C.cast<float>();
  const Eigen::VectorXf a = p.a.cast<float>(), e = p.e.cast<float>(), c = p.c.cast<float>();
  ASSERT_EQ(qp.solve(G, a, E, e, C, c), QpStatus::solved);
  EXPECT_LE((qp.solution().cast<double>() - reference.solution()).norm(), 1e-3 * (1 + reference.solution().norm()));
}

TEST(DenseQp, CopiedBeforeFirstSolveIsWhole) {
  std::mt19937 rng(8);
  const Problem p = random_problem(rng, 8, 0, 12);
  DenseQp<double> original(8, 0, 12);
  DenseQp<double> copy = original;
  DenseQp<double> moved = std::move(original);
  ASSERT_EQ(solve(copy, p), QpStatus::solved);
  ASSERT_EQ(solve(moved, p), QpStatus::solved);
  EXPECT_EQ(copy.solution(), moved.solution());
}

}  // namespace
