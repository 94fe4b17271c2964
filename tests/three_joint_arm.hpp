#pragma once
// A fixed arm of three bodies, joints about z, y and x, each link alike: the small chain the rotor
// tests build their drives on (test_rotor.cpp, test_rnea_derivatives.cpp).
#include <string>

#include "mbgen/mbgen.hpp"

namespace mbgen::test {

/// `adjust(joint, j)` gives joint j (0, 1, 2) what the test needs (a drive, a turned frame) before
/// it is added.
template <typename Adjust> Model three_joint_arm(const Inertia<double>& link, Adjust adjust) {
  Model model;
  BodyIndex parent = kWorldBody;
  const Vec3<double> axes[3] = {Vec3<double>::UnitZ(), Vec3<double>::UnitY(), Vec3<double>::UnitX()};
  for (int j = 0; j < 3; ++j) {
    Joint joint;
    joint.name = "j" + std::to_string(j + 1);
    joint.axis = axes[j];
    adjust(joint, j);
    parent = model.add_body(parent, joint, "link" + std::to_string(j + 1), link);
  }
  return model;
}

}  // namespace mbgen::test
