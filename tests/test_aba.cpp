// ABA against CRBA and RNEA (three independent algorithms) on every URDF, fixed and floating base:
//   ABA(q, v, tau) = M(q)^-1 (tau - RNEA(q, v, 0))   and   RNEA(q, v, ABA(q, v, tau)) = tau.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "test_support.hpp"

namespace mbgen::test {
namespace {

class AbaTest : public ::testing::TestWithParam<UrdfCase> {};

TEST_P(AbaTest, MatchesCrbaAndRnea) {
  const Model model = load_tree(GetParam().path, GetParam().base);
  Data<double> data(model);
  std::mt19937_64 rng(42);
  // 1e-10 relative: three O(n) / O(n^2) algorithms that share no code path beyond kinematics.
  constexpr double kTol = 1e-10;
  double worst_solve = 0, worst_roundtrip = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const VecX<double> v = random_vector<double>(model.nv(), rng, 2.0);
    const VecX<double> tau = random_vector<double>(model.nv(), rng, 10.0);
    const VecX<double> ddq = aba<double>(model, data, q, v, tau);
    const VecX<double> bias = nonlinear_effects<double>(model, data, q, v);
    const MatX<double> M = crba<double>(model, data, q);
    ASSERT_LT(relative_error(M, MatX<double>(M.transpose())), 1e-14);
    const VecX<double> ddq_crba = M.ldlt().solve(tau - bias);
    const VecX<double> tau_back = rnea<double>(model, data, q, v, ddq);
    // Normwise backward errors: the residual of M ddq = tau - bias relative to the size of its
    // terms. They do not grow with the conditioning of M (the 5-bar's 654 t ball makes M
    // badly conditioned, so forward errors in ddq would measure the model, not the algorithm).
    const double scale = M.norm() * ddq.norm() + tau.norm() + bias.norm();
    worst_solve = std::max(worst_solve, (M * (ddq - ddq_crba)).norm() / scale);
    worst_roundtrip = std::max(worst_roundtrip, (tau_back - tau).norm() / scale);
  }
  EXPECT_LT(worst_solve, kTol);
  EXPECT_LT(worst_roundtrip, kTol);
}

INSTANTIATE_TEST_SUITE_P(AllUrdfs, AbaTest, ::testing::ValuesIn(all_urdf_cases()), urdf_case_name);

}  // namespace
}  // namespace mbgen::test
