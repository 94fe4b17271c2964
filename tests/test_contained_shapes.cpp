// Shapes inside another shape of their compound (runtime/include/mbgen/collision/contained_shapes.hpp):
// the protrusion against closed forms for each container kind, which shapes drop_contained_shapes
// removes (and which it must keep), and that a compound without them has the distances of the
// compound with them, against every shape pair tried (1e5 random placements).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mbgen/collision/compound_distance.hpp"
#include "mbgen/collision/contained_shapes.hpp"

namespace mbgen::collision {
namespace {

Shape point(const Vec3<double>& c, double r) {
  Shape s;
  s.kind = Shape::Kind::Point;
  s.points[0] = c;
  s.radius = r;
  update_bound(s);
  return s;
}

Shape line(const Vec3<double>& a, const Vec3<double>& b, double r) {
  Shape s;
  s.kind = Shape::Kind::Line;
  s.points = {a, b, Vec3<double>::Zero()};
  s.radius = r;
  update_bound(s);
  return s;
}

Shape triangle(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c, double r) {
  Shape s;
  s.kind = Shape::Kind::Triangle;
  s.points = {a, b, c};
  s.radius = r;
  update_bound(s);
  return s;
}

Compound compound_of(std::vector<Shape> shapes) {
  Compound c;
  c.name = "test";
  c.shapes = std::move(shapes);
  update_bound(c);
  return c;
}

/// The ROS capsule idiom as collision_ssv.cpp reads it: a cylinder of radius r from z = 0 to
/// z = -l (a line SSV) and a sphere of radius r at each end.
std::vector<Shape> capsule_idiom(double r, double l) {
  return {line(Vec3<double>(0, 0, 0), Vec3<double>(0, 0, -l), r), point(Vec3<double>(0, 0, 0), r), point(Vec3<double>(0, 0, -l), r)};
}

TEST(ContainedShapes, ProtrusionMatchesClosedForms) {
  const Shape capsule = line(Vec3<double>(0, 0, 0), Vec3<double>(0, 0, -0.2), 0.05);
  // A sphere beside the segment's middle: its centre 0.03 off the axis, radius 0.01.
  EXPECT_NEAR(protrusion(capsule, point(Vec3<double>(0.03, 0, -0.1), 0.01)), 0.03 + 0.01 - 0.05, 1e-15);
  // Beyond the end, on the axis: distance to the end point.
  EXPECT_NEAR(protrusion(capsule, point(Vec3<double>(0, 0, 0.04), 0.02)), 0.04 + 0.02 - 0.05, 1e-15);
  // A capsule inside a capsule: the farther of its two end spheres.
  EXPECT_NEAR(protrusion(capsule, line(Vec3<double>(0.01, 0, -0.05), Vec3<double>(0.02, 0, 0.01), 0.005)),
              std::hypot(0.02, 0.01) + 0.005 - 0.05, 1e-15);
  // A sphere container: centre distance plus radius less the container's.
  EXPECT_NEAR(protrusion(point(Vec3<double>(1, 2, 3), 0.5), point(Vec3<double>(1, 2.3, 3.4), 0.1)), 0.5 + 0.1 - 0.5, 1e-15);
  // A triangle container: above its interior, the height; beside an edge, the distance to it.
  const Shape plate = triangle(Vec3<double>(0, 0, 0), Vec3<double>(1, 0, 0), Vec3<double>(0, 1, 0), 0.1);
  EXPECT_NEAR(protrusion(plate, point(Vec3<double>(0.2, 0.2, 0.07), 0.02)), 0.07 + 0.02 - 0.1, 1e-15);
  EXPECT_NEAR(protrusion(plate, point(Vec3<double>(0.5, -0.03, 0.04), 0.01)), 0.05 + 0.01 - 0.1, 1e-15);
  // A triangle inside: the worst of its three corners.
  EXPECT_NEAR(protrusion(capsule, triangle(Vec3<double>(0, 0, -0.1), Vec3<double>(0.04, 0, -0.1), Vec3<double>(0, 0.01, -0.1), 0.001)),
              0.04 + 0.001 - 0.05, 1e-15);
}

TEST(ContainedShapes, CapsuleIdiomKeepsTheLineOnly) {
  Compound c = compound_of(capsule_idiom(0.012, 0.18));
  const double bound_before = c.bound_radius;
  const std::vector<ContainedShape> dropped = drop_contained_shapes(c);
  ASSERT_EQ(dropped.size(), 2u);
  EXPECT_EQ(dropped[0].shape, 1);
  EXPECT_EQ(dropped[0].container, 0);
  EXPECT_EQ(dropped[1].shape, 2);
  EXPECT_EQ(dropped[1].container, 0);
  EXPECT_LE(std::abs(dropped[0].protrusion), 1e-15);
  ASSERT_EQ(c.shapes.size(), 1u);
  EXPECT_EQ(c.shapes[0].kind, Shape::Kind::Line);
  EXPECT_NEAR(c.bound_radius, 0.09 + 0.012, 1e-15);  // the capsule's own sphere
  EXPECT_LE(c.bound_radius, bound_before);
}

TEST(ContainedShapes, CapOffTheEndByRoundingIsDroppedAndAProtrudingSphereKept) {
  // A URDF rpy of 3.14159265359 for pi moves the cylinder's end ~1e-13 m off the sphere's centre.
  std::vector<Shape> shapes = capsule_idiom(0.012, 0.18);
  shapes[1].points[0].x() += 2e-13;
  shapes[2].radius += 1e-6;  // reaches 1e-6 m out of the capsule's end: not the same volume
  Compound c = compound_of(shapes);
  const std::vector<ContainedShape> dropped = drop_contained_shapes(c);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0].shape, 1);
  ASSERT_EQ(c.shapes.size(), 2u);
  EXPECT_EQ(c.shapes[1].kind, Shape::Kind::Point);
  EXPECT_NEAR(protrusion(c.shapes[0], c.shapes[1]), 1e-6, 1e-15);
}

TEST(ContainedShapes, OfTwoEqualShapesTheLaterStays) {
  Compound c = compound_of({point(Vec3<double>(0.1, 0, 0), 0.05), point(Vec3<double>(0.1, 0, 0), 0.05), line(Vec3<double>(0, 0, 0), Vec3<double>(0, 0.3, 0), 0.01)});
  const std::vector<ContainedShape> dropped = drop_contained_shapes(c);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0].shape, 0);
  EXPECT_EQ(dropped[0].container, 1);
  EXPECT_EQ(c.shapes.size(), 2u);
}

TEST(ContainedShapes, DisjointAndOverlappingShapesAreKept) {
  // Overlapping but neither inside the other (the forearm and hand of a compound), and apart.
  Compound c = compound_of({line(Vec3<double>(0, 0, 0), Vec3<double>(0, 0, -0.2), 0.04), point(Vec3<double>(0, 0, -0.22), 0.05),
                            point(Vec3<double>(0.5, 0, 0), 0.01)});
  EXPECT_TRUE(drop_contained_shapes(c).empty());
  EXPECT_EQ(c.shapes.size(), 3u);
}

/// The compound's distance to another one, with and without its contained shapes, over random
/// placements: the same (to the rounding of the container's own formula where a cap is the
/// closest feature: 1e-15 m), and the same pair of witnesses where the container was closest.
TEST(ContainedShapes, DroppingChangesNoDistance) {
  std::vector<Shape> given = capsule_idiom(0.03, 0.25);
  given.push_back(point(Vec3<double>(0.01, 0.005, -0.1), 0.015));               // inside the middle
  given.push_back(triangle(Vec3<double>(0.05, 0, 0), Vec3<double>(0.1, 0, 0), Vec3<double>(0.05, 0.05, 0), 0.01));  // apart
  const Compound full = compound_of(given);
  Compound pruned = full;
  ASSERT_EQ(drop_contained_shapes(pruned).size(), 3u);
  ASSERT_EQ(pruned.shapes.size(), 2u);
  const Compound other = compound_of({line(Vec3<double>(-0.05, 0, 0), Vec3<double>(0.05, 0, 0), 0.02), point(Vec3<double>(0, 0.1, 0), 0.03)});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  double worst = 0;
  for (int k = 0; k < 100000; ++k) {
    SE3<double> X_Wa, X_Wb;
    X_Wa.rotation = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    X_Wb.rotation = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    X_Wa.translation = Vec3<double>::Zero();
    X_Wb.translation = 0.4 * Vec3<double>(u(rng), u(rng), u(rng));
    const double d_full = compound_distance<double>(full, X_Wa, other, X_Wb).result.distance;
    const double d_pruned = compound_distance<double>(pruned, X_Wa, other, X_Wb).result.distance;
    worst = std::max(worst, std::abs(d_full - d_pruned));
  }
  EXPECT_LE(worst, 1e-15);
}

}  // namespace
}  // namespace mbgen::collision
