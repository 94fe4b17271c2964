// Centroidal momentum matrix against its definition (sum of body momenta about the centre of
// mass) and against finite differences of the centre of mass (linear part = m dc/dt).
#include <gtest/gtest.h>

#include <random>

#include "test_support.hpp"

namespace mbgen::test {
namespace {

class CentroidalTest : public ::testing::TestWithParam<std::string> {};

TEST_P(CentroidalTest, MatchesDefinitionAndFiniteDifferences) {
  for (gen::BaseType base : loadable_bases(GetParam())) {
    const Model model = load_tree(GetParam(), base);
    Data<double> data(model), kin(model), other(model);
    std::mt19937_64 rng(21);
    const double h = 1e-6;
    for (int trial = 0; trial < 20; ++trial) {
      const VecX<double> q = random_configuration<double>(model, rng);
      const VecX<double> v = random_vector<double>(model.nv(), rng, 1.0);
      const Vec6<double> hg = centroidal_momentum<double>(model, data, q, v);
      // Definition: each body's momentum, taken about the centre of mass, in world axes.
      forward_kinematics<double>(model, kin, q, v);
      Vec6<double> h_def = Vec6<double>::Zero();
      for (int k = 1; k < model.num_bodies(); ++k) {
        const BodyIndex b(k);
        const Force<double> h_W = kin.X_WB[b].act(model.body(b).inertia * kin.v[b]);
        h_def.head<3>() += h_W.linear;
        h_def.tail<3>() += h_W.angular - data.com.cross(h_W.linear);
      }
      // Both sides are sums of the same magnitude; 1e-12 relative to the momentum's size.
      EXPECT_LT(relative_error(hg, h_def), 1e-12);
      // Finite differences: linear momentum = total mass x velocity of the centre of mass.
      const auto [q_plus, q_minus] = central_pair(model, q, v, h);
      const Vec3<double> c_plus = center_of_mass<double>(model, other, q_plus);
      const Vec3<double> c_minus = center_of_mass<double>(model, other, q_minus);
      EXPECT_LT(relative_error(hg.head<3>(), model.total_mass() * (c_plus - c_minus) / (2 * h)), 1e-7);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllUrdfs, CentroidalTest, ::testing::ValuesIn(all_urdfs()),
                         [](const auto& info) { return short_name(info.param); });

}  // namespace
}  // namespace mbgen::test
