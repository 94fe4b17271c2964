// SSV pair distances (runtime/include/mbgen/collision/) against an independent reference, on
// seeded random and adversarial cases (about 1.3e5 in total).
//
// Reference: the cores are simplices (1, 2 or 3 corners). The squared core distance is a convex
// quadratic over the product of the two simplices, so its minimum is the stationary point of
// the affine hulls of some pair of faces (a face: a non-empty subset of the corners) that lies
// inside both faces. The reference enumerates every face pair (up to 7 x 7), solves the least
// squares problem of each in long double (column-pivoted Householder QR, so the error grows
// with the condition number of the edge matrix, not its square, which thin triangles need;
// rank-deficient systems are skipped, a lower face attains the same minimum), keeps the feasible ones and
// evaluates the distance at the minimiser in long double. It shares no code and no case analysis
// with the production path. It is itself checked against dense parametric sampling
// (Reference.NotAboveDenseSampling).
//
// Tolerances (scale = largest coordinate magnitude of the case, at least the core size):
//   double: |d - d_ref| <= 1e-12 scale (the issue asks 1e-9; measured worst ~1e-15 scale, i.e.
//           a few eps, printed by each test); returned core points on their cores within 1e-12
//           scale (reference point-to-core distance); |core2 - core1| == core_distance to 1e-12
//           scale; |n| = 1 to 1e-12; point2 - point1 == d n to 1e-12 scale; swapped arguments
//           give the same distance to 1e-12 scale and, when the cores are apart by more than
//           1e-12 scale, the negated normal to 1e-12 scale / core distance (a closest point off by
//           delta turns the normal by ~delta / core distance).
//           Reference distance never below the returned one by more than the tolerance: implied
//           by the two-sided distance check.
//   float:  inputs rounded to float, reference (long double) on the rounded inputs. A closest
//           point is a few operations on inputs of magnitude <= scale, each adding a rounding
//           error <= eps_f scale / 2 (eps_f = 2^-23 ~ 1.2e-7); the distance is 1-Lipschitz in
//           both points, so a handful of operations per point gives well under 16 eps_f scale:
//           |d - d_ref| <= 16 eps_f scale ~ 1.9e-6 scale (measured worst ~3 eps_f), core points
//           on cores within 16 eps_f scale, |n| = 1 to 16 eps_f; point2 - point1 == d n and
//           swapped normals to 64 eps_f scale (/ core distance): with touching cores (at most
//           16 eps_f scale apart, ssv_distance.hpp) the fallback normal is not along core2 - core1.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/QR>

#include "malloc_guard.hpp"
#include "mbgen/collision/ssv_distance.hpp"
#include "mbgen/spatial/types.hpp"  // Eigen vectors: the tests build SSVs from them (SsvVec3 converts)

namespace mbgen::collision {
namespace {

using LD = long double;
using V3 = Eigen::Matrix<LD, 3, 1>;

// ---------------------------------------------------------------- reference (long double)

/// A core as its corners: 1 (point), 2 (segment) or 3 (triangle).
struct Core {
  std::vector<Vec3<double>> v;
};

V3 to_ld(const Vec3<double>& p) { return p.cast<LD>(); }

/// Minimum distance over the face pair (mask1 of core a, mask2 of core b); +inf if the
/// stationary point is outside the faces or the system is singular.
LD face_pair_distance(const Core& a, unsigned mask1, const Core& b, unsigned mask2) {
  std::vector<V3> f1, f2;
  for (std::size_t i = 0; i < a.v.size(); ++i)
    if (mask1 & (1u << i)) f1.push_back(to_ld(a.v[i]));
  for (std::size_t i = 0; i < b.v.size(); ++i)
    if (mask2 & (1u << i)) f2.push_back(to_ld(b.v[i]));
  // P - Q = r + J x, x = (alpha_1.., beta_1..); P = f1[0] + sum alpha_i (f1[i] - f1[0]).
  const V3 r = f1[0] - f2[0];
  std::vector<V3> cols;
  for (std::size_t i = 1; i < f1.size(); ++i) cols.push_back(f1[i] - f1[0]);
  for (std::size_t i = 1; i < f2.size(); ++i) cols.push_back(-(f2[i] - f2[0]));
  const int k = static_cast<int>(cols.size());
  Eigen::Matrix<LD, 4, 1> x = Eigen::Matrix<LD, 4, 1>::Zero();
  if (k > 0) {
    Eigen::Matrix<LD, 3, Eigen::Dynamic> J(3, k);
    for (int i = 0; i < k; ++i) J.col(i) = cols[i];
    Eigen::ColPivHouseholderQR<Eigen::Matrix<LD, 3, Eigen::Dynamic>> qr(J);
    qr.setThreshold(1e-30L);
    if (qr.rank() < k) return std::numeric_limits<LD>::infinity();
    x.head(k) = qr.solve(-r);
  }
  // Feasibility: barycentrics of each face non-negative.
  const int k1 = static_cast<int>(f1.size()) - 1;
  LD sum1 = 0, sum2 = 0;
  for (int i = 0; i < k; ++i) {
    if (x[i] < 0) return std::numeric_limits<LD>::infinity();
    (i < k1 ? sum1 : sum2) += x[i];
  }
  if (sum1 > 1 || sum2 > 1) return std::numeric_limits<LD>::infinity();
  V3 d = r;
  for (int i = 0; i < k; ++i) d += x[i] * cols[i];
  return d.norm();
}

/// The exact core distance, by enumeration of face pairs.
LD reference_distance(const Core& a, const Core& b) {
  LD best = std::numeric_limits<LD>::infinity();
  for (unsigned m1 = 1; m1 < (1u << a.v.size()); ++m1)
    for (unsigned m2 = 1; m2 < (1u << b.v.size()); ++m2) best = std::min(best, face_pair_distance(a, m1, b, m2));
  return best;
}

LD reference_point_distance(const Vec3<double>& p, const Core& b) { return reference_distance(Core{{p}}, b); }

/// A point of the core at parameters (u, w) in [0,1]^2: the segment at u; the triangle at
/// barycentrics (1 - u, u (1 - w), u w) (covers the triangle as u, w sweep the square).
V3 core_point(const Core& c, LD u, LD w) {
  if (c.v.size() == 1) return to_ld(c.v[0]);
  if (c.v.size() == 2) return (1 - u) * to_ld(c.v[0]) + u * to_ld(c.v[1]);
  return (1 - u) * to_ld(c.v[0]) + u * (1 - w) * to_ld(c.v[1]) + u * w * to_ld(c.v[2]);
}

// ---------------------------------------------------------------- cases

using PointD = PointSsv<double>;
using LineD = LineSsv<double>;
using TriD = TriangleSsv<double>;

Core core_of(const PointD& x) { return {{x.center}}; }
Core core_of(const LineD& x) { return {{x.p0, x.p1}}; }
Core core_of(const TriD& x) { return {{x.a, x.b, x.c}}; }

double max_coord(const Core& c) {
  double m = 0;
  for (const auto& p : c.v) m = std::max(m, p.cwiseAbs().maxCoeff());
  return m;
}
double core_size(const Core& c) {
  double m = 0;
  for (const auto& p : c.v)
    for (const auto& q : c.v) m = std::max(m, (p - q).norm());
  return m;
}

/// The scale of a case: the largest coordinate magnitude, at least the size of either core (cases
/// at the mm scale are built near the origin).
double scale_of(const Core& a, const Core& b) { return std::max({max_coord(a), max_coord(b), core_size(a), core_size(b)}); }

template <typename X> X swapped_radius(X x, double r) {
  x.radius = r;
  return x;
}

struct Tolerances {
  double distance, on_core, unit, consistency;
};
constexpr Tolerances kDouble{1e-12, 1e-12, 1e-12, 1e-12};
constexpr double kEpsF = 1.1920928955078125e-07;  // 2^-23
constexpr Tolerances kFloat{16 * kEpsF, 16 * kEpsF, 16 * kEpsF, 64 * kEpsF};

/// Failure counting with a few printed examples (a failing seed prints its case).
struct Checker {
  std::string kind;
  int failures = 0;
  int cases = 0;
  int ties = 0;  // swapped calls that returned another, equally close pair
  double worst_distance_error = 0;  // in units of scale
  void fail(const std::string& what) {
    if (++failures <= 5) ADD_FAILURE() << kind << ": " << what;
  }
};

bool all_finite(const SsvDistance<double>& r) {
  return std::isfinite(r.distance) && std::isfinite(r.core_distance) && r.normal.allFinite() && r.point1.allFinite() &&
         r.point2.allFinite() && r.core1.allFinite() && r.core2.allFinite();
}
bool all_finite(const SsvDistance<float>& r) {
  return std::isfinite(r.distance) && std::isfinite(r.core_distance) && r.normal.allFinite() && r.point1.allFinite() &&
         r.point2.allFinite() && r.core1.allFinite() && r.core2.allFinite();
}

std::string describe(const Core& a, double ra, const Core& b, double rb) {
  std::string s;
  char buf[128];
  for (const Core* c : {&a, &b}) {
    s += "{";
    for (const auto& p : c->v) {
      std::snprintf(buf, sizeof buf, "(%.17g, %.17g, %.17g) ", p.x(), p.y(), p.z());
      s += buf;
    }
    std::snprintf(buf, sizeof buf, "r %.17g} ", c == &a ? ra : rb);
    s += buf;
  }
  return s;
}

/// Every check on one result r of volumes (x, y), in double or float (S); cores a, b are the
/// inputs as seen by S (rounded for float).
template <typename S>
void check_result(Checker& chk, const SsvDistance<S>& r, const Core& a, double ra, const Core& b, double rb,
                  const Tolerances& tol) {
  ++chk.cases;
  const double scale = scale_of(a, b);
  const std::string where = describe(a, ra, b, rb);
  if (!all_finite(r)) return chk.fail("non-finite result for " + where);
  const LD ref = reference_distance(a, b);
  const double d_ref = static_cast<double>(ref) - ra - rb;
  const double err = std::fabs(static_cast<double>(r.distance) - d_ref);
  chk.worst_distance_error = std::max(chk.worst_distance_error, err / scale);
  if (err > tol.distance * scale)
    chk.fail("distance " + std::to_string(r.distance) + " vs reference " + std::to_string(d_ref) + " (error " +
             std::to_string(err / scale) + " scale) for " + where);
  const Vec3<double> c1 = r.core1.template cast<double>(), c2 = r.core2.template cast<double>();
  const Vec3<double> n = r.normal.template cast<double>();
  if (static_cast<double>(reference_point_distance(c1, a)) > tol.on_core * scale) chk.fail("core1 off core 1 for " + where);
  if (static_cast<double>(reference_point_distance(c2, b)) > tol.on_core * scale) chk.fail("core2 off core 2 for " + where);
  if (std::fabs((c2 - c1).norm() - static_cast<double>(r.core_distance)) > tol.consistency * scale)
    chk.fail("|core2 - core1| != core_distance for " + where);
  if (std::fabs(n.norm() - 1) > tol.unit) chk.fail("|n| != 1 for " + where);
  const Vec3<double> p1 = r.point1.template cast<double>(), p2 = r.point2.template cast<double>();
  if ((p2 - p1 - static_cast<double>(r.distance) * n).norm() > tol.consistency * scale)
    chk.fail("point2 - point1 != d n for " + where);
  if (static_cast<double>(r.core_distance) > tol.distance * scale &&
      ((c2 - c1) - static_cast<double>(r.core_distance) * n).norm() > tol.consistency * scale)
    chk.fail("normal not along core2 - core1 for " + where);
}

/// Symmetry: the swapped call gives the same distance and, when the cores are apart, -n.
template <typename S>
void check_swap(Checker& chk, const SsvDistance<S>& r, const SsvDistance<S>& s, double scale, const Tolerances& tol) {
  if (!all_finite(s)) return chk.fail("non-finite swapped result");
  if (std::fabs(static_cast<double>(r.distance - s.distance)) > tol.distance * scale)
    chk.fail("swapped distance differs: " + std::to_string(r.distance) + " vs " + std::to_string(s.distance));
  // A closest point off by delta turns the normal by ~delta / core distance: allowed delta is
  // the consistency tolerance. When the swapped call returns a different closest pair (further
  // apart than 1e-6 scale: a tie between two features, e.g. a point equidistant from two
  // corners, where the normal is discontinuous), the swapped result was checked in full by
  // check_result and only the distance must agree; such ties are counted and printed.
  const double core = static_cast<double>(r.core_distance);
  const double normal_error = (r.normal + s.normal).template cast<double>().norm();
  const double pair_offset = (r.core1 - s.core2).template cast<double>().norm() + (r.core2 - s.core1).template cast<double>().norm();
  if (pair_offset > 1e-6 * scale) {
    ++chk.ties;
    return;
  }
  if (core > tol.distance * scale && normal_error > tol.consistency * scale / core)
    chk.fail("swapped normal is not negated: core distance " + std::to_string(core / scale * 1e9) +
             "e-9 scale, |n + n_swapped| = " + std::to_string(normal_error * 1e9) + "e-9");
}

// Random generation ---------------------------------------------------------

struct Gen {
  std::mt19937_64 rng;
  explicit Gen(unsigned seed) : rng(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
  Vec3<double> vec(double s) { return {uniform(-s, s), uniform(-s, s), uniform(-s, s)}; }
  Vec3<double> unit() {
    for (;;) {
      Vec3<double> v = vec(1);
      if (v.norm() > 0.1 && v.norm() <= 1) return v.normalized();
    }
  }
  /// A unit vector perpendicular to u.
  Vec3<double> perp(const Vec3<double>& u) {
    for (;;) {
      Vec3<double> v = unit();
      v -= v.dot(u) * u;
      if (v.norm() > 0.1) return v.normalized();
    }
  }
  double radius(double s) { return integer(0, 4) == 0 ? 0.0 : uniform(0, 0.3 * s); }
  double scale() {
    static const double scales[] = {1e-3, 1e-2, 1e-1, 1.0};
    return scales[integer(0, 3)];
  }
};

/// The cores of a case, double precision, and helpers to build the SSVs.
PointD point(const Vec3<double>& c, double r) { return {c, r}; }
LineD line(const Vec3<double>& p0, const Vec3<double>& p1, double r) { return {p0, p1, r}; }
TriD tri(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c, double r) { return {a, b, c, r}; }

/// A random point-like, segment-like or triangle-like core with a chance of degeneracy.
Vec3<double> near(Gen& g, const Vec3<double>& p, double s) {
  switch (g.integer(0, 5)) {
    case 0: return p;                                          // coincident
    case 1: return p + g.unit() * s * std::pow(10.0, -g.integer(6, 15));  // almost coincident
    default: return g.vec(s);
  }
}

LineD random_line(Gen& g, double s) {
  const Vec3<double> p0 = g.vec(s);
  return line(p0, near(g, p0, s), g.radius(s));
}

TriD random_tri(Gen& g, double s) {
  const Vec3<double> a = g.vec(s);
  const Vec3<double> b = near(g, a, s);
  Vec3<double> c;
  switch (g.integer(0, 6)) {
    case 0: c = a + g.uniform(-0.5, 1.5) * (b - a); break;  // collinear (needle or flat)
    case 1: c = a + g.uniform(-0.5, 1.5) * (b - a) + g.unit() * s * std::pow(10.0, -g.integer(4, 15)); break;  // needle
    case 2: c = b; break;
    default: c = g.vec(s);
  }
  return tri(a, b, c, g.radius(s));
}

/// Moves y so that its core touches x's core at a random point (core distance 0), or so that the
/// volumes overlap, depending on mode; keeps it unchanged otherwise.
template <typename X> X translate(X x, const Vec3<double>& t);
template <> PointD translate(PointD x, const Vec3<double>& t) { return {x.center + t, x.radius}; }
template <> LineD translate(LineD x, const Vec3<double>& t) { return {x.p0 + t, x.p1 + t, x.radius}; }
template <> TriD translate(TriD x, const Vec3<double>& t) { return {x.a + t, x.b + t, x.c + t, x.radius}; }

Vec3<double> some_point(Gen& g, const PointD& x) { (void)g; return x.center; }
Vec3<double> some_point(Gen& g, const LineD& x) { const double u = g.uniform(0, 1); return x.p0 + u * (x.p1 - x.p0); }
Vec3<double> some_point(Gen& g, const TriD& x) {
  double u = g.uniform(0, 1), w = g.uniform(0, 1);
  if (u + w > 1) u = 1 - u, w = 1 - w;
  return x.a + u * (x.b - x.a) + w * (x.c - x.a);
}

/// Cross-kind consistency: a point is a zero-length segment, a segment is a triangle with two
/// equal corners, so PL == LL, PT == LT == TT, LT == TT on those embeddings (to 1e-9 scale).
LineD as_line(const PointD& x) { return {x.center, x.center, x.radius}; }
TriD as_tri(const LineD& x) { return {x.p0, x.p1, x.p1, x.radius}; }
TriD as_tri(const PointD& x) { return {x.center, x.center, x.center, x.radius}; }

template <typename X> X to_float_rounded(const X& x);
template <> PointD to_float_rounded(const PointD& x) { return {x.center.cast<float>().cast<double>(), double(float(x.radius))}; }
template <> LineD to_float_rounded(const LineD& x) {
  return {x.p0.cast<float>().cast<double>(), x.p1.cast<float>().cast<double>(), double(float(x.radius))};
}
template <> TriD to_float_rounded(const TriD& x) {
  return {x.a.cast<float>().cast<double>(), x.b.cast<float>().cast<double>(), x.c.cast<float>().cast<double>(),
          double(float(x.radius))};
}
PointSsv<float> to_float(const PointD& x) { return {x.center.cast<float>(), float(x.radius)}; }
LineSsv<float> to_float(const LineD& x) { return {x.p0.cast<float>(), x.p1.cast<float>(), float(x.radius)}; }
TriangleSsv<float> to_float(const TriD& x) {
  return {x.a.cast<float>(), x.b.cast<float>(), x.c.cast<float>(), float(x.radius)};
}

/// Runs every check on one pair of double volumes (and their float twin every `float_every`).
template <typename X, typename Y>
void check_pair(Checker& chk, Checker& chk_float, const X& x, const Y& y, bool check_float) {
  const Core a = core_of(x), b = core_of(y);
  const SsvDistance<double> r = ssv_distance(x, y);
  check_result(chk, r, a, x.radius, b, y.radius, kDouble);
  if constexpr (std::is_same_v<X, Y>) {
    const SsvDistance<double> swapped = ssv_distance(y, x);
    check_result(chk, swapped, b, y.radius, a, x.radius, kDouble);
    check_swap(chk, r, swapped, scale_of(a, b), kDouble);
  }
  if (check_float) {
    const X xf = to_float_rounded(x);
    const Y yf = to_float_rounded(y);
    const SsvDistance<float> rf = ssv_distance(to_float(x), to_float(y));
    check_result(chk_float, rf, core_of(xf), xf.radius, core_of(yf), yf.radius, kFloat);
    if constexpr (std::is_same_v<X, Y>) {
      const SsvDistance<float> sf = ssv_distance(to_float(y), to_float(x));
      check_result(chk_float, sf, core_of(yf), yf.radius, core_of(xf), xf.radius, kFloat);
      check_swap(chk_float, rf, sf, scale_of(core_of(xf), core_of(yf)), kFloat);
    }
  }
}

/// Random pair generators: general position, touching (core distance 0), overlapping.
template <typename X, typename Y, typename MakeX, typename MakeY>
void run_random(const std::string& kind, unsigned seed, int n, MakeX make_x, MakeY make_y) {
  Checker chk{kind}, chk_float{kind + " float"};
  Gen g(seed);
  for (int i = 0; i < n; ++i) {
    const double s = g.scale();
    X x = make_x(g, s);
    Y y = make_y(g, s);
    const int mode = g.integer(0, 9);
    if (mode == 0) y = translate(y, some_point(g, x) - some_point(g, y));                  // touching cores
    else if (mode == 1) y = translate(y, some_point(g, x) - some_point(g, y) + g.vec(0.01 * s));  // overlap-ish
    else if (mode == 2) y = translate(y, g.vec(3 * s));                                     // far apart
    else if (mode == 3) y = translate(y, Vec3<double>::Constant(g.integer(0, 1) ? 1.0 : -1.0));  // offset 1 m
    check_pair(chk, chk_float, x, y, i % 4 == 0);
  }
  EXPECT_EQ(chk.failures, 0) << kind << ": " << chk.failures << " of " << chk.cases;
  EXPECT_EQ(chk_float.failures, 0) << kind << " float: " << chk_float.failures << " of " << chk_float.cases;
  std::printf("%s: %d double cases (worst |d - d_ref| %.2e scale, %d swap ties), %d float cases (worst %.2e scale, %d swap ties)\n",
              kind.c_str(), chk.cases, chk.worst_distance_error, chk.ties, chk_float.cases, chk_float.worst_distance_error,
              chk_float.ties);
}

auto make_point = [](Gen& g, double s) { return point(g.vec(s), g.radius(s)); };
auto make_line = [](Gen& g, double s) { return random_line(g, s); };
auto make_tri = [](Gen& g, double s) { return random_tri(g, s); };

TEST(SsvDistance, PointPointRandom) { run_random<PointD, PointD>("PP", 1, 12000, make_point, make_point); }
TEST(SsvDistance, PointLineRandom) { run_random<PointD, LineD>("PL", 2, 12000, make_point, make_line); }
TEST(SsvDistance, PointTriangleRandom) { run_random<PointD, TriD>("PT", 3, 12000, make_point, make_tri); }
TEST(SsvDistance, LineLineRandom) { run_random<LineD, LineD>("LL", 4, 15000, make_line, make_line); }
TEST(SsvDistance, LineTriangleRandom) { run_random<LineD, TriD>("LT", 5, 12000, make_line, make_tri); }
TEST(SsvDistance, TriangleTriangleRandom) { run_random<TriD, TriD>("TT", 6, 10000, make_tri, make_tri); }

/// Near-parallel segments: lengths 1 mm .. 1 m, angles 0 and 1e-12 .. 1e-2 rad, lateral offsets
/// from 0 (lines meeting) to the length, along-axis shifts from full overlap to disjoint.
TEST(SsvDistance, LineLineNearParallel) {
  Checker chk{"LL near-parallel"}, chk_float{"LL near-parallel float"};
  Gen g(7);
  const double lengths[] = {1e-3, 1e-2, 1e-1, 1.0};
  const double angles[] = {0, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2};
  for (double L : lengths)
    for (double angle : angles)
      for (int k = 0; k < 250; ++k) {
        const Vec3<double> u = g.unit(), w = g.perp(u);
        const Vec3<double> v = std::cos(angle) * u + std::sin(angle) * w;
        const double offsets[] = {0, 1e-12 * L, 1e-6 * L, 1e-3 * L, 0.1 * L, L};
        const Vec3<double> lateral = g.perp(u) * offsets[g.integer(0, 5)];
        const double shift = g.uniform(-1.5, 1.5) * L;
        const Vec3<double> p0 = g.vec(L);
        const double L2 = L * g.uniform(0.2, 1.5);
        const LineD x = line(p0, p0 + L * u, g.radius(L));
        const Vec3<double> q0 = p0 + lateral + shift * u;
        const LineD y = g.integer(0, 1) ? line(q0, q0 + L2 * v, g.radius(L)) : line(q0 + L2 * v, q0, g.radius(L));
        check_pair(chk, chk_float, x, y, k % 4 == 0);
      }
  EXPECT_EQ(chk.failures, 0);
  EXPECT_EQ(chk_float.failures, 0);
  std::printf("LL near-parallel: %d cases (worst %.2e scale, %d swap ties), float %d (worst %.2e scale, %d swap ties)\n",
              chk.cases, chk.worst_distance_error, chk.ties, chk_float.cases, chk_float.worst_distance_error, chk_float.ties);
}

/// Adversarial triangle cases: needle and point triangles, segments piercing, identical
/// primitives, segments and triangles in one plane.
TEST(SsvDistance, TriangleAdversarial) {
  Checker chk{"T adversarial"}, chk_float{"T adversarial float"};
  Gen g(8);
  for (int k = 0; k < 4000; ++k) {
    const double s = g.scale();
    const Vec3<double> a = g.vec(s), b = g.vec(s), c = g.vec(s);
    const Vec3<double> nrm = (b - a).cross(c - a).normalized();
    const TriD t = tri(a, b, c, g.radius(s));
    // A segment through a random interior point, at a random slant (piercing), and one lying
    // in the plane through it.
    double u = g.uniform(0, 1), w = g.uniform(0, 1);
    if (u + w > 1) u = 1 - u, w = 1 - w;
    const Vec3<double> x = a + u * (b - a) + w * (c - a);
    const Vec3<double> dir = (nrm + g.vec(1)).normalized();
    const double t0 = g.uniform(0, 1) * s;
    const LineD pierce = line(x - t0 * dir, x + g.uniform(0, 1) * s * dir, g.radius(s));
    const Vec3<double> in_plane = g.perp(nrm);
    const LineD coplanar = line(x - t0 * in_plane, x + s * in_plane, g.radius(s));
    check_pair(chk, chk_float, pierce, t, k % 4 == 0);
    check_pair(chk, chk_float, coplanar, t, k % 4 == 0);
    // Identical primitives and a triangle piercing another through an edge.
    check_pair(chk, chk_float, t, t, k % 4 == 0);
    check_pair(chk, chk_float, pierce, pierce, k % 4 == 0);
    check_pair(chk, chk_float, tri(pierce.p0, pierce.p1, pierce.p1 + g.vec(s), g.radius(s)), t, k % 4 == 0);
    // Needles (height down to 1e-12 of the length) and points against points and segments.
    const double h = s * std::pow(10.0, -g.integer(3, 12));
    const TriD needle = tri(a, b, a + g.uniform(-0.2, 1.2) * (b - a) + h * g.perp((b - a).normalized()), g.radius(s));
    const TriD pt = tri(a, a, a, g.radius(s));
    check_pair(chk, chk_float, point(g.vec(s), g.radius(s)), needle, k % 4 == 0);
    check_pair(chk, chk_float, random_line(g, s), needle, k % 4 == 0);
    check_pair(chk, chk_float, needle, t, k % 4 == 0);
    check_pair(chk, chk_float, point(g.vec(s), g.radius(s)), pt, k % 4 == 0);
    check_pair(chk, chk_float, pt, needle, k % 4 == 0);
    // A point far above a thin triangle, projecting inside it (the plane tilt rule).
    const Vec3<double> above = a + 0.5 * (needle.b - a) + 0.3 * (needle.c - needle.b) +
                               s * g.uniform(0.5, 3) * (needle.b - a).cross(needle.c - a).normalized();
    check_pair(chk, chk_float, point(above, 0.0), needle, k % 4 == 0);
  }
  EXPECT_EQ(chk.failures, 0);
  EXPECT_EQ(chk_float.failures, 0);
  std::printf("triangle adversarial: %d cases (worst %.2e scale), float %d (worst %.2e scale)\n", chk.cases,
              chk.worst_distance_error, chk_float.cases, chk_float.worst_distance_error);
}

/// Extreme scales: the same random cases scaled by 1e-70 .. 1e70 (double) and 1e-6 .. 1e8
/// (float), inside the documented range (fourth powers must not overflow), and cases mixing
/// magnitudes over that range, checked in full; at 1e-300 / 1e-200 (squared lengths underflow)
/// for finite results with unit normals only.
template <typename S, typename X, typename Y> void check_finite_scaled(Checker& chk, const X& x, const Y& y) {
  if constexpr (std::is_same_v<S, double>) {
    const SsvDistance<double> r = ssv_distance(x, y);
    if (!all_finite(r) || std::fabs(r.normal.norm() - 1) > kDouble.unit) chk.fail("non-finite or non-unit at tiny scale");
  } else {
    const SsvDistance<float> r = ssv_distance(to_float(x), to_float(y));
    if (!all_finite(r) || std::fabs(static_cast<double>(r.normal.norm()) - 1) > kFloat.unit)
      chk.fail("non-finite or non-unit at tiny scale");
  }
  ++chk.cases;
}

template <typename X> X scaled(X x, double f);
template <> PointD scaled(PointD x, double f) { return {x.center * f, x.radius * f}; }
template <> LineD scaled(LineD x, double f) { return {x.p0 * f, x.p1 * f, x.radius * f}; }
template <> TriD scaled(TriD x, double f) { return {x.a * f, x.b * f, x.c * f, x.radius * f}; }

TEST(SsvDistance, ExtremeScales) {
  Checker chk{"extreme scales"}, chk_float{"extreme scales float"};
  Gen g(11);
  for (int k = 0; k < 600; ++k) {
    const PointD p = point(g.vec(1), g.radius(1));
    const LineD l = random_line(g, 1), l2 = random_line(g, 1);
    const TriD t = random_tri(g, 1), t2 = random_tri(g, 1);
    for (double f : {1e-70, 1e-30, 1e30, 1e70}) {
      check_pair(chk, chk_float, scaled(p, f), scaled(l, f), false);
      check_pair(chk, chk_float, scaled(l, f), scaled(l2, f), false);
      check_pair(chk, chk_float, scaled(l, f), scaled(t, f), false);
      check_pair(chk, chk_float, scaled(t, f), scaled(t2, f), false);
    }
    for (double f : {1e-6, 1e-3, 1e3, 1e8}) {
      Checker unused{"unused"};
      check_pair(unused, chk_float, scaled(l, f), scaled(l2, f), true);
      check_pair(unused, chk_float, scaled(l, f), scaled(t, f), true);
      check_pair(unused, chk_float, scaled(t, f), scaled(t2, f), true);
    }
    for (double f : {1e-300, 1e-200}) {
      check_finite_scaled<double>(chk, scaled(l, f), scaled(l2, f));
      check_finite_scaled<double>(chk, scaled(l, f), scaled(t, f));
      check_finite_scaled<double>(chk, scaled(t, f), scaled(t2, f));
      check_finite_scaled<double>(chk, scaled(p, f), scaled(t, f));
    }
    for (double f : {1e-30, 1e-25}) {
      check_finite_scaled<float>(chk_float, scaled(l, f), scaled(l2, f));
      check_finite_scaled<float>(chk_float, scaled(l, f), scaled(t, f));
      check_finite_scaled<float>(chk_float, scaled(t, f), scaled(t2, f));
    }
  }
  // Mixed magnitudes within one case: every coordinate +-10^u, u uniform in [-70, 70] (double)
  // or [-6, 8] (float), checked in full (scale: the largest coordinate).
  auto wild = [&g](double lo, double hi) {
    Vec3<double> v;
    for (int i = 0; i < 3; ++i) v[i] = (g.integer(0, 1) ? 1 : -1) * std::pow(10.0, g.uniform(lo, hi));
    return v;
  };
  for (int k = 0; k < 500; ++k) {
    for (auto [lo, hi, with_float] : {std::tuple<double, double, bool>{-70, 70, false}, {-6, 8, true}}) {
      Checker& c = with_float ? chk_float : chk;
      Checker unused{"unused"};
      Checker& cd = with_float ? unused : chk;
      const LineD l = line(wild(lo, hi), wild(lo, hi), 0), l2 = line(wild(lo, hi), wild(lo, hi), 0);
      const TriD t = tri(wild(lo, hi), wild(lo, hi), wild(lo, hi), 0), t2 = tri(wild(lo, hi), wild(lo, hi), wild(lo, hi), 0);
      check_pair(cd, c, point(wild(lo, hi), 0), l, with_float);
      check_pair(cd, c, l, l2, with_float);
      check_pair(cd, c, l, t, with_float);
      check_pair(cd, c, t, t2, with_float);
    }
  }
  EXPECT_EQ(chk.failures, 0);
  EXPECT_EQ(chk_float.failures, 0);
  std::printf("extreme scales: %d double cases (worst %.2e scale), %d float (worst %.2e scale)\n", chk.cases,
              chk.worst_distance_error, chk_float.cases, chk_float.worst_distance_error);
}

/// No heap: every pair kind, double and float, on prepared inputs, under the malloc guard.
TEST(SsvDistance, NoAllocation) {
  Gen g(12);
  std::vector<PointD> points;
  std::vector<LineD> lines;
  std::vector<TriD> tris;
  for (int k = 0; k < 64; ++k) {
    points.push_back(point(g.vec(1), g.radius(1)));
    lines.push_back(random_line(g, 1));
    tris.push_back(random_tri(g, 1));
  }
  double sum = 0;
  float sum_f = 0;
  {
    test::MallocGuard guard;
    for (int k = 0; k < 64; ++k) {
      const int j = (k + 1) % 64;
      sum += ssv_distance(points[k], points[j]).distance + ssv_distance(points[k], lines[j]).distance +
             ssv_distance(points[k], tris[j]).distance + ssv_distance(lines[k], lines[j]).distance +
             ssv_distance(lines[k], tris[j]).distance + ssv_distance(tris[k], tris[j]).distance;
      sum_f += ssv_distance(to_float(lines[k]), to_float(lines[j])).distance +
               ssv_distance(to_float(tris[k]), to_float(tris[j])).distance +
               ssv_distance(to_float(points[k]), to_float(tris[j])).distance;
    }
    EXPECT_EQ(guard.count(), 0u);
  }
  EXPECT_TRUE(std::isfinite(sum) && std::isfinite(sum_f));
}

/// Hand-worked values and the documented fallback normals.
TEST(SsvDistance, WorkedExamplesAndFallbackNormals) {
  const Vec3<double> o = Vec3<double>::Zero(), ex = Vec3<double>::UnitX(), ey = Vec3<double>::UnitY(),
                     ez = Vec3<double>::UnitZ();
  // Two spheres 3 apart along y, radii 0.5 and 1: distance 1.5, normal +y, witness points.
  SsvDistance<double> r = ssv_distance(point(o, 0.5), point(3 * ey, 1.0));
  EXPECT_NEAR(r.distance, 1.5, 1e-15);
  EXPECT_LT((r.normal - ey).norm(), 1e-15);
  EXPECT_LT((r.point1 - 0.5 * ey).norm(), 1e-15);
  EXPECT_LT((r.point2 - 2 * ey).norm(), 1e-15);
  // Coincident spheres: +z, distance -r1 - r2.
  r = ssv_distance(point(ex, 0.1), point(ex, 0.2));
  EXPECT_EQ(r.normal, ez);
  EXPECT_NEAR(r.distance, -0.3, 1e-15);
  // Crossing segments x and y axes, 1 apart in z: normal +z; crossing in a point: x cross y.
  r = ssv_distance(line(-ex, ex, 0), line(-ey + ez, ey + ez, 0));
  EXPECT_NEAR(r.distance, 1, 1e-15);
  EXPECT_LT((r.normal - ez).norm(), 1e-15);
  r = ssv_distance(line(-ey, ey, 0), line(-ex, ex, 0));
  EXPECT_EQ(r.core_distance, 0);
  EXPECT_LT((r.normal + ez).norm(), 1e-15);  // ey x ex = -ez
  // Identical segments: parallel, so perpendicular to the segment.
  r = ssv_distance(line(o, ex, 0.1), line(o, ex, 0.1));
  EXPECT_EQ(r.core_distance, 0);
  EXPECT_NEAR(r.normal.dot(ex), 0, 1e-15);
  EXPECT_NEAR(r.normal.norm(), 1, 1e-15);
  // Zero-length segments: points.
  r = ssv_distance(line(ex, ex, 0), line(-ex, -ex, 0));
  EXPECT_NEAR(r.distance, 2, 1e-15);
  EXPECT_LT((r.normal + ex).norm(), 1e-15);
  // Point in the triangle x-y: the triangle normal +z; above it: its height.
  const TriD t = tri(o, ex, ey, 0);
  r = ssv_distance(point(Vec3<double>(0.25, 0.25, 0), 0.0), t);
  EXPECT_EQ(r.core_distance, 0);
  EXPECT_LT((r.normal - ez).norm(), 1e-15);
  r = ssv_distance(point(Vec3<double>(0.25, 0.25, 2), 0.5), t);
  EXPECT_NEAR(r.distance, 1.5, 1e-15);
  EXPECT_LT((r.normal + ez).norm(), 1e-15);
  // Segment piercing the triangle from z = 0.3 (shallow) to z = -1 (deep): the shorter way out is
  // to move the segment down by 0.3, i.e. -normal = -z, normal = +z (and the mirror case -z).
  r = ssv_distance(line(Vec3<double>(0.2, 0.2, 0.3), Vec3<double>(0.2, 0.2, -1), 0.1), t);
  EXPECT_EQ(r.core_distance, 0);
  EXPECT_LT((r.core1 - Vec3<double>(0.2, 0.2, 0)).norm(), 1e-15);
  EXPECT_LT((r.normal - ez).norm(), 1e-15);
  EXPECT_NEAR(r.distance, -0.1, 1e-15);
  r = ssv_distance(line(Vec3<double>(0.2, 0.2, -0.3), Vec3<double>(0.2, 0.2, 1), 0.1), t);
  EXPECT_LT((r.normal + ez).norm(), 1e-15);
  // Triangle through triangle: edge of triangle 1 through triangle 2, and the other way round.
  const TriD vertical = tri(Vec3<double>(0.2, 0.2, 0.3), Vec3<double>(0.2, 0.2, -1), Vec3<double>(0.2, 0.3, 0), 0);
  r = ssv_distance(vertical, t);
  EXPECT_EQ(r.core_distance, 0);
  EXPECT_LT((r.normal - ez).norm(), 1e-15);
  EXPECT_LT((ssv_distance(t, vertical).normal + ez).norm(), 1e-15);
  // Degenerate triangle (all corners equal) at distance 2 from a point.
  r = ssv_distance(point(2 * ez, 0), tri(o, o, o, 0));
  EXPECT_NEAR(r.distance, 2, 1e-15);
  EXPECT_LT((r.normal + ez).norm(), 1e-15);
  r = ssv_distance(point(o, 0), tri(o, o, o, 0));
  EXPECT_EQ(r.normal, ez);
}

/// PL == LL(zero-length, .), PT == LT(zero-length, .) == TT(point triangle, .), LT == TT(needle, .).
TEST(SsvDistance, CrossKindConsistency) {
  Gen g(9);
  int failures = 0;
  for (int k = 0; k < 3000; ++k) {
    const double s = g.scale();
    const PointD p = point(g.vec(s), g.radius(s));
    const LineD l = random_line(g, s);
    const TriD t = random_tri(g, s);
    const double tol = 1e-9 * std::max(scale_of(core_of(p), core_of(t)), scale_of(core_of(l), core_of(t)));
    const double pl = ssv_distance(p, l).distance, pt = ssv_distance(p, t).distance, lt = ssv_distance(l, t).distance;
    failures += std::fabs(pl - ssv_distance(as_line(p), l).distance) > tol;
    failures += std::fabs(pl - ssv_distance(l, as_line(p)).distance) > tol;
    failures += std::fabs(pt - ssv_distance(as_line(p), t).distance) > tol;
    failures += std::fabs(pt - ssv_distance(as_tri(p), t).distance) > tol;
    failures += std::fabs(pt - ssv_distance(t, as_tri(p)).distance) > tol;
    failures += std::fabs(lt - ssv_distance(as_tri(l), t).distance) > tol;
    failures += std::fabs(lt - ssv_distance(t, as_tri(l)).distance) > tol;
  }
  EXPECT_EQ(failures, 0);
}

/// Continuity across feature switches: a volume translated in steps of h changes the distance by
/// at most h (distance is 1-Lipschitz in a rigid translation) plus rounding (1e-12 scale).
/// `at(k)` is the distance after k steps of length h.
void sweep(const std::string& what, const std::function<double(int)>& at, int steps, double h, double scale) {
  double prev = at(0), worst = 0;
  for (int k = 1; k <= steps; ++k) {
    const double d = at(k);
    worst = std::max(worst, std::fabs(d - prev) - h);
    prev = d;
  }
  EXPECT_LE(worst, 1e-12 * scale) << what;
}

TEST(SsvDistance, ContinuityAcrossFeatureSwitches) {
  const Vec3<double> o = Vec3<double>::Zero(), ex = Vec3<double>::UnitX();
  const TriD t = tri(o, ex, Vec3<double>::UnitY(), 0.05);
  const int n = 20000;
  const double h = 3.0 / n;
  // Segment above the triangle's plane slid along x past the edge x + y = 1 and the corner (1, 0).
  const LineD above{Vec3<double>(-1, 0.3, 0.1), Vec3<double>(-1, 0.6, 0.5), 0.02};
  sweep("LT past an edge", [&](int k) { return ssv_distance(translate(above, k * h * ex), t).distance; }, n, h, 2);
  // Slanted segment through the triangle (piercing), in and out across edges.
  const LineD through{Vec3<double>(-1, 0.2, -0.5), Vec3<double>(-0.9, 0.25, 0.5), 0.02};
  sweep("LT piercing", [&](int k) { return ssv_distance(translate(through, k * h * ex), t).distance; }, n, h, 2);
  // Segment past a segment endpoint: nearly parallel (1e-9 rad) and crossing.
  const LineD base{o, ex, 0.01};
  const LineD parallel{Vec3<double>(-2, 0, 1e-3), Vec3<double>(-1, 1e-9, 1e-3), 0.01};
  sweep("LL past an endpoint, near-parallel",
        [&](int k) { return ssv_distance(base, translate(parallel, k * h * ex)).distance; }, n, h, 2);
  const LineD crossing{Vec3<double>(-1, -0.5, 1e-3), Vec3<double>(-1, 0.5, 1e-3), 0.01};
  sweep("LL past an endpoint, crossing",
        [&](int k) { return ssv_distance(base, translate(crossing, k * h * ex)).distance; }, n, h, 2);
  // Point past the triangle's corner and edges; triangle past and through a triangle.
  const PointD p{Vec3<double>(-1, -0.2, 0.3), 0};
  sweep("PT past a corner", [&](int k) { return ssv_distance(translate(p, k * h * ex), t).distance; }, n, h, 2);
  const TriD t2{Vec3<double>(-1.5, 0.2, 0.2), Vec3<double>(-1, 0.2, 0.1), Vec3<double>(-1, 0.5, 0.4), 0};
  sweep("TT past an edge", [&](int k) { return ssv_distance(translate(t2, k * h * ex), t).distance; }, n, h, 2);
  const TriD t3{Vec3<double>(-1.5, 0.2, -0.2), Vec3<double>(-1, 0.2, 0.1), Vec3<double>(-1, 0.5, 0.4), 0};
  sweep("TT through", [&](int k) { return ssv_distance(translate(t3, k * h * ex), t).distance; }, n, h, 2);
  // A segment rotating about z through parallel (-1e-3 .. 1e-3 rad) 1e-4 above another one:
  // its endpoints move by at most the angle step times its length (1).
  const double da = 2e-3 / n;
  sweep("LL rotating through parallel",
        [&](int k) {
          const double a = -1e-3 + da * k;
          return ssv_distance(base, LineD{Vec3<double>(0.5, 0, 1e-4), Vec3<double>(0.5 + std::cos(a), std::sin(a), 1e-4), 0})
              .distance;
        },
        n, 1.5 * da, 2);
}

/// The reference is checked against dense sampling of both cores (21 x 21 parameters each):
/// the sampled minimum is never below the reference (it would be missing a minimum), and not far
/// above it (the sampling resolution).
TEST(SsvReference, NotAboveDenseSampling) {
  Gen g(10);
  for (int k = 0; k < 60; ++k) {
    const TriD x = random_tri(g, 1), y = random_tri(g, 1);
    const LineD l = random_line(g, 1);
    for (const auto& [a, b] : {std::pair<Core, Core>{core_of(x), core_of(y)}, {core_of(l), core_of(y)}}) {
      const LD ref = reference_distance(a, b);
      const int m = 20;
      LD sampled = std::numeric_limits<LD>::infinity();
      std::vector<V3> pa, pb;
      for (int i = 0; i <= m; ++i)
        for (int j = 0; j <= m; ++j) {
          pa.push_back(core_point(a, LD(i) / m, LD(j) / m));
          pb.push_back(core_point(b, LD(i) / m, LD(j) / m));
        }
      for (const V3& p : pa)
        for (const V3& q : pb) sampled = std::min(sampled, (p - q).norm());
      EXPECT_GE(sampled, ref - 1e-15L);
      EXPECT_LE(sampled, ref + 0.2L);  // grid spacing: cores of size <= 3.5 sampled at 1/20
    }
  }
}

}  // namespace
}  // namespace mbgen::collision
