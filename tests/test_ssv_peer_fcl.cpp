// SSV distances against FCL 0.7 (Debian libfcl-dev), the collision library most robot stacks
// use: sphere-sphere, sphere-capsule, capsule-capsule through fcl::distance on CollisionObjects,
// on seeded random non-overlapping cases. mbgen's own accuracy is established against the
// long-double reference in test_ssv_distance.cpp; here FCL is the peer.
//
// FCL's Capsule is centred at its frame's origin along z with length lz (the segment length):
// a segment p0-p1 becomes the transform translation (p0 + p1) / 2, rotation taking z to
// (p1 - p0) / |p1 - p0| (identity for a zero-length segment).
//
// Tolerance: 1e-12 scale (scale: largest coordinate magnitude, >= 1e-3). Measured agreement on
// random cases is ~1e-15 scale for all three pairs.
// FCL 0.7's capsule-capsule (detail::closestPtSegmentSegment, Ericson's closed form) is NOT
// exact near parallel: it forms a e - b^2 (cancellation: the squared sine of the angle is known
// only to ~eps absolute) and compares it with a fixed absolute threshold (eps^(7/8))^2 ~ 4.6e-28
// that does not scale with the segment lengths. Below ~1e-7 rad its s is then rounding noise and
// the returned pair slides along the valley of the near-parallel pair, whose slope is the angle:
// the distance is off by up to ~length * angle. CapsuleCapsuleNearParallel measures this against
// a long-double reference (worst 1e-8 scale at 1e-8 rad, i.e. wrong in the 8th digit; exact at
// 1e-2 rad), checks that bound, and keeps mbgen at 1e-12 scale there; the exact comparison with
// FCL is restricted to random directions, where such angles do not occur.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <random>

#include <Eigen/QR>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/distance.h>

#include "mbgen/collision/ssv_distance.hpp"
#include "mbgen/spatial/types.hpp"  // Eigen vectors: the tests build SSVs from them (SsvVec3 converts)

namespace mbgen::collision {
namespace {

using V = Vec3<double>;
using LD = long double;

fcl::Transform3d capsule_pose(const V& p0, const V& p1) {
  fcl::Transform3d X = fcl::Transform3d::Identity();
  X.translation() = (p0 + p1) / 2;
  const V d = p1 - p0;
  if (d.norm() > 0) {
    // Columns x, y, z = an orthonormal frame with z along the segment (not
    // Quaterniond::FromTwoVectors, which loses accuracy for directions near -z).
    const V z = d.normalized();
    const V x = (std::fabs(z.x()) < 0.6 ? V::UnitX() : V::UnitY()).cross(z).normalized();
    X.linear().col(0) = x;
    X.linear().col(1) = z.cross(x);
    X.linear().col(2) = z;
  }
  return X;
}

/// fcl::distance between two shapes at two poses (min_distance; -1 when FCL reports contact).
double fcl_distance(const std::shared_ptr<fcl::CollisionGeometryd>& g1, const fcl::Transform3d& X1,
                    const std::shared_ptr<fcl::CollisionGeometryd>& g2, const fcl::Transform3d& X2) {
  fcl::CollisionObjectd o1(g1, X1), o2(g2, X2);
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  fcl::distance(&o1, &o2, request, result);
  return result.min_distance;
}

double fcl_distance(const PointSsv<double>& a, const PointSsv<double>& b) {
  fcl::Transform3d X1 = fcl::Transform3d::Identity(), X2 = fcl::Transform3d::Identity();
  X1.translation() = Vec3<double>(a.center.x(), a.center.y(), a.center.z());
  X2.translation() = Vec3<double>(b.center.x(), b.center.y(), b.center.z());
  return fcl_distance(std::make_shared<fcl::Sphered>(a.radius), X1, std::make_shared<fcl::Sphered>(b.radius), X2);
}
double fcl_distance(const PointSsv<double>& a, const LineSsv<double>& b) {
  fcl::Transform3d X1 = fcl::Transform3d::Identity();
  X1.translation() = Vec3<double>(a.center.x(), a.center.y(), a.center.z());
  return fcl_distance(std::make_shared<fcl::Sphered>(a.radius), X1,
                      std::make_shared<fcl::Capsuled>(b.radius, (b.p1 - b.p0).norm()), capsule_pose(b.p0, b.p1));
}
double fcl_distance(const LineSsv<double>& a, const LineSsv<double>& b) {
  return fcl_distance(std::make_shared<fcl::Capsuled>(a.radius, (a.p1 - a.p0).norm()), capsule_pose(a.p0, a.p1),
                      std::make_shared<fcl::Capsuled>(b.radius, (b.p1 - b.p0).norm()), capsule_pose(b.p0, b.p1));
}

/// Long-double reference for segment-segment (the same face-pair enumeration as
/// test_ssv_distance.cpp, specialised to two segments): the four endpoint-segment distances and
/// the interior stationary point when it is inside, solved by QR.
LD reference_segments(const LineSsv<double>& a, const LineSsv<double>& b) {
  using VL = Eigen::Matrix<LD, 3, 1>;
  const VL p0 = a.p0.cast<LD>(), p1 = a.p1.cast<LD>(), q0 = b.p0.cast<LD>(), q1 = b.p1.cast<LD>();
  auto point_segment = [](const VL& p, const VL& x, const VL& y) {
    const VL d = y - x;
    const LD dd = d.squaredNorm();
    LD t = dd > 0 ? (p - x).dot(d) / dd : 0;
    t = std::min<LD>(1, std::max<LD>(0, t));
    return (p - x - t * d).norm();
  };
  LD best = std::min({point_segment(p0, q0, q1), point_segment(p1, q0, q1), point_segment(q0, p0, p1),
                      point_segment(q1, p0, p1)});
  Eigen::Matrix<LD, 3, 2> J;
  J.col(0) = p1 - p0;
  J.col(1) = -(q1 - q0);
  Eigen::ColPivHouseholderQR<Eigen::Matrix<LD, 3, 2>> qr(J);
  qr.setThreshold(1e-30L);
  if (qr.rank() == 2) {
    const Eigen::Matrix<LD, 2, 1> x = qr.solve(VL(q0 - p0));
    if (x(0) >= 0 && x(0) <= 1 && x(1) >= 0 && x(1) <= 1) best = std::min(best, (p0 + x(0) * J.col(0) + x(1) * J.col(1) - q0).norm());
  }
  return best;
}

struct Gen {
  std::mt19937_64 rng;
  explicit Gen(unsigned seed) : rng(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  V vec(double s) { return {uniform(-s, s), uniform(-s, s), uniform(-s, s)}; }
  double scale() {
    static const double scales[] = {1e-3, 1e-2, 1e-1, 1.0};
    return scales[std::uniform_int_distribution<int>(0, 3)(rng)];
  }
};

double scale_of(std::initializer_list<V> points) {
  double m = 1e-3;
  for (const V& p : points) m = std::max(m, p.cwiseAbs().maxCoeff());
  return m;
}

constexpr double kTol = 1e-12;
constexpr int kCases = 3000;

TEST(SsvPeerFcl, SphereSphere) {
  Gen g(21);
  int compared = 0;
  double worst = 0;
  for (int k = 0; k < kCases; ++k) {
    const double s = g.scale();
    const PointSsv<double> a{g.vec(s), g.uniform(0, 0.3 * s)}, b{g.vec(s), g.uniform(0, 0.3 * s)};
    const double d = ssv_distance(a, b).distance;
    if (d <= 0) continue;  // FCL's distance() answers -1 for contact
    const double err = std::fabs(d - fcl_distance(a, b)) / scale_of({a.center, b.center});
    worst = std::max(worst, err);
    EXPECT_LE(err, kTol) << k;
    ++compared;
  }
  EXPECT_GT(compared, kCases / 2);
  std::printf("sphere-sphere: %d cases, worst |d - d_fcl| %.2e scale\n", compared, worst);
}

TEST(SsvPeerFcl, SphereCapsule) {
  Gen g(22);
  int compared = 0;
  double worst = 0;
  for (int k = 0; k < kCases; ++k) {
    const double s = g.scale();
    const V p0 = g.vec(s);
    const PointSsv<double> a{g.vec(s), g.uniform(0, 0.2 * s)};
    const LineSsv<double> b{p0, k % 10 == 0 ? p0 : g.vec(s), g.uniform(0, 0.2 * s)};
    const double d = ssv_distance(a, b).distance;
    if (d <= 0) continue;
    const double err = std::fabs(d - fcl_distance(a, b)) / scale_of({a.center, b.p0, b.p1});
    worst = std::max(worst, err);
    EXPECT_LE(err, kTol) << k << " d " << d << " length " << (b.p1 - b.p0).norm() << " scale " << s;
    ++compared;
  }
  EXPECT_GT(compared, kCases / 2);
  std::printf("sphere-capsule: %d cases, worst |d - d_fcl| %.2e scale\n", compared, worst);
}

TEST(SsvPeerFcl, CapsuleCapsuleRandomDirections) {
  Gen g(23);
  int compared = 0;
  double worst = 0;
  for (int k = 0; k < kCases; ++k) {
    const double s = g.scale();
    const V p0 = g.vec(s), q0 = g.vec(s);
    const LineSsv<double> a{p0, k % 10 == 0 ? p0 : g.vec(s), g.uniform(0, 0.2 * s)};
    const LineSsv<double> b{q0, k % 10 == 5 ? q0 : g.vec(s), g.uniform(0, 0.2 * s)};
    const double d = ssv_distance(a, b).distance;
    if (d <= 0) continue;
    const double err = std::fabs(d - fcl_distance(a, b)) / scale_of({a.p0, a.p1, b.p0, b.p1});
    worst = std::max(worst, err);
    EXPECT_LE(err, kTol) << k;
    ++compared;
  }
  EXPECT_GT(compared, kCases / 3);
  std::printf("capsule-capsule, random directions: %d cases, worst |d - d_fcl| %.2e scale\n", compared, worst);
}

/// Near-parallel capsules (lengths 1 mm .. 1 m, angles 1e-12 .. 1e-2 rad, the second segment
/// centred near the first one's middle, the lines 0 or 1e-15 .. 1e-3 length apart, radii 0: the
/// distance of the cores, where FCL's error is not hidden behind a radius), against the
/// long-double reference. mbgen must stay within 1e-12 scale everywhere. FCL's error per angle is
/// printed; it is bounded by ~length * angle (the pair slides along the valley of a near-parallel
/// pair, whose slope is the angle), which is checked (2 angle scale + 1e-12 scale), and FCL must be
/// exact (1e-12 scale) at 1e-2 rad. Measured (seed 24, 400 cases per angle): FCL off by more than
/// 1e-9 scale in ~65 % of the cases at 1e-8 rad (worst 1e-8 scale), worst 1e-10 scale at
/// 1e-10 rad, 4e-10 at 1e-6 rad, 4e-12 at 1e-4 rad, 3e-14 at 1e-2 rad; mbgen ~1e-15 throughout.
TEST(SsvPeerFcl, CapsuleCapsuleNearParallel) {
  Gen g(24);
  const double angles[] = {1e-12, 1e-10, 1e-8, 1e-6, 1e-4, 1e-2};
  std::map<double, int> fcl_off;
  std::map<double, double> fcl_worst, mbgen_worst;
  int per_angle = 0;
  for (double angle : angles) {
    per_angle = 0;
    for (double L : {1e-3, 1e-2, 1e-1, 1.0})
      for (int k = 0; k < 100; ++k, ++per_angle) {
        V u = g.vec(1).normalized();
        V w = u.cross(g.vec(1)).normalized();
        const V p0 = g.vec(L);
        const LineSsv<double> a{p0, p0 + L * u, 0};
        const double gap = k % 4 == 0 ? 0.0 : L * std::pow(10.0, g.uniform(-15, -3));
        const V q0 = p0 + g.uniform(0.3, 0.7) * L * u + gap * u.cross(w);
        const V v = std::cos(angle) * u + std::sin(angle) * w;
        const LineSsv<double> b{q0 - 0.5 * L * v, q0 + 0.5 * L * v, 0};
        const double ref = static_cast<double>(reference_segments(a, b));
        const double scale = scale_of({a.p0, a.p1, b.p0, b.p1});
        const double mbgen_err = std::fabs(ssv_distance(a, b).distance - ref) / scale;
        mbgen_worst[angle] = std::max(mbgen_worst[angle], mbgen_err);
        EXPECT_LE(mbgen_err, kTol);
        // Through fcl::distance the capsule ends are rebuilt from a pose (rounding ~eps scale).
        const double err = std::fabs(fcl_distance(a, b) - ref) / scale;
        fcl_worst[angle] = std::max(fcl_worst[angle], err);
        fcl_off[angle] += err > 1e-9;
        EXPECT_LE(err, 2 * angle + kTol) << "FCL beyond its length * angle error bound";
      }
  }
  for (double angle : angles)
    std::printf("capsule-capsule near-parallel, %.0e rad: FCL off by > 1e-9 scale in %3d of %d (worst %.1e scale), "
                "mbgen worst %.1e scale\n",
                angle, fcl_off[angle], per_angle, fcl_worst[angle], mbgen_worst[angle]);
  EXPECT_LE(fcl_worst[1e-2], kTol);
}

}  // namespace
}  // namespace mbgen::collision
