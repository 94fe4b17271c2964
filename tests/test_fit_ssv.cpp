// SSV compounds fitted to meshes (generator/mesh/fit_ssv.cpp): enclosure of the whole surface,
// size against the convex hull, the budget, closed forms, determinism, bad input.
#include "mesh/fit_ssv.hpp"

#include <gtest/gtest.h>

#include <random>

#include "mbgen/collision/ssv_distance.hpp"
#include "mesh/convex_hull.hpp"
#include "mesh_shapes.hpp"

namespace {

using mbgen::Vec3;
using namespace mbgen::mesh;
using mbgen::test::surface_samples;

/// Distance from p to the compound through the runtime's SSV distance (a radius-0 point-SSV
/// against each primitive): the code the generated self-distances use, not the fitter's.
double runtime_distance(const Vec3<double>& p, const std::vector<FittedPrimitive>& compound) {
  namespace c = mbgen::collision;
  double best = 1e300;
  const c::PointSsv<double> point{p, 0.0};
  for (const FittedPrimitive& f : compound) {
    const auto& q = f.points;
    double d = q.size() == 1   ? c::ssv_distance(point, c::PointSsv<double>{q[0], f.radius}).distance
               : q.size() == 2 ? c::ssv_distance(point, c::LineSsv<double>{q[0], q[1], f.radius}).distance
                               : c::ssv_distance(point, c::TriangleSsv<double>{q[0], q[1], q[2], f.radius}).distance;
    best = std::min(best, d);
  }
  return best;
}

struct Shape {
  const char* name;
  TriangleMesh mesh;
  double factor;  ///< the compound's volume (budget 4) may be at most this times the convex hull's
};

std::vector<Shape> shapes() {
  return {{"box", box_mesh(Vec3<double>(0.3, 0.1, 0.05)), 1.35},
          {"cylinder", mbgen::test::cylinder_mesh(0.04, 0.3, 32), 1.2},
          {"l_shape", mbgen::test::l_shape(), 1.4},
          {"thin_plate", box_mesh(Vec3<double>(0.2, 0.15, 0.004)), 1.06},
          {"sphere", mbgen::test::sphere_mesh(0.1, 12, 24), 1.05}};
}

// Every vertex and 20,000 random surface points of each shape lie inside the compound, for
// every budget; the runtime's distance agrees (nothing further out than -0 m).
TEST(FitSsv, EnclosesTheWholeSurfaceOfEachShapeForEveryBudget) {
  for (const Shape& s : shapes())
    for (int budget = 1; budget <= 6; ++budget) {
      FitOptions options;
      options.budget = budget;
      const FittedCompound c = fit_ssv_compound(s.mesh, options);
      EXPECT_LE(static_cast<int>(c.primitives.size()), budget) << s.name;
      EXPECT_LE(c.report.largest_outside, 0.0) << s.name;
      double worst = -1e300;
      for (const auto& v : s.mesh.vertices) worst = std::max(worst, runtime_distance(v, c.primitives));
      for (const auto& p : surface_samples(s.mesh, 20000, 7 + budget)) worst = std::max(worst, runtime_distance(p, c.primitives));
      EXPECT_LE(worst, 0.0) << s.name << " budget " << budget;
    }
}

// The stated factors: the fitted compound's swept volume (budget 4) against the convex hull.
// The hull volume is checked against the closed form where there is one.
TEST(FitSsv, VolumeWithinAStatedFactorOfTheConvexHull) {
  for (const Shape& s : shapes()) {
    const FittedCompound c = fit_ssv_compound(s.mesh);
    const double ratio = c.report.volume / c.report.hull_volume;
    EXPECT_LE(ratio, s.factor) << s.name;
    // A convex mesh's compound cannot be smaller than its hull; the L's (not convex) may be.
    if (std::string(s.name) != "l_shape") {
      EXPECT_GE(ratio, 1.0) << s.name;
    }
    std::printf("  %-10s %d primitives, volume %.4g L = %.3f x hull, gap %.1f mm\n", s.name,
                static_cast<int>(c.primitives.size()), 1e3 * c.report.volume, ratio, 1e3 * c.report.largest_gap);
  }
  EXPECT_NEAR(convex_hull(box_mesh(Vec3<double>(0.3, 0.1, 0.05)).vertices).volume, 0.3 * 0.1 * 0.05, 1e-15);
  EXPECT_NEAR(convex_hull(mbgen::test::l_shape().vertices).volume, 0.3 * 0.25 * 0.05 - 0.5 * 0.24 * 0.19 * 0.05, 1e-15);
}

// Closed forms: a sphere mesh gets one point-SSV of the sphere's radius; a thin plate gets two
// triangles of half its thickness spanning it; a long cylinder gets one capsule on its axis.
TEST(FitSsv, ClosedFormsForSphereCylinderAndPlate) {
  const FittedCompound ball = fit_ssv_compound(mbgen::test::sphere_mesh(0.1, 12, 24));
  ASSERT_EQ(ball.primitives.size(), 1u);
  EXPECT_EQ(ball.primitives[0].points.size(), 1u);
  EXPECT_NEAR(ball.primitives[0].points[0].norm(), 0.0, 2e-6);
  EXPECT_NEAR(ball.primitives[0].radius, 0.1, 2e-6);
  // The mesh's faces sit inside the sphere by at most 0.1 (1 - cos(pi/12)) = 3.4 mm.
  EXPECT_LE(ball.report.largest_gap, 0.1 * (1 - std::cos(M_PI / 12)) + 2e-6);
  EXPECT_GT(ball.report.largest_gap, 0.0);

  const FittedCompound plate = fit_ssv_compound(box_mesh(Vec3<double>(0.2, 0.15, 0.004)));
  ASSERT_EQ(plate.primitives.size(), 2u);
  for (const FittedPrimitive& p : plate.primitives) {
    EXPECT_EQ(p.points.size(), 3u);
    EXPECT_NEAR(p.radius, 0.002, 2e-6);
    for (const auto& x : p.points) {
      EXPECT_NEAR(std::abs(x.x()), 0.1, 2e-6);
      EXPECT_NEAR(std::abs(x.y()), 0.075, 2e-6);
    }
  }

  const FittedCompound rod = fit_ssv_compound(mbgen::test::cylinder_mesh(0.02, 0.5, 64));
  ASSERT_EQ(rod.primitives.size(), 1u);
  ASSERT_EQ(rod.primitives[0].points.size(), 2u);
  EXPECT_NEAR(rod.primitives[0].radius, 0.02, 2e-6);
  for (const auto& x : rod.primitives[0].points) EXPECT_NEAR(x.head<2>().norm(), 0.0, 2e-6);
}

// Steiner's formula against a count of grid points inside each kind of primitive (1 mm grid).
TEST(FitSsv, PrimitiveVolumeMatchesAPointCount) {
  const std::vector<FittedPrimitive> kinds = {{{Vec3<double>(0.01, 0.02, 0.0)}, 0.05},
                                              {{Vec3<double>(0, 0, 0), Vec3<double>(0.1, 0.05, 0.02)}, 0.03},
                                              {{Vec3<double>(0, 0, 0), Vec3<double>(0.12, 0, 0), Vec3<double>(0.02, 0.09, 0.03)}, 0.02}};
  for (const FittedPrimitive& p : kinds) {
    const double h = 1e-3;
    long inside = 0;
    for (double x = -0.1; x < 0.2; x += h)
      for (double y = -0.1; y < 0.2; y += h)
        for (double z = -0.1; z < 0.15; z += h)
          if (core_distance(Vec3<double>(x, y, z), p) <= p.radius) ++inside;
    EXPECT_NEAR(inside * h * h * h / primitive_volume(p), 1.0, 0.01) << p.points.size() << " points";
  }
}

// More budget never makes the compound larger, and the same mesh gives the same compound.
TEST(FitSsv, BudgetHelpsAndTheFitIsDeterministic) {
  const TriangleMesh l = mbgen::test::l_shape();
  double previous = 1e300;
  for (int budget = 1; budget <= 6; ++budget) {
    FitOptions options;
    options.budget = budget;
    const double volume = fit_ssv_compound(l, options).report.volume;
    EXPECT_LE(volume, previous * (1 + 1e-12)) << budget;
    previous = volume;
  }
  const FittedCompound a = fit_ssv_compound(l), b = fit_ssv_compound(l);
  ASSERT_EQ(a.primitives.size(), b.primitives.size());
  for (std::size_t i = 0; i < a.primitives.size(); ++i) {
    EXPECT_EQ(a.primitives[i].radius, b.primitives[i].radius);
    EXPECT_EQ(a.primitives[i].points, b.primitives[i].points);
  }
  // An L with budget 4 is cut: one primitive cannot hug both bars.
  EXPECT_GE(a.primitives.size(), 2u);
}

TEST(FitSsv, RefusesAZeroBudgetAndAnEmptyMesh) {
  FitOptions zero;
  zero.budget = 0;
  EXPECT_THROW(fit_ssv_compound(box_mesh(Vec3<double>(1, 1, 1)), zero), std::invalid_argument);
  EXPECT_THROW(fit_ssv_compound(TriangleMesh{}), std::invalid_argument);
}

// Qhull's hull: flat input has no volume and keeps every point; a cube's hull is its 8 corners
// even with interior points added.
TEST(ConvexHull, SolidFlatAndInteriorPoints) {
  std::vector<Vec3<double>> cube = box_mesh(Vec3<double>(2, 2, 2)).vertices;
  cube.push_back(Vec3<double>(0.1, 0.2, 0.3));
  const ConvexHull hull = convex_hull(cube);
  EXPECT_TRUE(hull.solid);
  EXPECT_NEAR(hull.volume, 8.0, 1e-14);
  EXPECT_EQ(hull.vertices.size(), 8u);
  const ConvexHull flat = convex_hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 0}});
  EXPECT_FALSE(flat.solid);
  EXPECT_EQ(flat.volume, 0.0);
  EXPECT_EQ(flat.vertices.size(), 5u);
}

}  // namespace
