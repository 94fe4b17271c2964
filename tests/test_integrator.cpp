// Energy conservation of passive robots integrated with RK4: an independent check of ABA
// (a wrong Coriolis or gravity term breaks conservation) and of the configuration derivative.
#include <gtest/gtest.h>

#include <random>

#include "test_support.hpp"

namespace mbgen::test {
namespace {

/// Integrates 2 s without joint forces and returns max |E(t) - E(0)| / (KE(0) + |PE(0)|).
double energy_drift(const Model& model, double dt, unsigned seed) {
  Data<double> data(model);
  Rk4Workspace<double> ws(model);
  std::mt19937_64 rng(seed);
  VecX<double> q = random_configuration<double>(model, rng);
  VecX<double> v = random_vector<double>(model.nv(), rng, 1.0);
  const VecX<double> tau = VecX<double>::Zero(model.nv());
  auto energy = [&] { return kinetic_energy<double>(model, data, q, v) + potential_energy<double>(model, data, q); };
  const double ke0 = kinetic_energy<double>(model, data, q, v);
  const double scale = ke0 + std::abs(potential_energy<double>(model, data, q));
  const double e0 = energy();
  double worst = 0;
  const int steps = static_cast<int>(std::lround(2.0 / dt));
  for (int k = 0; k < steps; ++k) {
    rk4_step<double>(model, data, ws, q, v, tau, dt);
    if (k % 100 == 99) worst = std::max(worst, std::abs(energy() - e0) / scale);
  }
  EXPECT_TRUE(q.allFinite() && v.allFinite());
  return worst;
}

TEST(Rk4, PassiveFloatingQuadrupedConservesEnergy) {
  const Model model = load_tree(shared_robot("solo12/solo12.urdf"), gen::BaseType::Floating);
  EXPECT_LT(energy_drift(model, 2e-4, 1), 1e-6);
}

TEST(Rk4, PassiveFloatingHyqConservesEnergy) {
  const Model model = load_tree(shared_robot("hyq/hyq_no_sensors.urdf"), gen::BaseType::Floating);
  EXPECT_LT(energy_drift(model, 2e-4, 2), 1e-6);
}

TEST(Rk4, PassiveFixedArmConservesEnergy) {
  const Model model = load_tree(shared_robot("iiwa14/iiwa14_primitive_collision.urdf"), gen::BaseType::Fixed);
  EXPECT_LT(energy_drift(model, 2e-4, 3), 1e-6);
}

TEST(Rk4, DriftShrinksWithTheStepAsFourthOrder) {
  // A method of order 4: halving dt divides the drift by about 16 (at least 8 here). This shows
  // the check above is sensitive: a first-order error would only halve it.
  const Model model = load_tree(shared_robot("solo12/solo12.urdf"), gen::BaseType::Floating);
  const double coarse = energy_drift(model, 4e-3, 7);
  const double fine = energy_drift(model, 2e-3, 7);
  EXPECT_GT(coarse, 0.0);
  EXPECT_GT(coarse / fine, 8.0);
}

}  // namespace
}  // namespace mbgen::test
