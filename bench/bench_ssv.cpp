// mbgen_bench: SSV pair distances (runtime/include/mbgen/collision/), named
// `ssv_<pair>/<case>/<implementation>` (bench/README.md).
//
//   pairs            pp (sphere-sphere), pl (sphere-capsule), pt, ll (capsule-capsule), lt, tt
//   cases            random: cores in a 1 m box, radii up to 5 cm, pairs whose volumes are apart
//                    (FCL's distance answers contacts by another path);
//                    near_parallel (ll only): 1 m segments at 1e-12 .. 1e-2 rad, 1 mm .. 1 cm apart
//   implementations  generic (mbgen's ssv_distance<double>: distance, witness points, normal),
//                    fcl (FCL 0.7, pp, pl and ll only),
//                    fcl_distance (ll/random only: the fcl::distance route below, for reference)
//
// FCL route: fcl::detail::GJKSolver_libccd<double>::shapeDistance(shape1, X1, shape2, X2, &d,
// &p1, &p2), with the shapes and poses built beforehand (a capsule's pose from its segment: not
// timed). For these shape pairs it dispatches at compile time to FCL's closed forms
// (sphereSphereDistance, sphereCapsuleDistance, capsuleCapsuleDistance), so it is the cheapest
// route a fair user has. fcl::distance(o1, o2, request, result) on preallocated
// CollisionObjects whose transforms are set per sample reaches the same functions through the
// distance dispatch table and DistanceResult bookkeeping and is 2-3x slower; it is kept as
// `ssv_ll/random/fcl_distance` because it is the call most FCL users write. All
// implementations return witness points (fcl_distance: enable_nearest_points).
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/detail/gjk_solver_libccd.h>
#include <fcl/narrowphase/distance.h>

#include "bench_support.hpp"
#include "mbgen/collision/ssv_distance.hpp"
#include "mbgen/spatial/types.hpp"  // Eigen vectors: the benchmarks build SSVs from them (SsvVec3 converts)

namespace mbgen::bench {
namespace {

using collision::LineSsv;
using collision::PointSsv;
using collision::SsvDistance;
using collision::TriangleSsv;
using V = Vec3<double>;

template <typename X, typename Y> struct SsvPair {
  X x;
  Y y;
};

/// One input of the FCL benchmarks: the two shapes and their poses.
template <typename Shape1, typename Shape2> struct FclPair {
  Shape1 s1;
  fcl::Transform3d X1;
  Shape2 s2;
  fcl::Transform3d X2;
};

fcl::Transform3d sphere_pose(const V& c) {
  fcl::Transform3d X = fcl::Transform3d::Identity();
  X.translation() = c;
  return X;
}

/// FCL's capsule is centred at its origin along z with length lz: the pose from a segment.
fcl::Transform3d capsule_pose(const V& p0, const V& p1) {
  fcl::Transform3d X = fcl::Transform3d::Identity();
  X.translation() = (p0 + p1) / 2;
  const V d = p1 - p0;
  if (d.norm() > 0) {
    const V z = d.normalized();
    const V x = (std::fabs(z.x()) < 0.6 ? V::UnitX() : V::UnitY()).cross(z).normalized();
    X.linear().col(0) = x;
    X.linear().col(1) = z.cross(x);
    X.linear().col(2) = z;
  }
  return X;
}

fcl::Sphered fcl_shape(const PointSsv<double>& x) { return fcl::Sphered(x.radius); }
fcl::Capsuled fcl_shape(const LineSsv<double>& x) { return fcl::Capsuled(x.radius, (x.p1 - x.p0).norm()); }
fcl::Transform3d fcl_pose(const PointSsv<double>& x) { return sphere_pose(x.center); }
fcl::Transform3d fcl_pose(const LineSsv<double>& x) { return capsule_pose(x.p0, x.p1); }

struct Gen {
  std::mt19937_64 rng{2024};
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  V vec(double s) { return {uniform(-s, s), uniform(-s, s), uniform(-s, s)}; }
  double radius() { return uniform(0, 0.05); }
  PointSsv<double> point() { return {vec(0.5), radius()}; }
  LineSsv<double> line() { return {vec(0.5), vec(0.5), radius()}; }
  TriangleSsv<double> tri() { return {vec(0.5), vec(0.5), vec(0.5), radius()}; }
};

/// kPoolSize random pairs whose volumes are apart.
template <typename X, typename Y, typename MakeX, typename MakeY>
std::shared_ptr<const std::vector<SsvPair<X, Y>>> random_pool(MakeX make_x, MakeY make_y) {
  Gen g;
  auto pool = std::make_shared<std::vector<SsvPair<X, Y>>>();
  while (pool->size() < kPoolSize) {
    SsvPair<X, Y> p{make_x(g), make_y(g)};
    if (collision::ssv_distance(p.x, p.y).distance > 0) pool->push_back(p);
  }
  return pool;
}

/// Near-parallel 1 m segments: angles 1e-12 .. 1e-2 rad (cycled), lines 1 mm .. 1 cm apart,
/// the second one shifted along the first by up to half a length.
std::shared_ptr<const std::vector<SsvPair<LineSsv<double>, LineSsv<double>>>> near_parallel_pool() {
  Gen g;
  auto pool = std::make_shared<std::vector<SsvPair<LineSsv<double>, LineSsv<double>>>>();
  const double angles[] = {1e-12, 1e-10, 1e-8, 1e-6, 1e-4, 1e-2, 0.0, 1e-9};
  for (std::size_t k = 0; k < kPoolSize; ++k) {
    const V u = g.vec(1).normalized();
    const V w = u.cross(g.vec(1)).normalized();
    const double angle = angles[k % 8];
    const V v = std::cos(angle) * u + std::sin(angle) * w;
    const V p0 = g.vec(0.5);
    const V q0 = p0 + g.uniform(-0.5, 0.5) * u + g.uniform(1e-3, 1e-2) * u.cross(w);
    pool->push_back({{p0, p0 + u, 1e-4}, {q0, q0 + v, 1e-4}});
  }
  return pool;
}

template <typename X, typename Y>
std::shared_ptr<const std::vector<FclPair<decltype(fcl_shape(X{})), decltype(fcl_shape(Y{}))>>> to_fcl(
    const std::vector<SsvPair<X, Y>>& pool) {
  using P = FclPair<decltype(fcl_shape(X{})), decltype(fcl_shape(Y{}))>;
  auto out = std::make_shared<std::vector<P>>();
  for (const auto& p : pool) out->push_back(P{fcl_shape(p.x), fcl_pose(p.x), fcl_shape(p.y), fcl_pose(p.y)});
  return out;
}

template <typename X, typename Y>
void add_generic(const std::string& pair, const std::string& name, std::shared_ptr<const std::vector<SsvPair<X, Y>>> pool) {
  // The result stays where the call returns it (a local, kept in memory by DoNotOptimize), as
  // FCL's rows write theirs straight into their output through pointers. Assigning it to a
  // persistent output instead copies the 136-byte SsvDistance once more, with store-forwarding
  // stalls (wide loads of the just-written narrow stores): ~3-4 ns per call that FCL's rows do
  // not pay.
  add_benchmark(pair, name, "generic", pool, [](const SsvPair<X, Y>& p) {
    SsvDistance<double> out = collision::ssv_distance(p.x, p.y);
    benchmark::DoNotOptimize(out);
    return static_cast<const void*>(nullptr);  // the output is already kept
  });
}

template <typename X, typename Y>
void add_fcl(const std::string& pair, const std::string& name, const std::shared_ptr<const std::vector<SsvPair<X, Y>>>& pool) {
  using P = FclPair<decltype(fcl_shape(X{})), decltype(fcl_shape(Y{}))>;
  struct Out {
    double d;
    fcl::Vector3d p1, p2;
  };
  // The same geometry: FCL and mbgen agree on every sample (to 1e-6: FCL is inexact near parallel,
  // tests/test_ssv_peer_fcl.cpp), else the registration fails loudly.
  const auto inputs = to_fcl(*pool);
  const fcl::detail::GJKSolver_libccd<double> check;
  for (std::size_t k = 0; k < kPoolSize; ++k) {
    double d = 0;
    fcl::Vector3d p1, p2;  // capsuleCapsuleDistance asserts that they are given
    const P& p = (*inputs)[k];
    check.shapeDistance(p.s1, p.X1, p.s2, p.X2, &d, &p1, &p2);
    if (std::fabs(d - collision::ssv_distance((*pool)[k].x, (*pool)[k].y).distance) > 1e-6)
      throw std::logic_error(pair + "/" + name + ": FCL and mbgen disagree on sample " + std::to_string(k));
  }
  add_benchmark(pair, name, "fcl", inputs,
                [solver = fcl::detail::GJKSolver_libccd<double>(), out = Out{0, fcl::Vector3d::Zero(), fcl::Vector3d::Zero()}](
                    const P& p) mutable {
                  solver.shapeDistance(p.s1, p.X1, p.s2, p.X2, &out.d, &out.p1, &out.p2);
                  return &out;
                });
}

/// fcl::distance on two preallocated CollisionObjects whose transforms are set per sample.
void add_fcl_distance(const std::string& pair, const std::string& name,
                      const std::shared_ptr<const std::vector<SsvPair<LineSsv<double>, LineSsv<double>>>>& pool) {
  using P = FclPair<fcl::Capsuled, fcl::Capsuled>;
  struct Work {
    std::vector<std::shared_ptr<fcl::Capsuled>> shapes1, shapes2;  // per sample (lengths differ)
    std::vector<fcl::CollisionObjectd> objects1, objects2;
    fcl::DistanceRequestd request;
    fcl::DistanceResultd result;
  };
  const auto inputs = to_fcl(*pool);
  auto work = std::make_shared<Work>();
  work->request.enable_nearest_points = true;
  for (const P& p : *inputs) {
    work->shapes1.push_back(std::make_shared<fcl::Capsuled>(p.s1));
    work->shapes2.push_back(std::make_shared<fcl::Capsuled>(p.s2));
    work->objects1.emplace_back(work->shapes1.back());
    work->objects2.emplace_back(work->shapes2.back());
  }
  // Sample k (its index in the pool) uses the k-th preallocated pair of objects, whose shapes
  // match it; only the transforms are set in the loop.
  add_benchmark(pair, name, "fcl_distance", inputs, [work, first = inputs->data()](const P& p) {
    const std::size_t k = static_cast<std::size_t>(&p - first);
    work->objects1[k].setTransform(p.X1);
    work->objects2[k].setTransform(p.X2);
    work->result.clear();
    fcl::distance(&work->objects1[k], &work->objects2[k], work->request, work->result);
    return &work->result.min_distance;
  });
}

/// Registered at static initialisation, as BENCHMARK() does, so that main (bench_dynamics.cpp)
/// need not know this file; the pools are owned by the registered callables.
const bool registered = [] {
  auto make_point = [](Gen& g) { return g.point(); };
  auto make_line = [](Gen& g) { return g.line(); };
  auto make_tri = [](Gen& g) { return g.tri(); };
  const auto pp = random_pool<PointSsv<double>, PointSsv<double>>(make_point, make_point);
  const auto pl = random_pool<PointSsv<double>, LineSsv<double>>(make_point, make_line);
  const auto ll = random_pool<LineSsv<double>, LineSsv<double>>(make_line, make_line);
  const auto ll_parallel = near_parallel_pool();
  add_generic("ssv_pp", "random", pp);
  add_fcl("ssv_pp", "random", pp);
  add_generic("ssv_pl", "random", pl);
  add_fcl("ssv_pl", "random", pl);
  add_generic("ssv_ll", "random", ll);
  add_fcl("ssv_ll", "random", ll);
  add_fcl_distance("ssv_ll", "random", ll);
  add_generic("ssv_ll", "near_parallel", ll_parallel);
  add_fcl("ssv_ll", "near_parallel", ll_parallel);
  add_generic("ssv_pt", "random", random_pool<PointSsv<double>, TriangleSsv<double>>(make_point, make_tri));
  add_generic("ssv_lt", "random", random_pool<LineSsv<double>, TriangleSsv<double>>(make_line, make_tri));
  add_generic("ssv_tt", "random", random_pool<TriangleSsv<double>, TriangleSsv<double>>(make_tri, make_tri));
  return true;
}();

}  // namespace
}  // namespace mbgen::bench
