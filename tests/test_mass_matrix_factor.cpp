// The mass matrix's L^T D L factor (runtime/include/mbgen/algorithm/mass_matrix_factor.hpp) on
// every URDF, fixed and floating base: it rebuilds M, keeps the branch-induced sparsity exactly,
// and its solve agrees with the articulated-body algorithm (a second algorithm) and allocates
// nothing.
#include <gtest/gtest.h>

#include <random>

#include "malloc_guard.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

class MassMatrixFactorTest : public ::testing::TestWithParam<UrdfCase> {};

bool is_ancestor(const Model& model, int ancestor, int k) {
  for (int i = model.velocity_parent(k); i >= 0; i = model.velocity_parent(i))
    if (i == ancestor) return true;
  return false;
}

// Model::velocity_parent against the body tree: the ancestors of coordinate k are the earlier
// coordinates of its own joint and every coordinate of the joints on its body's path to the root.
TEST_P(MassMatrixFactorTest, VelocityParentsFollowTheBodyTree) {
  const Model model = load_tree(GetParam().path, GetParam().base);
  for (int k = 0; k < model.nv(); ++k) {
    const Joint& own = model.joint(model.joint_of_v(k));
    std::vector<int> expected;
    for (int v = k - 1; v >= own.idx_v; --v) expected.push_back(v);
    for (BodyIndex b = model.body(own.child).parent; b != kWorldBody; b = model.body(b).parent) {
      const Joint& joint = model.joint(model.body(b).joint);
      for (int v = joint.idx_v + joint.nv - 1; v >= joint.idx_v; --v) expected.push_back(v);
    }
    std::vector<int> chain;
    for (int i = model.velocity_parent(k); i >= 0; i = model.velocity_parent(i)) chain.push_back(i);
    EXPECT_EQ(chain, expected) << "coordinate " << k;
  }
}

TEST_P(MassMatrixFactorTest, RebuildsTheMassMatrixWithoutFillIn) {
  const Model model = load_tree(GetParam().path, GetParam().base);
  Data<double> data(model);
  std::mt19937_64 rng(5);
  const int n = model.nv();
  double worst = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const MatX<double> M = crba<double>(model, data, q);
    const MatX<double> LD = mass_matrix_factor<double>(model, data, q);
    MatX<double> L = MatX<double>::Identity(n, n);
    L.triangularView<Eigen::StrictlyLower>() = LD.triangularView<Eigen::StrictlyLower>();
    const VecX<double> D = LD.diagonal();
    // 1e-13 relative: the factor is a few multiply-adds per entry away from M.
    worst = std::max(worst, relative_error(MatX<double>(L.transpose() * D.asDiagonal() * L), M));
    for (int r = 0; r < n; ++r) {
      EXPECT_GT(D[r], 0.0) << "pivot " << r;
      for (int c = 0; c < n; ++c) {
        if (c > r) {
          EXPECT_EQ(LD(r, c), 0.0) << r << "," << c << " above the diagonal";
        } else if (c < r && !is_ancestor(model, c, r)) {
          EXPECT_EQ(LD(r, c), 0.0) << r << "," << c << " is no ancestor: fill-in";
        }
      }
    }
  }
  EXPECT_LT(worst, 1e-13);
}

TEST_P(MassMatrixFactorTest, SolveGivesTheArticulatedBodyAccelerations) {
  const Model model = load_tree(GetParam().path, GetParam().base);
  Data<double> data(model);
  std::mt19937_64 rng(6);
  double worst = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const VecX<double> v = random_vector<double>(model.nv(), rng, 2.0);
    const VecX<double> tau = random_vector<double>(model.nv(), rng, 10.0);
    const VecX<double> ddq = aba<double>(model, data, q, v, tau);
    const VecX<double> bias = nonlinear_effects<double>(model, data, q, v);
    const MatX<double> M = crba<double>(model, data, q);
    const MatX<double> LD = mass_matrix_factor<double>(model, data, q);
    VecX<double> x = tau - bias;
    mass_matrix_solve_in_place<double>(model, LD, x);
    // Normwise backward error, as in test_aba.cpp (M's conditioning does not enter).
    worst = std::max(worst, (M * (x - ddq)).norm() / (M.norm() * ddq.norm() + tau.norm() + bias.norm()));
  }
  EXPECT_LT(worst, 1e-10);
}

TEST_P(MassMatrixFactorTest, FactorAndSolveAllocateNothing) {
  const Model model = load_tree(GetParam().path, GetParam().base);
  Data<double> data(model);
  std::mt19937_64 rng(7);
  const VecX<double> q = random_configuration<double>(model, rng);
  VecX<double> b = random_vector<double>(model.nv(), rng, 1.0);
  MallocGuard guard;
  mass_matrix_factor<double>(model, data, q);
  mass_matrix_solve_in_place<double>(model, data.M, b);
  EXPECT_EQ(guard.count(), 0u);
}

INSTANTIATE_TEST_SUITE_P(AllUrdfs, MassMatrixFactorTest, ::testing::ValuesIn(all_urdf_cases()), urdf_case_name);

}  // namespace
}  // namespace mbgen::test
