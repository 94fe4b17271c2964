#pragma once
// Lola's drive linkages in closed form (robots/lola/README.md, "Geometry and closed forms"): the
// independent reference of tests/test_transmissions.cpp and tests/test_actuator_joint_map.cpp.
#include <cmath>

#include <Eigen/Geometry>

#include "mbgen/spatial/types.hpp"

namespace mbgen::test {

/// The knee nut's travel (m) for knee angle theta.
inline double knee_actuator(double theta) {
  const double px = 0.03 * std::cos(theta) + 0.052 * std::sin(theta), pz = -0.44 - 0.03 * std::sin(theta) + 0.052 * std::cos(theta);
  return pz + std::sqrt(0.18 * 0.18 - (0.03 - px) * (0.03 - px)) + 0.208;
}

/// An ankle rod's extension (m) for foot pitch alpha and roll beta; b_y: the ball joint's y in
/// the foot frame (the universal joint's in the shank frame is the same).
inline double ankle_actuator(double alpha, double beta, double b_y) {
  const Mat3<double> R =
      Eigen::AngleAxisd(alpha, Vec3<double>::UnitY()).toRotationMatrix() * Eigen::AngleAxisd(beta, Vec3<double>::UnitX()).toRotationMatrix();
  const Vec3<double> O(0, 0, -0.44), b(-0.05, b_y, 0), A(-0.05, b_y, -0.10);
  return (O + R * b - A).norm() - 0.34;
}

}  // namespace mbgen::test
