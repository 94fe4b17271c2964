#pragma once
// A compliant ground scene for the derivative tests of the contact dynamics and the simulator's
// step (test_contact_dynamics_derivatives.cpp, test_step_derivatives.cpp) on any tree: three
// spheres on each leaf body at random offsets, a ground tilted by 0.2 rad whose plane cuts the
// spheres between their two middle heights at the given configuration (half of them in contact),
// and a soft law (k = 1e3 N/m^1.5: forces of the order of the robots' weights at the depths the
// cut gives), so that springs, damping and both friction regimes act at once.
#include <algorithm>
#include <random>
#include <vector>

#include "mbgen/algorithm/contact_points.hpp"

namespace mbgen::test {

struct CompliantScene {
  std::vector<ContactSphere> spheres;
  GroundPlane ground = GroundPlane::tilted_about_x(0.2);
  ContactParameters law;
  double ground_inputs[kGroundInputs] = {}, law_inputs[kLawInputs] = {};

  /// The plane between the spheres' two middle heights at q (ground and its inputs updated).
  void cut_at(const Model& model, const VecX<double>& q) {
    Data<double> data(model);
    VecX<double> c(3 * spheres.size()), J(6 * model.nv() * spheres.size());
    contact_points<double>(model, data, spheres, q, c.data(), J.data());
    std::vector<double> heights;
    for (std::size_t k = 0; k < spheres.size(); ++k)
      heights.push_back(ground.normal.dot(c.segment<3>(3 * static_cast<int>(k))) - spheres[k].radius);
    // Midway between the two middle heights: no sphere at zero depth, where the law's
    // delta^1.5 has no second derivative (central differences would straddle it).
    std::sort(heights.begin(), heights.end());
    const std::size_t m = heights.size() / 2;
    ground.offset = 0.5 * (heights[m - 1] + heights[m]);
    contact_inputs(ground, law, ground_inputs, law_inputs);
  }
};

inline CompliantScene leaf_spheres(const Model& model, std::mt19937_64& rng) {
  CompliantScene scene;
  scene.law.stiffness = 1e3;
  scene.law.damping = 0.5;
  std::vector<char> has_child(static_cast<std::size_t>(model.num_bodies()), 0);
  for (int k = 1; k < model.num_bodies(); ++k) has_child[static_cast<std::size_t>(model.body(BodyIndex(k)).parent.value())] = 1;
  std::uniform_real_distribution<double> offset(-0.05, 0.05);
  for (int k = 1; k < model.num_bodies(); ++k) {
    if (has_child[static_cast<std::size_t>(k)]) continue;
    for (int i = 0; i < 3; ++i) {
      ContactSphere s;
      s.body = BodyIndex(k);
      s.center = Vec3<double>(offset(rng), offset(rng), offset(rng));
      s.radius = 0.02;
      scene.spheres.push_back(s);
    }
  }
  contact_inputs(scene.ground, scene.law, scene.ground_inputs, scene.law_inputs);
  return scene;
}

}  // namespace mbgen::test
