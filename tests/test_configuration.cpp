// configuration.hpp's integrate and difference: inverses of each other on every robot's
// configuration space, the floating base's included (1e-12 for rotations away from pi; near zero
// velocity 1e-8 relative, the quaternion's rounding over a 1e-7 rad angle, plus 1e-13 absolute),
// and integrate's
// floating base is the exponential of a body twist (a constant twist for unit time: two half
// steps reach the same pose, 1e-14).
#include <gtest/gtest.h>

#include <random>

#include "test_support.hpp"

namespace mbgen::test {
namespace {

class ConfigurationTest : public ::testing::TestWithParam<UrdfCase> {};

TEST_P(ConfigurationTest, DifferenceInvertsIntegrate) {
  const Model model = load_tree(GetParam().path, GetParam().base);
  std::mt19937_64 rng(57);
  VecX<double> q1(model.nq()), v(model.nv()), half(model.nq()), twice(model.nq());
  for (int trial = 0; trial < 50; ++trial) {
    const VecX<double> q0 = random_configuration<double>(model, rng);
    const double scale = trial % 2 ? 1.0 : 1e-7;
    const VecX<double> w = random_vector<double>(model.nv(), rng, scale);
    integrate<double>(model, q0, w, q1);
    difference<double>(model, q0, q1, v);
    // Plus the rounding of q0 + w - q0 (1e-13 absolute, for coordinates up to a few units).
    EXPECT_LT((v - w).norm(), (scale == 1.0 ? 1e-12 : 1e-8) * w.norm() + 1e-13);
    // Two half steps of the same twist: the same pose as one whole step.
    integrate<double>(model, q0, w / 2, half);
    integrate<double>(model, half, w / 2, twice);
    EXPECT_LT((twice - q1).norm(), 1e-14 * (1 + q1.norm()));
    // difference then integrate from random pairs reaches the second configuration.
    const VecX<double> q2 = random_configuration<double>(model, rng);
    difference<double>(model, q0, q2, v);
    integrate<double>(model, q0, v, q1);
    for (int j = 1; j < model.num_joints(); ++j) {
      const Joint& joint = model.joint(JointIndex(j));
      if (joint.type != JointType::Floating) continue;
      // A quaternion and its negative are one rotation.
      if (q1.segment<4>(joint.idx_q + 3).dot(q2.segment<4>(joint.idx_q + 3)) < 0) q1.segment<4>(joint.idx_q + 3) *= -1;
      EXPECT_LE(v.segment<3>(joint.idx_v + 3).norm(), M_PI + 1e-12);  // the short way round
    }
    EXPECT_LT((q1 - q2).norm(), 1e-12 * (1 + q2.norm()));
  }
}

INSTANTIATE_TEST_SUITE_P(AllUrdfs, ConfigurationTest, ::testing::ValuesIn(all_urdf_cases()), urdf_case_name);

}  // namespace
}  // namespace mbgen::test
